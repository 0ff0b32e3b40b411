//! What a stream of ARKit weights looks like, as numbers: the statistics
//! that the simulated tracker is measured against real Live Link Face takes
//! with (see `sim-data/README.md`, "The tracker").
//!
//! The same function computes them on a real take and on a simulated
//! stream, so the comparison in the tests is like for like. All are robust
//! (medians, percentiles), because a performance mixes long rests with fast
//! expressions.
//!
//! | statistic | what it shows | definition |
//! |---|---|---|
//! | jitter | sensor noise | per moving channel, the robust σ (1.4826 · MAD) of the second differences `w_{t+1} − 2w_t + w_{t−1}`; the median over channels |
//! | lag-1 autocorrelation of the first differences | temporal smoothing | per moving channel, the correlation of `Δw_t` with `Δw_{t+1}`; the median (white noise on a slow signal: −0.5; smooth: towards +1) |
//! | band shares | the spectrum | per moving channel, the share of the power of `Δw` below 2 Hz, 2–6 Hz, 6–15 Hz and above 15 Hz (Welch's method); the median per band |
//! | rest level | the weight at rest | per channel, the 5th percentile of its values |
//! | zero share | clamping at 0 | per channel, the share of frames at exactly 0 |
//! | frame timing | dropped or irregular frames | the median spacing, and how many spacings are over 1.5 × or under 0.5 × it |
//! | quantum | value quantization | the smallest non-zero difference between two values of one channel |
//! | mirror co-movement | which weights move together | for each left/right pair where both move, the correlation of their first differences; the median |
//! | rest noise | the sensor noise alone | in *quiet windows* (31 frames, about half a second, of one channel whose range stays under 0.03 and whose values stay above 0.01, so neither moving nor clamped at 0): the σ of the residual of a quadratic fit, the σ of the second differences and the lag-1 autocorrelation of the first differences; medians over all quiet windows |
//! | fastest blink | the tracker's lag | the fewest frames an eyeBlink weight takes from 10% to 90% of a rise of at least 0.5 (the true lid closes in 50–100 ms, so a heavily filtering tracker shows it slower) |
//!
//! A channel *moves* when its 95th and 5th percentiles are at least
//! [`MOVING_RANGE`] apart.

use likeness::{BLENDSHAPE_COUNT, Blendshape, Frame};

/// A channel whose 5th-to-95th percentile range is at least this moves.
pub const MOVING_RANGE: f64 = 0.05;

/// Length of a quiet window (frames).
pub const QUIET_WINDOW: usize = 31;

/// A quiet window's values stay within this range…
pub const QUIET_RANGE: f64 = 0.03;

/// …and above this level (so the tracker's clamp at 0 does not hide noise).
pub const QUIET_FLOOR: f64 = 0.01;

/// Edges of the spectral bands (Hz) of [`StreamStatistics::band_shares`].
pub const BAND_EDGES_HZ: [f64; 3] = [2.0, 6.0, 15.0];

/// The statistics of one weight stream (see the module table).
#[derive(Clone, Debug, PartialEq)]
pub struct StreamStatistics {
    /// Number of frames.
    pub frames: usize,
    /// Channels that move.
    pub moving: Vec<Blendshape>,
    /// Median over moving channels of the robust σ of second differences.
    pub jitter: f64,
    /// Median over moving channels of the lag-1 autocorrelation of first
    /// differences.
    pub lag1_autocorrelation: f64,
    /// Median over moving channels of the share of `Δw`'s power in each band
    /// (below 2 Hz, 2–6, 6–15, above 15 Hz).
    pub band_shares: [f64; 4],
    /// Per channel, the 5th percentile of its values.
    pub rest_levels: [f64; BLENDSHAPE_COUNT],
    /// Per channel, the share of frames at exactly zero.
    pub zero_shares: [f64; BLENDSHAPE_COUNT],
    /// Median spacing of the timestamps (s).
    pub median_interval: f64,
    /// Spacings over 1.5 × the median (dropped frames).
    pub long_intervals: usize,
    /// Spacings under 0.5 × the median (repeated or bunched frames).
    pub short_intervals: usize,
    /// Smallest non-zero difference between two values of one channel.
    pub quantum: f64,
    /// Median over left/right pairs that both move of the correlation of
    /// their first differences.
    pub mirror_correlation: f64,
    /// Number of quiet windows found.
    pub quiet_windows: usize,
    /// Median σ of a quiet window's residual after a quadratic fit.
    pub rest_noise: f64,
    /// Median σ of a quiet window's second differences.
    pub rest_jitter: f64,
    /// Median lag-1 autocorrelation of a quiet window's first differences.
    pub rest_lag1_autocorrelation: f64,
    /// Fewest frames from 10% to 90% of an eyeBlink rise of at least 0.5
    /// (`None` without such a rise).
    pub fastest_blink_rise: Option<usize>,
}

/// The standard deviation of `x` about its mean.
fn sigma(x: &[f64]) -> f64 {
    let n = x.len().max(1) as f64;
    let m = x.iter().sum::<f64>() / n;
    (x.iter().map(|v| (v - m) * (v - m)).sum::<f64>() / n).sqrt()
}

/// Residual of the least-squares parabola through `y` (at t = 0, 1, …).
fn quadratic_residual(y: &[f64]) -> Vec<f64> {
    // Centred abscissae make the normal equations well conditioned; the
    // parabola a + b t + c t² is fitted by solving them with Cramer's rule.
    let n = y.len() as f64;
    let c0 = (n - 1.0) / 2.0;
    let t: Vec<f64> = (0..y.len()).map(|i| i as f64 - c0).collect();
    let s = |p: i32| t.iter().map(|v| v.powi(p)).sum::<f64>();
    let sy = |p: i32| t.iter().zip(y).map(|(v, w)| v.powi(p) * w).sum::<f64>();
    let m = [[n, s(1), s(2)], [s(1), s(2), s(3)], [s(2), s(3), s(4)]];
    let r = [sy(0), sy(1), sy(2)];
    let det = |a: [[f64; 3]; 3]| {
        a[0][0] * (a[1][1] * a[2][2] - a[1][2] * a[2][1])
            - a[0][1] * (a[1][0] * a[2][2] - a[1][2] * a[2][0])
            + a[0][2] * (a[1][0] * a[2][1] - a[1][1] * a[2][0])
    };
    let d = det(m);
    let coefficient = |k: usize| {
        let mut a = m;
        for (row, value) in a.iter_mut().zip(r) {
            row[k] = value;
        }
        det(a) / d
    };
    let (a, b, c) = (coefficient(0), coefficient(1), coefficient(2));
    t.iter()
        .zip(y)
        .map(|(v, w)| w - (a + b * v + c * v * v))
        .collect()
}

/// The rest-noise statistics over all quiet windows of all channels:
/// `(windows, residual σ, second-difference σ, lag-1 autocorrelation)`.
fn rest_noise(channels: &[Vec<f64>]) -> (usize, f64, f64, f64) {
    let (mut residuals, mut jitters, mut lags) = (Vec::new(), Vec::new(), Vec::new());
    for c in channels {
        for window in c.chunks_exact(QUIET_WINDOW) {
            let (lo, hi) = window
                .iter()
                .fold((f64::INFINITY, f64::NEG_INFINITY), |(l, h), v| {
                    (l.min(*v), h.max(*v))
                });
            if hi - lo >= QUIET_RANGE || lo <= QUIET_FLOOR {
                continue;
            }
            let d = differences(window);
            residuals.push(sigma(&quadratic_residual(window)));
            jitters.push(sigma(&differences(&d)));
            let lag = correlation(&d[..d.len() - 1], &d[1..]);
            if lag.is_finite() {
                lags.push(lag);
            }
        }
    }
    (
        residuals.len(),
        median(&mut residuals),
        median(&mut jitters),
        median(&mut lags),
    )
}

/// The fewest frames from 10% to 90% of a rise of at least 0.5 in `x`,
/// measured from each local minimum below 0.2 to the highest value within
/// the next 30 frames.
fn fastest_rise(x: &[f64]) -> Option<usize> {
    let mut best: Option<usize> = None;
    for t0 in 1..x.len().saturating_sub(1) {
        if !(x[t0] < 0.2 && x[t0] <= x[t0 - 1] && x[t0] < x[t0 + 1]) {
            continue;
        }
        let end = (t0 + 30).min(x.len());
        let (peak_at, peak) =
            x[t0..end]
                .iter()
                .enumerate()
                .fold(
                    (0, f64::NEG_INFINITY),
                    |b, (k, v)| if *v > b.1 { (k, *v) } else { b },
                );
        let (lo, rise) = (x[t0], peak - x[t0]);
        if rise < 0.5 {
            continue;
        }
        let crosses = |level: f64| {
            x[t0..=t0 + peak_at]
                .iter()
                .position(|v| *v >= lo + level * rise)
        };
        if let (Some(a), Some(b)) = (crosses(0.1), crosses(0.9)) {
            best = Some(best.map_or(b - a, |m| m.min(b - a)));
        }
    }
    best
}

fn median(values: &mut [f64]) -> f64 {
    percentile(values, 0.5)
}

/// The `q`-quantile of `values` (nearest rank after sorting; NaN if empty).
fn percentile(values: &mut [f64], q: f64) -> f64 {
    if values.is_empty() {
        return f64::NAN;
    }
    values.sort_by(f64::total_cmp);
    let k = ((values.len() - 1) as f64 * q).round() as usize;
    values[k.min(values.len() - 1)]
}

fn differences(x: &[f64]) -> Vec<f64> {
    x.windows(2).map(|w| w[1] - w[0]).collect()
}

/// 1.4826 · median absolute deviation: σ for Gaussian data.
fn robust_sigma(x: &[f64]) -> f64 {
    let mut v = x.to_vec();
    let m = median(&mut v);
    let mut dev: Vec<f64> = x.iter().map(|y| (y - m).abs()).collect();
    1.4826 * median(&mut dev)
}

fn correlation(a: &[f64], b: &[f64]) -> f64 {
    let n = a.len().min(b.len());
    if n < 2 {
        return f64::NAN;
    }
    let (ma, mb) = (
        a[..n].iter().sum::<f64>() / n as f64,
        b[..n].iter().sum::<f64>() / n as f64,
    );
    let (mut sab, mut saa, mut sbb) = (0.0, 0.0, 0.0);
    for (x, y) in a[..n].iter().zip(&b[..n]) {
        sab += (x - ma) * (y - mb);
        saa += (x - ma) * (x - ma);
        sbb += (y - mb) * (y - mb);
    }
    sab / (saa * sbb).sqrt()
}

/// Length of a Welch segment (frames): 256 frames, 4.3 s at 60 fps, resolve
/// the spectrum to 0.23 Hz.
pub const WELCH_SEGMENT: usize = 256;

/// Share of the power of `x` (sampled at `rate` Hz) in each band of
/// [`BAND_EDGES_HZ`], by Welch's method: the mean periodogram of
/// Hann-windowed segments of [`WELCH_SEGMENT`] frames overlapping by half,
/// each segment's mean removed (a signal shorter than one segment is one
/// segment).
fn band_shares(x: &[f64], rate: f64) -> [f64; 4] {
    let n = WELCH_SEGMENT.min(x.len());
    if n < 4 {
        return [f64::NAN; 4];
    }
    let tau = std::f64::consts::TAU;
    let hann: Vec<f64> = (0..n)
        .map(|t| 0.5 - 0.5 * (tau * t as f64 / n as f64).cos())
        .collect();
    let (cos, sin): (Vec<f64>, Vec<f64>) = (0..n)
        .map(|t| {
            let (s, c) = (tau * t as f64 / n as f64).sin_cos();
            (c, s)
        })
        .unzip();
    let mut power = [0.0; 4];
    let mut start = 0;
    while start + n <= x.len() {
        let segment = &x[start..start + n];
        let mean = segment.iter().sum::<f64>() / n as f64;
        let windowed: Vec<f64> = segment
            .iter()
            .zip(&hann)
            .map(|(v, h)| (v - mean) * h)
            .collect();
        for k in 1..=n / 2 {
            let (mut re, mut im) = (0.0, 0.0);
            for (t, v) in windowed.iter().enumerate() {
                let phase = (k * t) % n;
                re += v * cos[phase];
                im -= v * sin[phase];
            }
            let f = k as f64 * rate / n as f64;
            let band = BAND_EDGES_HZ.iter().filter(|e| f >= **e).count();
            power[band] += re * re + im * im;
        }
        start += n / 2;
    }
    let total: f64 = power.iter().sum();
    if total > 0.0 {
        power.map(|p| p / total)
    } else {
        [f64::NAN; 4]
    }
}

/// The statistics of `frames` (weights and timestamps only).
pub fn stream_statistics(frames: &[Frame]) -> StreamStatistics {
    let channels: Vec<Vec<f64>> = (0..BLENDSHAPE_COUNT)
        .map(|j| frames.iter().map(|f| f64::from(f.weights.0[j])).collect())
        .collect();
    let mut intervals: Vec<f64> = frames
        .windows(2)
        .map(|w| w[1].timestamp - w[0].timestamp)
        .collect();
    let median_interval = median(&mut intervals.clone());
    let rate = if median_interval > 0.0 {
        1.0 / median_interval
    } else {
        60.0
    };
    let moving: Vec<Blendshape> = Blendshape::ALL
        .into_iter()
        .filter(|s| {
            let mut v = channels[s.index()].clone();
            percentile(&mut v, 0.95) - percentile(&mut v, 0.05) >= MOVING_RANGE
        })
        .collect();
    let mut jitters = Vec::new();
    let mut lags = Vec::new();
    let mut bands: [Vec<f64>; 4] = Default::default();
    for s in &moving {
        let d = differences(&channels[s.index()]);
        let d2 = differences(&d);
        jitters.push(robust_sigma(&d2));
        lags.push(correlation(
            &d[..d.len().saturating_sub(1)],
            &d[1.min(d.len())..],
        ));
        for (b, share) in bands.iter_mut().zip(band_shares(&d, rate)) {
            b.push(share);
        }
    }
    let mut mirrors = Vec::new();
    for s in &moving {
        let m = s.mirror();
        if m.index() > s.index() && moving.contains(&m) {
            let a = differences(&channels[s.index()]);
            let b = differences(&channels[m.index()]);
            mirrors.push(correlation(&a, &b));
        }
    }
    let mut quantum = f64::INFINITY;
    for c in &channels {
        let mut v = c.clone();
        v.sort_by(f64::total_cmp);
        for w in v.windows(2) {
            let d = w[1] - w[0];
            if d > 0.0 && d < quantum {
                quantum = d;
            }
        }
    }
    let (quiet_windows, rest_noise, rest_jitter, rest_lag1_autocorrelation) = rest_noise(&channels);
    let fastest_blink_rise = [Blendshape::EyeBlinkLeft, Blendshape::EyeBlinkRight]
        .iter()
        .filter_map(|s| fastest_rise(&channels[s.index()]))
        .min();
    StreamStatistics {
        frames: frames.len(),
        quiet_windows,
        rest_noise,
        rest_jitter,
        rest_lag1_autocorrelation,
        fastest_blink_rise,
        jitter: median(&mut jitters),
        lag1_autocorrelation: median(&mut lags),
        band_shares: std::array::from_fn(|b| median(&mut bands[b])),
        rest_levels: std::array::from_fn(|j| percentile(&mut channels[j].clone(), 0.05)),
        zero_shares: std::array::from_fn(|j| {
            channels[j].iter().filter(|w| **w == 0.0).count() as f64 / frames.len().max(1) as f64
        }),
        long_intervals: intervals
            .iter()
            .filter(|d| **d > 1.5 * median_interval)
            .count(),
        short_intervals: intervals
            .iter_mut()
            .filter(|d| **d < 0.5 * median_interval)
            .count(),
        median_interval,
        quantum,
        mirror_correlation: median(&mut mirrors),
        moving,
    }
}
