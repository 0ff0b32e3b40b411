//! §3.1: the neutral scan. It is taken once the face has been relaxed and
//! still for about a second: every weight low, no weight changing, and the
//! mesh not moving.
//!
//! A real person's relaxed face is not ARKit's zero: some shapes rest well
//! above 0 (a brow that rests low reads as browDown 0.3–0.5). Such a face
//! is still, just not low: after [`NeutralConfig::relaxed_duration`] of
//! stillness with every weight at most [`NeutralConfig::max_rest_weight`],
//! it is taken as the person's neutral too, and the weights it rests at are
//! the person's *rest levels*, which the expression detectors then measure
//! from ([`crate::capture::rest_levels`]).

use crate::arkit::{BLENDSHAPE_COUNT, Weights};
use crate::session::Frame;
use std::collections::VecDeque;

/// When a face counts as neutral and still; [`Default`] gives the
/// documented values.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct NeutralConfig {
    /// Largest weight a relaxed face may show (default 0.25: ARKit reports
    /// 0.05–0.2 on some shapes of a relaxed face, e.g. a slight squint or
    /// jaw opening, while a performed expression is above 0.5).
    pub max_weight: f32,
    /// Largest change of any weight within the still stretch (default 0.08,
    /// several times ARKit's frame-to-frame jitter of about 0.01).
    pub max_weight_change: f32,
    /// Largest RMS vertex distance (m) between any frame of the stretch and
    /// its last frame (default 1 mm: ARKit's mesh wanders 0.1–0.3 mm on a
    /// still face; a blink or a twitch moves it several millimetres).
    pub max_motion: f32,
    /// How long the face must stay so (s, default 1.0).
    pub duration: f64,
    /// Largest weight a still face may rest at and still be taken, after
    /// [`NeutralConfig::relaxed_duration`], as the person's neutral
    /// (default 0.6: above the 0.3–0.5 at which shapes of some relaxed
    /// faces rest, below the 0.7–1.0 of a performed expression).
    pub max_rest_weight: f32,
    /// How long a still face with a weight above
    /// [`NeutralConfig::max_weight`] must stay so (s, default 1.5: half a
    /// second more than a low face, so that an expression on its way, which
    /// is not still that long, is not taken).
    pub relaxed_duration: f64,
}

impl Default for NeutralConfig {
    fn default() -> Self {
        NeutralConfig {
            max_weight: 0.25,
            max_weight_change: 0.08,
            max_motion: 0.001,
            duration: 1.0,
            max_rest_weight: 0.6,
            relaxed_duration: 1.5,
        }
    }
}

/// Online detection of a still, neutral stretch, one frame at a time.
#[derive(Clone, Debug)]
pub struct NeutralDetector {
    config: NeutralConfig,
    /// The current still stretch: (stream index, frame), oldest first.
    window: VecDeque<(u64, Frame)>,
}

impl NeutralDetector {
    /// A detector with `config`.
    pub fn new(config: NeutralConfig) -> NeutralDetector {
        NeutralDetector {
            config,
            window: VecDeque::new(),
        }
    }

    /// Feeds frame number `index`; once the stretch ending here has lasted
    /// [`NeutralConfig::duration`] (every weight at most
    /// [`NeutralConfig::max_weight`]) or [`NeutralConfig::relaxed_duration`]
    /// (every weight at most [`NeutralConfig::max_rest_weight`]), returns
    /// the neutral scan: the newest frame of the stretch that carries a mesh
    /// (else the newest frame), and the rest levels, each weight's mean over
    /// the stretch.
    pub fn push(&mut self, index: u64, frame: Frame) -> Option<NeutralScan> {
        let c = self.config;
        if !frame.tracked
            || frame
                .weights
                .0
                .iter()
                .any(|w| w.is_nan() || *w > c.max_rest_weight)
        {
            self.window.clear();
            return None;
        }
        // Everything up to the last frame that differs too much from this
        // one is not part of a still stretch ending here.
        let moved = self
            .window
            .iter()
            .rposition(|(_, old)| !still(old, &frame, &c));
        if let Some(last_moved) = moved {
            self.window.drain(..=last_moved);
        }
        self.window.push_back((index, frame));
        let span = self.window.back()?.1.timestamp - self.window.front()?.1.timestamp;
        let low = self
            .window
            .iter()
            .all(|(_, f)| f.weights.0.iter().all(|w| *w <= c.max_weight));
        let needed = if low { c.duration } else { c.relaxed_duration };
        // Half a frame of slack for timestamps that jitter.
        if span < needed * 0.99 {
            return None;
        }
        let mut sum = [0.0f64; BLENDSHAPE_COUNT];
        for (_, f) in &self.window {
            for (s, w) in sum.iter_mut().zip(&f.weights.0) {
                *s += f64::from(*w);
            }
        }
        let n = self.window.len() as f64;
        let rest = Weights(sum.map(|s| (s / n) as f32));
        let keep = self
            .window
            .iter()
            .rposition(|(_, f)| f.vertices.is_some())
            .unwrap_or(self.window.len() - 1);
        let chosen = self.window.remove(keep);
        self.window.clear();
        chosen.map(|(index, frame)| NeutralScan { index, frame, rest })
    }
}

/// The neutral scan the detector chose.
#[derive(Clone, Debug, PartialEq)]
pub struct NeutralScan {
    /// Its index in the stream.
    pub index: u64,
    /// The frame.
    pub frame: Frame,
    /// Each weight's mean over the still stretch: the person's rest levels.
    pub rest: Weights,
}

/// Whether `old` and `new` show the same still face: weights within
/// `max_weight_change`, and (when both carry meshes) an RMS vertex distance
/// within `max_motion`.
fn still(old: &Frame, new: &Frame, c: &NeutralConfig) -> bool {
    let weights = old
        .weights
        .0
        .iter()
        .zip(&new.weights.0)
        .all(|(a, b)| (a - b).abs() <= c.max_weight_change);
    let mesh = match (&old.vertices, &new.vertices) {
        (Some(a), Some(b)) if a.len() == b.len() && !a.is_empty() => {
            let sum: f32 = a.iter().zip(b).map(|(p, q)| p.distance_squared(*q)).sum();
            (sum / a.len() as f32).sqrt() <= c.max_motion
        }
        _ => true,
    };
    weights && mesh
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::Weights;
    use glam::Vec3;

    fn frame(t: f64, w: f32, offset: f32) -> Frame {
        Frame {
            timestamp: t,
            weights: Weights([w; crate::BLENDSHAPE_COUNT]),
            tracked: true,
            vertices: Some(vec![Vec3::new(offset, 0.0, 0.0); 10]),
        }
    }

    fn run(frames: impl Iterator<Item = Frame>) -> Option<u64> {
        let mut d = NeutralDetector::new(NeutralConfig::default());
        frames
            .enumerate()
            .find_map(|(i, f)| d.push(i as u64, f))
            .map(|scan| scan.index)
    }

    #[test]
    fn a_still_relaxed_second_is_captured_at_its_end() {
        let found = run((0..200).map(|i| frame(i as f64 / 60.0, 0.05, 0.0)));
        assert_eq!(found, Some(60));
    }

    #[test]
    fn a_raised_weight_restarts_the_second() {
        let found =
            run((0..200).map(|i| frame(i as f64 / 60.0, if i == 30 { 0.6 } else { 0.05 }, 0.0)));
        assert_eq!(found, Some(91));
    }

    #[test]
    fn a_moving_mesh_is_not_still() {
        // 2 mm jump at frame 40: the stretch restarts there.
        let found =
            run((0..200).map(|i| frame(i as f64 / 60.0, 0.05, if i < 40 { 0.0 } else { 0.002 })));
        assert_eq!(found, Some(100));
    }

    #[test]
    fn untracked_frames_restart_the_second() {
        let found = run((0..200).map(|i| Frame {
            tracked: i != 10,
            ..frame(i as f64 / 60.0, 0.05, 0.0)
        }));
        assert_eq!(found, Some(71));
    }

    #[test]
    fn a_face_that_never_relaxes_is_never_neutral() {
        assert_eq!(
            run((0..200).map(|i| frame(i as f64 / 60.0, 0.7, 0.0))),
            None
        );
    }

    #[test]
    fn a_face_resting_high_is_its_own_neutral_after_longer_stillness() {
        // Every weight at 0.4: still, but not low; taken after 1.5 s, with
        // its rest levels.
        let mut d = NeutralDetector::new(NeutralConfig::default());
        let scan = (0..200)
            .map(|i| frame(i as f64 / 60.0, 0.4, 0.0))
            .enumerate()
            .find_map(|(i, f)| d.push(i as u64, f))
            .expect("a neutral scan");
        assert_eq!(scan.index, 90);
        assert!(scan.rest.0.iter().all(|r| (r - 0.4).abs() < 1e-6));
    }
}
