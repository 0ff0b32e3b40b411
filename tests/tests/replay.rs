//! The guided capture replayed on the committed simulated sessions, exactly
//! as the app would feed their frames live: every prompt is captured within
//! ±2 frames of the expression's true peak, despite the one-frame spikes,
//! failed first attempts, held co-activations (conjugate gaze) and tracking
//! losses the simulator injects; the same holds for the weights alone, read
//! back from a Live Link Face CSV.

use likeness::capture::guided_capture::{GuidedCaptureConfig, Step};
use likeness::capture::replay::{ReplayReport, replay_frames, replay_session};
use likeness_tests::live_link::live_link_csv;

fn committed(seed: u64) -> likeness::Session {
    likeness_tests::committed::read(seed).expect("committed session")
}

fn prompt_errors(report: &ReplayReport) -> Vec<i64> {
    report.prompt_errors().collect()
}

#[test]
fn every_prompt_of_every_committed_session_is_captured_within_two_frames() {
    for seed in 1..=4 {
        let session = committed(seed);
        let tests = session.tests.len();
        let report = replay_session(session, GuidedCaptureConfig::default()).unwrap();
        assert!(report.finished, "seed {seed}: did not finish");
        assert_eq!(report.skipped(), 0, "seed {seed}: {:?}", report.steps);
        assert_eq!(report.steps.len(), 1 + 52 + tests);
        let errors = prompt_errors(&report);
        assert_eq!(errors.len(), 52, "seed {seed}: truth for every prompt");
        assert!(
            report.max_frame_error() <= Some(2),
            "seed {seed}: capture − true peak {errors:?}"
        );
        // Every prompt's captured frame carries its mesh (the committed
        // files keep meshes within 0.4 s of each true capture).
        for step in &report.steps[1..=52] {
            assert!(step.has_mesh, "seed {seed}: {} without mesh", step.name);
        }
        // The test expressions are found too (no target in the issue; the
        // measured worst is 2 frames).
        assert!(
            report.max_test_frame_error() <= Some(3),
            "seed {seed}: tests {:?}",
            report.steps[53..]
                .iter()
                .map(|s| s.frame_error())
                .collect::<Vec<_>>()
        );
    }
}

#[test]
fn a_replay_is_deterministic() {
    let a = replay_session(committed(2), GuidedCaptureConfig::default()).unwrap();
    let b = replay_session(committed(2), GuidedCaptureConfig::default()).unwrap();
    assert_eq!(a, b);
}

#[test]
fn a_live_link_face_export_of_the_weights_replays_within_two_frames() {
    let session = committed(3);
    let truth = session.truth.clone().expect("simulated");
    let path = std::env::temp_dir().join(format!("likeness-replay-{}.csv", std::process::id()));
    std::fs::write(&path, live_link_csv(&session.frames)).unwrap();
    let frames = likeness::session::interchange::read_frames(&path).unwrap();
    std::fs::remove_file(&path).unwrap();
    assert_eq!(frames.len(), session.frames.len());
    let report = replay_frames(frames, GuidedCaptureConfig::default(), |step| match step {
        Step::Expression(shape) => truth.peak_frame(shape).map(u64::from),
        _ => None,
    })
    .unwrap();
    // No tests were asked for: neutral + 52 prompts, weights only.
    assert!(report.finished);
    assert_eq!(report.captured(), 53);
    assert!(report.steps.iter().all(|s| !s.has_mesh));
    let errors = prompt_errors(&report);
    assert!(report.max_frame_error() <= Some(2), "{errors:?}");
}
