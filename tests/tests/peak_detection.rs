//! The peak detector of §3.1 on the committed sessions' recorded streams,
//! prompts taken in the app's order, one detector per prompt: every prompt is
//! captured, in order, near its true peak, despite the injected one-frame
//! spikes, failed first attempts and held co-activations (conjugate gaze).
//!
//! Measured with the default parameters: capture − true peak ranges from −1
//! to +4 frames over the 208 prompts, median +1, because the tracker's
//! smoothing delays the weights. This test guards that; the target for the
//! guided capture is ±2 frames, which the detector does not reach yet.

use likeness::peak_detector::{PeakDetector, PeakDetectorConfig};
use likeness::prompt_order::PROMPT_ORDER;

#[test]
fn every_prompt_of_every_committed_session_is_captured_near_its_true_peak() {
    for seed in 1..=4 {
        let path = format!(
            "{}/../sim-data/sessions/subject-{seed}.likeness",
            env!("CARGO_MANIFEST_DIR")
        );
        let session = likeness::session_file::read(path).expect("committed session");
        let truth = session.truth.as_ref().expect("simulated");
        let mut prompt = 0;
        let mut detector = PeakDetector::new(PeakDetectorConfig::default());
        let mut pushed: Vec<usize> = Vec::new();
        let mut offsets = Vec::new();
        for (f, frame) in session.frames.iter().enumerate() {
            if prompt == PROMPT_ORDER.len() {
                break;
            }
            if !frame.tracked {
                continue;
            }
            pushed.push(f);
            if let Some(peak) = detector.push(frame.weights.get(PROMPT_ORDER[prompt])) {
                let shape = PROMPT_ORDER[prompt];
                let true_peak = truth
                    .peak_frames
                    .iter()
                    .find(|p| p.0 == shape)
                    .expect("truth")
                    .1;
                offsets.push(pushed[peak.frame] as i64 - i64::from(true_peak));
                prompt += 1;
                detector = PeakDetector::new(PeakDetectorConfig::default());
                pushed.clear();
            }
        }
        assert_eq!(prompt, 52, "seed {seed}: only {prompt} prompts captured");
        let worst = offsets.iter().map(|o| o.abs()).max().unwrap_or(0);
        assert!(
            worst <= 4,
            "seed {seed}: a capture is {worst} frames from its true peak: {offsets:?}"
        );
        let mut sorted = offsets.clone();
        sorted.sort_unstable();
        assert!(
            sorted[26].abs() <= 2,
            "seed {seed}: median offset {}",
            sorted[26]
        );
    }
}
