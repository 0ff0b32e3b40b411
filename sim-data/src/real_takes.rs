//! Statistics of real ARKit weight streams, measured once and committed as
//! numbers (the takes themselves are not ours to commit), so that a test on
//! a fresh clone can hold the simulated tracker to them.
//!
//! Provenance: six Live Link Face takes (an iPhone with a TrueDepth
//! camera, 60 fps, exported with the app's neutral-pose calibration),
//! `MySlate_164…169_iPhone_cal.csv` from the repository
//! AnimaVR/NeuroSync_Player, folder `livelink/animations/`, commit
//! f31b8fad5d8673b8d23257c1f1efe0549c2b51b0 (MIT licence for individuals
//! and small businesses); 1,825–1,895 frames each, free performances
//! (angry, sad), weights only. Measured with
//! `cargo run --release -p likeness-sim --example measure_streams -- TAKES…`
//! ([`crate::stream_statistics`]), on 2026-12-01.

/// One take's figures (see [`crate::stream_statistics::StreamStatistics`]).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct RealTake {
    /// The take's file.
    pub name: &'static str,
    /// Frames.
    pub frames: usize,
    /// Quiet windows found.
    pub quiet_windows: usize,
    /// Median residual σ of a quiet window after a quadratic fit.
    pub rest_noise: f64,
    /// Median σ of a quiet window's second differences.
    pub rest_jitter: f64,
    /// Median lag-1 autocorrelation of a quiet window's first differences.
    pub rest_lag1_autocorrelation: f64,
    /// Fewest frames from 10% to 90% of an eyeBlink rise of at least 0.5.
    pub fastest_blink_rise: usize,
    /// Channels whose 5th percentile is exactly 0.
    pub channels_resting_at_zero: usize,
    /// Median spacing of the timecodes (s).
    pub median_interval: f64,
    /// Spacings over 1.5 or under 0.5 times the median.
    pub irregular_intervals: usize,
    /// Whole take, moving channels: median robust σ of second differences.
    pub jitter: f64,
    /// Whole take, moving channels: median lag-1 autocorrelation of the
    /// first differences.
    pub lag1_autocorrelation: f64,
    /// Whole take, moving channels: median share of the power of `Δw`
    /// below 2 Hz, 2–6, 6–15 and above 15 Hz.
    pub band_shares: [f64; 4],
    /// Whole take: median correlation of the first differences of
    /// left/right pairs that both move.
    pub mirror_correlation: f64,
}

/// The six takes. Every value is printed to at most 0.5% of rounding; the
/// timecodes advance by 1.001–1.002 frames per row, hence 0.01670 s.
pub const REAL_TAKES: [RealTake; 6] = [
    RealTake {
        name: "MySlate_164_iPhone_cal.csv",
        frames: 1895,
        quiet_windows: 738,
        rest_noise: 8.19e-4,
        rest_jitter: 2.86e-4,
        rest_lag1_autocorrelation: 0.802,
        fastest_blink_rise: 2,
        channels_resting_at_zero: 38,
        median_interval: 0.01670,
        irregular_intervals: 0,
        jitter: 1.380e-4,
        lag1_autocorrelation: 0.670,
        band_shares: [0.186, 0.335, 0.300, 0.120],
        mirror_correlation: 0.925,
    },
    RealTake {
        name: "MySlate_165_iPhone_cal.csv",
        frames: 1852,
        quiet_windows: 801,
        rest_noise: 7.70e-4,
        rest_jitter: 2.62e-4,
        rest_lag1_autocorrelation: 0.798,
        fastest_blink_rise: 2,
        channels_resting_at_zero: 39,
        median_interval: 0.01670,
        irregular_intervals: 0,
        jitter: 1.468e-4,
        lag1_autocorrelation: 0.697,
        band_shares: [0.237, 0.308, 0.266, 0.098],
        mirror_correlation: 0.906,
    },
    RealTake {
        name: "MySlate_166_iPhone_cal.csv",
        frames: 1848,
        quiet_windows: 782,
        rest_noise: 7.06e-4,
        rest_jitter: 2.71e-4,
        rest_lag1_autocorrelation: 0.795,
        fastest_blink_rise: 2,
        channels_resting_at_zero: 34,
        median_interval: 0.01670,
        irregular_intervals: 0,
        jitter: 3.140e-4,
        lag1_autocorrelation: 0.699,
        band_shares: [0.319, 0.312, 0.235, 0.099],
        mirror_correlation: 0.844,
    },
    RealTake {
        name: "MySlate_167_iPhone_cal.csv",
        frames: 1825,
        quiet_windows: 692,
        rest_noise: 6.62e-4,
        rest_jitter: 2.37e-4,
        rest_lag1_autocorrelation: 0.803,
        fastest_blink_rise: 2,
        channels_resting_at_zero: 37,
        median_interval: 0.01670,
        irregular_intervals: 0,
        jitter: 1.870e-4,
        lag1_autocorrelation: 0.645,
        band_shares: [0.200, 0.331, 0.322, 0.127],
        mirror_correlation: 1.000,
    },
    RealTake {
        name: "MySlate_168_iPhone_cal.csv",
        frames: 1838,
        quiet_windows: 578,
        rest_noise: 8.58e-4,
        rest_jitter: 3.22e-4,
        rest_lag1_autocorrelation: 0.782,
        fastest_blink_rise: 2,
        channels_resting_at_zero: 41,
        median_interval: 0.01670,
        irregular_intervals: 0,
        jitter: 1.913e-4,
        lag1_autocorrelation: 0.594,
        band_shares: [0.126, 0.346, 0.315, 0.169],
        mirror_correlation: 1.000,
    },
    RealTake {
        name: "MySlate_169_iPhone_cal.csv",
        frames: 1852,
        quiet_windows: 587,
        rest_noise: 9.20e-4,
        rest_jitter: 3.03e-4,
        rest_lag1_autocorrelation: 0.799,
        fastest_blink_rise: 2,
        channels_resting_at_zero: 40,
        median_interval: 0.01670,
        irregular_intervals: 0,
        jitter: 1.780e-4,
        lag1_autocorrelation: 0.664,
        band_shares: [0.199, 0.338, 0.313, 0.123],
        mirror_correlation: 1.000,
    },
];

/// The smallest and largest value of `f` over the takes.
pub fn range(f: impl Fn(&RealTake) -> f64) -> (f64, f64) {
    REAL_TAKES
        .iter()
        .map(f)
        .fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), v| {
            (lo.min(v), hi.max(v))
        })
}
