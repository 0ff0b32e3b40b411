//! The recorder on synthetic streams over the test face grid: smooth
//! expression bumps, 60 fps, starting at an uptime of 100 s as ARKit's
//! timestamps do.

use super::*;
use crate::arkit::{Blendshape, Weights};
use crate::capture::guided_capture::GuidedCaptureError;
use crate::geometry::topology::GeometryError;
use crate::test_support::face_grid;

const RATE: f64 = 60.0;
const UPTIME: f64 = 100.0;

fn config() -> RecorderConfig {
    let mut c = RecorderConfig::default();
    c.guided.peak.latency_frames = 0.0;
    c
}

fn recorder() -> (Recorder, Vec<Vec3>) {
    let (topology, neutral, _) = face_grid();
    let template = Template {
        neutral: neutral.clone(),
        shapes: std::array::from_fn(|j| {
            neutral
                .iter()
                .map(|p| *p + Vec3::Y * 1e-4 * (j + 1) as f32)
                .collect()
        }),
    };
    let device = DeviceInfo {
        model: "test".into(),
        ..DeviceInfo::default()
    };
    let r = Recorder::new(topology, template, device, config()).unwrap();
    (r, neutral)
}

/// Weights per frame: a held neutral second, then one 60-frame bump per
/// prompt peaking at 0.9 at its frame 30, 30 quiet frames after each.
fn whole_session() -> (Vec<Weights>, Vec<usize>) {
    let mut weights = vec![Weights::ZERO; 90];
    let peaks = PROMPT_ORDER
        .iter()
        .map(|shape| {
            let start = weights.len();
            for f in 0..60 {
                let x = (f as f32 - 30.0) / 10.0;
                let mut w = Weights::ZERO;
                w.set(*shape, 0.9 * (-x * x).exp());
                weights.push(w);
            }
            weights.extend([Weights::ZERO; 30]);
            start + 30
        })
        .collect();
    (weights, peaks)
}

fn frame(i: usize, weights: Weights, mesh: Option<&[Vec3]>) -> Frame {
    Frame {
        timestamp: UPTIME + i as f64 / RATE,
        weights,
        tracked: true,
        vertices: mesh.map(|m| m.iter().map(|p| *p + Vec3::Z * 1e-7 * i as f32).collect()),
    }
}

fn record(r: &mut Recorder, weights: &[Weights], mesh: Option<&[Vec3]>) -> Vec<RecorderEvent> {
    let mut events = r.start();
    for (i, w) in weights.iter().enumerate() {
        events.extend(r.push(frame(i, *w, mesh)).expect("valid frame"));
    }
    events
}

#[test]
fn a_whole_session_becomes_a_session_with_every_capture_and_meshes_near_them() {
    let (mut r, neutral) = recorder();
    let (weights, peaks) = whole_session();
    let events = record(&mut r, &weights, Some(&neutral));
    assert_eq!(
        events.last(),
        Some(&RecorderEvent::Capture(CaptureEvent::Finished {
            captured: 53,
            skipped: 0
        }))
    );
    assert!(r.is_finished());
    let session = r.session().unwrap();
    assert_eq!(session.captures.len(), 52);
    for (c, (shape, peak)) in session.captures.iter().zip(PROMPT_ORDER.iter().zip(&peaks)) {
        assert_eq!((c.prompt, c.frame), (*shape, Some(*peak as u32)));
        assert_eq!(c.weights.get(*shape), 0.9);
    }
    assert_eq!(session.frames.len(), weights.len());
    assert_eq!(session.frames[0].timestamp, 0.0);
    assert!((session.frame_rate - 60.0).abs() < 1e-3);
    assert_eq!(session.device.model, "test");
    // Meshes within 0.4 s (24 frames) of a capture, none elsewhere.
    let neutral_frame = r.capture_of(Step::Neutral).unwrap().frame as usize;
    let centres: Vec<usize> = peaks.iter().copied().chain([neutral_frame]).collect();
    for (i, f) in session.frames.iter().enumerate() {
        let near = centres.iter().any(|c| c.abs_diff(i) <= 24);
        assert_eq!(f.vertices.is_some(), near, "frame {i}");
    }
    assert_eq!(session.neutral.len(), neutral.len());
}

#[test]
fn old_meshes_are_dropped_while_recording_unless_a_capture_needs_them() {
    let (mut r, neutral) = recorder();
    // Ten seconds of a neutral face: the neutral scan at frame 60, then a
    // prompt that is never performed.
    record(&mut r, &[Weights::ZERO; 600], Some(&neutral));
    let kept: Vec<usize> = (0..600)
        .filter(|&i| r.stream[i].vertices.is_some())
        .collect();
    // The neutral scan's window (frames 36–84) and the last 3 s (from
    // frame 419 or 420, as the timestamps round).
    let tail = kept.iter().position(|&i| i > 84).unwrap();
    assert_eq!(kept[..tail], (36..=84).collect::<Vec<_>>()[..]);
    assert!([419, 420].contains(&kept[tail]), "{}", kept[tail]);
    assert_eq!(kept.len() - tail, 600 - kept[tail]);
}

#[test]
fn bad_frames_are_refused_naming_the_field_and_record_nothing() {
    let (mut r, neutral) = recorder();
    r.push(frame(0, Weights::ZERO, Some(&neutral))).unwrap();
    let mut nan = Weights::ZERO;
    nan.set(Blendshape::JawOpen, f32::NAN);
    let e = r.push(frame(1, nan, None)).unwrap_err();
    assert!(matches!(
        &e,
        RecorderError::Frame(SessionError::BadWeight { what, shape: Blendshape::JawOpen, .. })
            if what == "frame 1"
    ));
    let short = &neutral[1..];
    let e = r.push(frame(1, Weights::ZERO, Some(short))).unwrap_err();
    assert!(matches!(
        e,
        RecorderError::Frame(SessionError::Geometry(GeometryError::VertexCount { .. }))
    ));
    let mut inf = neutral.clone();
    inf[3].x = f32::INFINITY;
    let e = r.push(frame(1, Weights::ZERO, Some(&inf))).unwrap_err();
    assert!(e.to_string().contains("frame 1"), "{e}");
    let mut back = frame(1, Weights::ZERO, None);
    back.timestamp = UPTIME - 1.0;
    assert!(matches!(
        r.push(back),
        Err(RecorderError::Capture(
            GuidedCaptureError::TimeWentBack { .. }
        ))
    ));
    assert_eq!(r.stream.len(), 1);
    assert_eq!(r.capture.frames_seen(), 1);
    // Ten minutes after the first frame is the last a session file holds.
    // (The face is not at rest, so no neutral scan is captured.)
    let mut open = Weights::ZERO;
    open.set(Blendshape::JawOpen, 0.8);
    let mut last = frame(1, open, None);
    last.timestamp = UPTIME + MAX_DURATION_SECONDS;
    r.push(last).unwrap();
    let mut past = frame(2, Weights::ZERO, None);
    past.timestamp = UPTIME + MAX_DURATION_SECONDS + 0.5;
    // The frame past it ends the capture instead: not recorded, the steps
    // left skipped, finished; later frames ignored, no retake.
    let events = r.push(past.clone()).unwrap();
    assert_eq!(
        events[0],
        RecorderEvent::LimitReached {
            frame: 2,
            seconds: MAX_DURATION_SECONDS + 0.5
        }
    );
    assert!(
        matches!(
            events.last(),
            Some(RecorderEvent::Capture(CaptureEvent::Finished {
                captured: 0,
                skipped: 53
            }))
        ),
        "{events:?}"
    );
    assert!(r.is_finished() && r.ended_at_limit());
    assert_eq!(r.stream.len(), 2);
    assert_eq!(r.push(past).unwrap(), Vec::new());
    assert_eq!(r.stream.len(), 2);
    assert_eq!(r.retake(1), Err(RecorderError::Ended));
    assert_eq!(r.session().unwrap_err(), RecorderError::NoNeutralScan);
}

#[test]
fn a_capture_at_its_length_limit_keeps_what_it_has() {
    let (mut r, neutral) = recorder();
    record(&mut r, &[Weights::ZERO; 90], Some(&neutral));
    assert_eq!(r.progress().captured, 1, "the neutral scan");
    // The person leaves the phone on the table past the limit.
    let mut late = frame(90, Weights::ZERO, Some(&neutral));
    late.timestamp = UPTIME + MAX_DURATION_SECONDS + 1.0;
    let events = r.push(late).unwrap();
    assert!(matches!(
        events[0],
        RecorderEvent::LimitReached { frame: 90, .. }
    ));
    let session = r.session().unwrap();
    assert_eq!(session.frames.len(), 90, "every frame before the limit");
    let p = r.progress();
    assert_eq!((p.captured, p.skipped, p.current), (1, 52, None));
}

#[test]
fn an_interruption_restarts_the_step_under_way() {
    let (mut r, neutral) = recorder();
    record(&mut r, &[Weights::ZERO; 90], Some(&neutral));
    let step = r.progress().current.unwrap();
    let events = r.interrupt();
    assert_eq!(
        events,
        vec![RecorderEvent::Capture(CaptureEvent::Started(step))],
        "the same step, asked for again"
    );
    assert_eq!(r.progress().current, Some(step));
}

#[test]
fn calls_in_the_wrong_order_are_errors() {
    let (mut r, neutral) = recorder();
    assert_eq!(r.skip(), Err(RecorderError::NotStarted));
    assert_eq!(r.retake(1), Err(RecorderError::NotStarted));
    assert!(matches!(
        r.session(),
        Err(RecorderError::NotFinished { done: 0, total: 53 })
    ));
    r.start();
    assert_eq!(
        r.skip(),
        Err(RecorderError::Capture(
            GuidedCaptureError::NeutralNotSkippable
        ))
    );
    assert_eq!(
        r.retake(53),
        Err(RecorderError::NoSuchStep {
            index: 53,
            total: 53
        })
    );
    record(&mut r, &[Weights::ZERO; 90], Some(&neutral));
    for _ in 0..52 {
        r.skip().unwrap();
    }
    assert!(r.is_finished());
    assert_eq!(r.skip(), Err(RecorderError::NothingToSkip));
    // Nothing but the neutral scan: a valid session without captures.
    assert!(r.session().unwrap().captures.is_empty());
}

#[test]
fn losing_and_finding_the_face_is_reported_once_each() {
    let (mut r, _) = recorder();
    let mut kinds = Vec::new();
    for (i, tracked) in [true, false, false, true, true].into_iter().enumerate() {
        let mut f = frame(i, Weights::ZERO, None);
        f.tracked = tracked;
        kinds.extend(
            r.push(f)
                .unwrap()
                .into_iter()
                .filter(|e| !matches!(e, RecorderEvent::Capture(_))),
        );
    }
    assert_eq!(
        kinds,
        [RecorderEvent::TrackingLost, RecorderEvent::TrackingResumed]
    );
}

#[test]
fn a_template_that_does_not_fit_names_the_shape() {
    let (topology, neutral, _) = face_grid();
    let mut shapes: [Vec<Vec3>; 52] = std::array::from_fn(|_| neutral.clone());
    shapes[Blendshape::MouthClose.index()].pop();
    let template = Template { neutral, shapes };
    let e = Recorder::new(topology, template, DeviceInfo::default(), config()).unwrap_err();
    assert!(e.to_string().contains("mouthClose"), "{e}");
}

#[test]
fn previews_are_the_template_at_each_step() {
    let (r, neutral) = recorder();
    assert_eq!(r.preview(0).unwrap(), &neutral[..]);
    let first = PROMPT_ORDER[0];
    assert_eq!(r.preview(1).unwrap(), &r.template.shapes[first.index()][..]);
    let info = r.step_info(r.step_at(1).unwrap());
    assert_eq!(
        (info.index, info.total, info.name.as_str()),
        (1, 53, first.name())
    );
    assert!(matches!(
        r.preview(60),
        Err(RecorderError::NoSuchStep { .. })
    ));
}

#[test]
fn a_stream_without_meshes_has_no_neutral_face() {
    let (mut r, _) = recorder();
    record(&mut r, &[Weights::ZERO; 90], None);
    for _ in 0..52 {
        r.skip().unwrap();
    }
    assert_eq!(r.session(), Err(RecorderError::NeutralWithoutMesh(60)));
}

#[test]
fn the_frame_rate_is_the_median_interval() {
    let frames: Vec<Frame> = [0.0, 0.02, 0.03, 0.05, 0.06, 0.08]
        .iter()
        .map(|t| Frame {
            timestamp: *t,
            weights: Weights::ZERO,
            tracked: true,
            vertices: None,
        })
        .collect();
    // Intervals 0.02, 0.01, 0.02, 0.01, 0.02: median 0.02.
    assert!((frame_rate(&frames) - 50.0).abs() < 1e-3);
    assert_eq!(frame_rate(&frames[..1]), NOMINAL_FRAME_RATE);
}

/// A stored stream with meshes only from frame `from`: the neutral scan
/// (taken at about frame 60) has none of its own. Every prompt skipped.
fn neutral_without_its_mesh(from: usize, weights: &[Weights]) -> (Recorder, Vec<Vec3>) {
    let (mut r, neutral) = recorder();
    r.start();
    for (i, w) in weights.iter().enumerate() {
        let mesh = (i >= from).then_some(neutral.as_slice());
        r.push(frame(i, *w, mesh)).unwrap();
    }
    while r.progress().current.is_some() {
        r.skip().unwrap();
    }
    (r, neutral)
}

#[test]
fn a_neutral_scan_without_a_mesh_takes_the_nearest_still_one() {
    let still = [Weights::ZERO; 90];
    let (r, neutral) = neutral_without_its_mesh(70, &still);
    let scan = r.capture_of(Step::Neutral).unwrap();
    assert!(scan.vertices.is_none() && scan.frame < 70);
    // Frame 70's mesh (each frame's mesh is offset by 1e-7 m per frame).
    let session = r.session().unwrap();
    let z = session.neutral[0].z - neutral[0].z;
    assert!((z - 70e-7).abs() < 1e-9, "{z}");

    // The face moved between the scan and the nearest mesh: none is taken.
    let mut moved = still;
    for w in &mut moved[65..] {
        w.set(Blendshape::JawOpen, 0.2);
    }
    let (r, _) = neutral_without_its_mesh(70, &moved);
    assert!(matches!(
        r.session(),
        Err(RecorderError::NeutralWithoutMesh(_))
    ));
}
