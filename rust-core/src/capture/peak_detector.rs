//! §3.1: capture an expression when the requested weight has exceeded a
//! threshold and reached a maximum over time (it starts decreasing).
//!
//! Real trackers make the literal rule fire at the wrong moment, so the
//! detector is causal but patient:
//! - a **one-frame spike** is not a peak: the weight must stay above the
//!   threshold for [`PeakDetectorConfig::min_frames_above`] frames in a row
//!   before a run counts, and a run that ends sooner is forgotten;
//! - **jitter on a plateau** does not fire early: the peak is confirmed only
//!   once the weight has fallen [`PeakDetectorConfig::release`] below the
//!   run's maximum, for [`PeakDetectorConfig::release_frames`] frames;
//! - a **first attempt that never reaches the threshold** never starts a run,
//!   so the detector simply waits for the next one;
//! - a weight that is **already high when detection starts** (the previous
//!   prompt's expression still held, e.g. both eyes looking up after
//!   eyeLookUpLeft when eyeLookUpRight is asked for) is not a performance:
//!   a run can only start after the weight has fallen to
//!   [`PeakDetectorConfig::rearm_below`], clearly under the threshold, so a
//!   held co-activation hovering *at* the threshold cannot slip in on noise.
//!
//! **Where the peak is.** The top of a voluntary expression is flat: within
//! two frames of its peak the activation changes by about as much as ARKit's
//! frame-to-frame noise, so the largest reported weight is a poor estimate of
//! the moment. The run's maximum of a centred three-frame mean locates the
//! peak roughly; a least-squares parabola through the raw weights within
//! [`PeakDetectorConfig::fit_half_width`] frames of it then places the vertex
//! to a fraction of a frame (the sub-sample peak interpolation of spectral
//! analysis, fitted over more samples because the noise is not small).
//! Where the tracker saturates at 1, the middle of the saturated stretch is
//! taken instead. Finally the tracker's filtering delay
//! [`PeakDetectorConfig::latency_frames`] is subtracted, so the reported
//! frame is the one at which the *face* peaked, whose geometry is captured.

use glam::{DMat3, DVec3};
use std::collections::VecDeque;

/// The detector's parameters; [`Default`] gives the documented values.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PeakDetectorConfig {
    /// Weight that counts as performing the expression (default 0.5: the
    /// simulated attempts peak at 0.7–1.0, failed ones at 0.15–0.35).
    pub threshold: f32,
    /// Level the weight must fall to, at the start and after each peak,
    /// before a new run can start (default 0.4: a held level jittering at
    /// the threshold, ARKit's frame noise being about 0.01, never gets
    /// there; a person starting an expression always does).
    pub rearm_below: f32,
    /// Frames in a row above the threshold before a run counts (default 3,
    /// 50 ms at 60 fps: longer than a tracker glitch, shorter than any
    /// deliberate expression).
    pub min_frames_above: usize,
    /// How far below the run's maximum the weight must fall to confirm the
    /// peak (default 0.05, five times ARKit's frame-to-frame jitter).
    pub release: f32,
    /// Frames in a row the weight must stay that far below (default 2).
    pub release_frames: usize,
    /// Half-width of the parabola fit around the rough peak (default 4, a
    /// 9-frame = 150 ms fit: the top of an expression is flat to within
    /// noise over about ±2 frames, and nine samples cut the noise on the
    /// vertex about threefold compared with three).
    pub fit_half_width: usize,
    /// How many frames the tracked weights trail the face (default 1.0).
    /// ARKit filters its weight estimates over time; an exponential filter
    /// of factor α delays a parabolic peak by (1 − α)/α frames: 1 frame for
    /// α = 0.5, the first tracker model of `sim-data`, 0.4 for the measured
    /// one (α = 0.7; real blinks bound the delay to under a frame). The
    /// default was fixed on the first model and kept: on the second, the
    /// committed subjects' prompts land at +0.1 frames on average and
    /// twenty further subjects' at +0.05 (the remaining delay is the
    /// expressions' own asymmetry about their peak). Set it to 0 for weights
    /// that are not filtered.
    pub latency_frames: f32,
}

impl Default for PeakDetectorConfig {
    fn default() -> Self {
        PeakDetectorConfig {
            threshold: 0.5,
            rearm_below: 0.4,
            min_frames_above: 3,
            release: 0.05,
            release_frames: 2,
            fit_half_width: 4,
            latency_frames: 1.0,
        }
    }
}

/// A confirmed peak.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Peak {
    /// Index of the frame at which the face peaked, counted from the first
    /// frame pushed: [`Peak::position`] rounded.
    pub frame: usize,
    /// Sub-frame position of the peak, latency subtracted.
    pub position: f64,
    /// The run's largest three-frame mean of the weight.
    pub weight: f32,
    /// When the weight was saturated at its top (the tracker clamps at 1):
    /// the first and last frame of the saturated stretch, latency subtracted.
    /// The weight cannot say where in the stretch the face peaked (the
    /// reported frame is its middle); the mesh can, see the guided capture.
    pub saturated: Option<(usize, usize)>,
}

/// Online peak detection on one weight, one frame at a time.
#[derive(Clone, Debug)]
pub struct PeakDetector {
    config: PeakDetectorConfig,
    /// Frames pushed so far.
    count: usize,
    /// The last three raw weights (oldest first) for the centred mean.
    recent: [f32; 3],
    /// Consecutive frames above the threshold.
    above: usize,
    /// Best smoothed value of the current run, and its first and last frame.
    best: Option<(f32, usize, usize)>,
    /// Consecutive frames below best − release.
    released: usize,
    /// At the start and after a peak, no run starts until the weight has
    /// fallen to `rearm_below`.
    waiting_for_release: bool,
    /// Raw weights from frame `history_start` on: enough to fit the parabola
    /// around the run's best frame.
    history: VecDeque<f32>,
    history_start: usize,
}

impl PeakDetector {
    /// A detector with `config`.
    pub fn new(config: PeakDetectorConfig) -> PeakDetector {
        PeakDetector {
            config,
            count: 0,
            recent: [0.0; 3],
            above: 0,
            best: None,
            released: 0,
            waiting_for_release: true,
            history: VecDeque::new(),
            history_start: 0,
        }
    }

    /// The earliest frame a peak reported from now on can be: frames before
    /// it may be forgotten by whoever keeps them.
    pub fn oldest_needed(&self) -> usize {
        self.history_start
    }

    /// Feeds the next frame's weight; returns the peak once it is confirmed
    /// (a few frames after it happened). Non-finite weights count as 0.
    pub fn push(&mut self, weight: f32) -> Option<Peak> {
        let w = if weight.is_finite() { weight } else { 0.0 };
        self.recent = [self.recent[1], self.recent[2], w];
        self.count += 1;
        self.remember(w);
        let c = &self.config;
        if self.waiting_for_release {
            if w > c.rearm_below {
                return None;
            }
            self.waiting_for_release = false;
        }
        if w > c.threshold {
            self.above += 1;
        } else if self.best.is_none() {
            // A run too short to count (a spike) is forgotten.
            self.above = 0;
        }
        if self.count < 2 || self.above < c.min_frames_above {
            return None;
        }
        // The centred mean belongs to the previous frame.
        let frame = self.count - 2;
        let smoothed = (self.recent[0] + self.recent[1] + self.recent[2]) / 3.0;
        let centre = self.recent[1];
        let value = if centre > c.threshold {
            smoothed
        } else {
            f32::MIN
        };
        match self.best {
            Some((b, first, _)) if value == b => self.best = Some((b, first, frame)),
            Some((b, _, _)) if value < b => {}
            _ if value > f32::MIN => {
                self.best = Some((value, frame, frame));
                self.released = 0;
            }
            _ => {}
        }
        let (b, first, last) = self.best?;
        if w < b - c.release {
            self.released += 1;
        } else {
            self.released = 0;
        }
        if self.released >= c.release_frames {
            let latency = f64::from(c.latency_frames);
            let position = (self.locate(first, last) - latency).max(0.0);
            let shift = |f: usize| (f as f64 - latency).max(0.0).round() as usize;
            let peak = Peak {
                frame: position.round() as usize,
                position,
                weight: b,
                saturated: (last > first).then(|| (shift(first), shift(last))),
            };
            self.above = 0;
            self.best = None;
            self.released = 0;
            self.waiting_for_release = true;
            return Some(peak);
        }
        None
    }

    /// Appends `w` to the history and drops what no peak can need.
    fn remember(&mut self, w: f32) {
        self.history.push_back(w);
        // The reported frame can lie `fit_half_width` + latency before the
        // best frame, which can be the frame before the newest.
        // Saturating: the configuration is public, and absurd values must
        // keep everything rather than overflow.
        let reach = self
            .config
            .fit_half_width
            .saturating_add(self.config.latency_frames.max(0.0).ceil() as usize);
        let keep_from = match self.best {
            Some((_, first, _)) => first.saturating_sub(reach),
            None => self.count.saturating_sub(reach.saturating_add(2)),
        };
        while self.history_start < keep_from && !self.history.is_empty() {
            self.history.pop_front();
            self.history_start += 1;
        }
    }

    /// Sub-frame peak of the run whose best three-frame mean spans frames
    /// `first..=last`: the middle of a saturated stretch, else the vertex of
    /// the least-squares parabola through the raw weights within
    /// `fit_half_width` frames of `first`, kept within that window.
    ///
    /// Indexing: `history` holds frames `history_start..count`, and the
    /// window `lo..=hi` is clamped to them (`count ≥ 2` here).
    fn locate(&self, first: usize, last: usize) -> f64 {
        if last > first {
            return (first + last) as f64 / 2.0;
        }
        let k = self.config.fit_half_width;
        let lo = first.saturating_sub(k).max(self.history_start);
        let hi = first.saturating_add(k).min(self.count - 1);
        let samples = (lo..=hi).map(|f| {
            let y = f64::from(self.history[f - self.history_start]);
            (f as f64 - first as f64, y)
        });
        let offset = parabola_vertex(samples)
            .map(|x| x.clamp(lo as f64 - first as f64, hi as f64 - first as f64))
            .unwrap_or(0.0);
        first as f64 + offset
    }
}

/// Vertex of the least-squares parabola y = a + b·x + c·x² through
/// `samples` (x, y), if it opens downwards: x* = −b / 2c.
fn parabola_vertex(samples: impl Iterator<Item = (f64, f64)>) -> Option<f64> {
    // Normal equations: [Σ1 Σx Σx²; Σx Σx² Σx³; Σx² Σx³ Σx⁴] (a b c)ᵀ = (Σy Σxy Σx²y)ᵀ.
    let mut m = [0.0f64; 5];
    let mut r = DVec3::ZERO;
    for (x, y) in samples {
        let mut p = 1.0;
        for power in m.iter_mut() {
            *power += p;
            p *= x;
        }
        r += DVec3::new(y, x * y, x * x * y);
    }
    let normal = DMat3::from_cols_array(&[m[0], m[1], m[2], m[1], m[2], m[3], m[2], m[3], m[4]]);
    if normal.determinant().abs() < 1e-9 {
        return None;
    }
    let abc = normal.inverse() * r;
    (abc.z < 0.0).then(|| -abc.y / (2.0 * abc.z))
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Unfiltered weights: no latency to subtract.
    fn unfiltered() -> PeakDetectorConfig {
        PeakDetectorConfig {
            latency_frames: 0.0,
            ..PeakDetectorConfig::default()
        }
    }

    fn detect(weights: &[f32]) -> Vec<Peak> {
        let mut d = PeakDetector::new(unfiltered());
        weights.iter().filter_map(|w| d.push(*w)).collect()
    }

    /// A smooth bump peaking at frame `at` with height `h`.
    fn bump(len: usize, at: f32, h: f32) -> Vec<f32> {
        (0..len)
            .map(|f| h * (-((f as f32 - at) / 8.0).powi(2)).exp())
            .collect()
    }

    #[test]
    fn finds_a_smooth_peak_at_its_frame() {
        let peaks = detect(&bump(80, 40.0, 0.9));
        assert_eq!(peaks.len(), 1);
        assert_eq!(peaks[0].frame, 40);
        assert!((peaks[0].position - 40.0).abs() < 0.01, "{peaks:?}");
    }

    #[test]
    fn the_parabola_finds_a_peak_between_frames() {
        let peaks = detect(&bump(80, 40.4, 0.9));
        assert!((peaks[0].position - 40.4).abs() < 0.05, "{peaks:?}");
    }

    #[test]
    fn the_latency_is_subtracted() {
        let mut d = PeakDetector::new(PeakDetectorConfig::default());
        let peaks: Vec<Peak> = bump(80, 40.0, 0.9)
            .iter()
            .filter_map(|w| d.push(*w))
            .collect();
        assert_eq!(peaks[0].frame, 39);
    }

    #[test]
    fn noise_on_a_flat_top_moves_the_fitted_peak_less_than_the_largest_sample() {
        // A flat top (σ = 12 frames) with ±0.01 pseudo-random noise: the
        // largest sample wanders, the fitted vertex stays within a frame.
        let mut worst_fit = 0.0f64;
        let mut worst_argmax = 0usize;
        for seed in 0..50u32 {
            let w: Vec<f32> = (0..100u32)
                .map(|f| {
                    let hash = f.wrapping_mul(2_654_435_761).wrapping_add(seed * 40_503) >> 8;
                    let noise = (hash % 2001) as f32 / 100_000.0 - 0.01;
                    0.9 * (-((f as f32 - 50.0) / 12.0).powi(2)).exp() + noise
                })
                .collect();
            let argmax = (0..100).max_by(|a, b| w[*a].total_cmp(&w[*b])).unwrap();
            worst_argmax = worst_argmax.max(argmax.abs_diff(50));
            let peaks = detect(&w);
            assert_eq!(peaks.len(), 1);
            worst_fit = worst_fit.max((peaks[0].position - 50.0).abs());
        }
        assert!(worst_fit < 1.5, "fitted peak {worst_fit} frames off");
        assert!(
            worst_fit < worst_argmax as f64,
            "{worst_fit} vs {worst_argmax}"
        );
    }

    #[test]
    fn a_one_frame_spike_is_not_a_peak() {
        let mut w = bump(100, 70.0, 0.9);
        w[20] = 1.0;
        let peaks = detect(&w);
        assert_eq!(peaks.len(), 1);
        assert_eq!(peaks[0].frame, 70);
    }

    #[test]
    fn an_attempt_below_the_threshold_is_waited_out() {
        let mut w = bump(60, 20.0, 0.35);
        w.extend(bump(80, 40.0, 0.8));
        let peaks = detect(&w);
        assert_eq!(peaks.len(), 1);
        assert_eq!(peaks[0].frame, 100);
    }

    #[test]
    fn jitter_on_a_plateau_does_not_fire_early() {
        let mut w: Vec<f32> = (0..20).map(|f| f as f32 * 0.045).collect();
        w.extend((0..40).map(|f| 0.9 + 0.02 * ((f * 7 % 5) as f32 - 2.0) / 2.0));
        w.extend((0..20).map(|f| 0.9 - f as f32 * 0.045));
        let peaks = detect(&w);
        assert_eq!(peaks.len(), 1, "{peaks:?}");
        assert!(peaks[0].frame >= 20 && peaks[0].frame < 60);
    }

    #[test]
    fn a_saturated_peak_is_reported_at_its_middle() {
        let mut w: Vec<f32> = (0..20).map(|f| f as f32 * 0.06).collect();
        w.iter_mut().for_each(|x| *x = x.min(1.0));
        w.extend([1.0; 10]);
        w.extend((0..20).map(|f| 1.0 - f as f32 * 0.06));
        let peaks = detect(&w);
        assert_eq!(peaks.len(), 1);
        assert!((20..=30).contains(&peaks[0].frame), "{peaks:?}");
    }

    #[test]
    fn nan_weights_count_as_zero() {
        let mut w = bump(80, 40.0, 0.9);
        w[5] = f32::NAN;
        assert_eq!(detect(&w).len(), 1);
    }

    #[test]
    fn absurd_configurations_and_weights_do_not_panic() {
        let mut w = bump(80, 40.0, 0.9);
        w.extend([
            f32::INFINITY,
            f32::NEG_INFINITY,
            1e30,
            -1e30,
            0.9,
            0.9,
            0.0,
            0.0,
        ]);
        w.extend(bump(40, 20.0, 1.0));
        let configs = [
            PeakDetectorConfig {
                fit_half_width: usize::MAX,
                latency_frames: f32::INFINITY,
                ..unfiltered()
            },
            PeakDetectorConfig {
                fit_half_width: usize::MAX - 1,
                latency_frames: f32::NAN,
                min_frames_above: 0,
                release_frames: 0,
                ..unfiltered()
            },
            PeakDetectorConfig {
                threshold: f32::NAN,
                rearm_below: f32::NAN,
                release: f32::NEG_INFINITY,
                latency_frames: -5.0,
                fit_half_width: 0,
                ..unfiltered()
            },
        ];
        for config in configs {
            let mut d = PeakDetector::new(config);
            for x in &w {
                if let Some(peak) = d.push(*x) {
                    assert!(
                        peak.position.is_finite() && peak.position >= 0.0,
                        "{peak:?}"
                    );
                }
            }
        }
    }
}
