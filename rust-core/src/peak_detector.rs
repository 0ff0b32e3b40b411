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
//!   a run can only start after the weight has been at or below the
//!   threshold.
//!
//! The reported frame is the maximum of the run, of the weight smoothed by a
//! centred three-frame mean (one frame of tracker noise cannot move it); where
//! the tracker saturates at 1, the middle of the saturated stretch.

/// The detector's parameters; [`Default`] gives the documented values.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PeakDetectorConfig {
    /// Weight that counts as performing the expression (default 0.5: the
    /// simulated attempts peak at 0.7–1.0, failed ones at 0.15–0.35).
    pub threshold: f32,
    /// Frames in a row above the threshold before a run counts (default 3,
    /// 50 ms at 60 fps: longer than a tracker glitch, shorter than any
    /// deliberate expression).
    pub min_frames_above: usize,
    /// How far below the run's maximum the weight must fall to confirm the
    /// peak (default 0.05, five times ARKit's frame-to-frame jitter).
    pub release: f32,
    /// Frames in a row the weight must stay that far below (default 2).
    pub release_frames: usize,
}

impl Default for PeakDetectorConfig {
    fn default() -> Self {
        PeakDetectorConfig {
            threshold: 0.5,
            min_frames_above: 3,
            release: 0.05,
            release_frames: 2,
        }
    }
}

/// A confirmed peak.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Peak {
    /// Index of the peak frame, counted from the first frame pushed.
    pub frame: usize,
    /// The (smoothed) weight there.
    pub weight: f32,
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
    /// been at or below the threshold.
    waiting_for_release: bool,
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
        }
    }

    /// Forgets everything, frame count included (for a retake).
    pub fn reset(&mut self) {
        *self = PeakDetector::new(self.config);
    }

    /// Feeds the next frame's weight; returns the peak once it is confirmed
    /// (a few frames after it happened). Non-finite weights count as 0.
    pub fn push(&mut self, weight: f32) -> Option<Peak> {
        let w = if weight.is_finite() { weight } else { 0.0 };
        self.recent = [self.recent[1], self.recent[2], w];
        self.count += 1;
        let c = &self.config;
        if self.waiting_for_release {
            if w > c.threshold {
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
            let peak = Peak {
                frame: (first + last) / 2,
                weight: b,
            };
            self.above = 0;
            self.best = None;
            self.released = 0;
            self.waiting_for_release = true;
            return Some(peak);
        }
        None
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn detect(weights: &[f32]) -> Vec<Peak> {
        let mut d = PeakDetector::new(PeakDetectorConfig::default());
        weights.iter().filter_map(|w| d.push(*w)).collect()
    }

    /// A smooth bump peaking at frame `at` with height `h`.
    fn bump(len: usize, at: usize, h: f32) -> Vec<f32> {
        (0..len)
            .map(|f| h * (-((f as f32 - at as f32) / 8.0).powi(2)).exp())
            .collect()
    }

    #[test]
    fn finds_a_smooth_peak_at_its_frame() {
        let peaks = detect(&bump(80, 40, 0.9));
        assert_eq!(peaks.len(), 1);
        assert_eq!(peaks[0].frame, 40);
    }

    #[test]
    fn a_one_frame_spike_is_not_a_peak() {
        let mut w = bump(100, 70, 0.9);
        w[20] = 1.0;
        let peaks = detect(&w);
        assert_eq!(peaks.len(), 1);
        assert_eq!(peaks[0].frame, 70);
    }

    #[test]
    fn an_attempt_below_the_threshold_is_waited_out() {
        let mut w = bump(60, 20, 0.35);
        w.extend(bump(80, 40, 0.8));
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
        let mut w = bump(80, 40, 0.9);
        w[5] = f32::NAN;
        assert_eq!(detect(&w).len(), 1);
    }
}
