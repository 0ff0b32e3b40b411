//! The state machine on synthetic streams: smooth expression bumps on
//! unfiltered weights (latency 0), 60 fps.

use super::*;
use crate::BLENDSHAPE_COUNT;

const RATE: f64 = 60.0;

fn config() -> GuidedCaptureConfig {
    let mut c = GuidedCaptureConfig::default();
    c.peak.latency_frames = 0.0;
    c.test_peak.latency_frames = 0.0;
    c
}

/// A stream under construction: weights per frame, meshes of 4 vertices.
#[derive(Default)]
struct Stream {
    weights: Vec<Weights>,
    untracked: Vec<usize>,
}

impl Stream {
    fn hold(&mut self, frames: usize) -> &mut Self {
        self.weights
            .extend(std::iter::repeat_n(Weights::default(), frames));
        self
    }

    /// A 60-frame bump of `shapes` peaking at `height` at its frame 30;
    /// returns the peak frame.
    fn bump(&mut self, shapes: &[Blendshape], height: f32) -> usize {
        let start = self.weights.len();
        for f in 0..60 {
            let x = (f as f32 - 30.0) / 10.0;
            let mut w = Weights::default();
            for s in shapes {
                w.set(*s, height * (-x * x).exp());
            }
            self.weights.push(w);
        }
        self.hold(30);
        start + 30
    }

    fn frames(&self) -> Vec<Frame> {
        self.weights
            .iter()
            .enumerate()
            .map(|(i, w)| Frame {
                timestamp: i as f64 / RATE,
                weights: *w,
                tracked: !self.untracked.contains(&i),
                vertices: Some(vec![glam::Vec3::splat(i as f32 * 1e-6); 4]),
            })
            .collect()
    }
}

/// Neutral second, then every prompt performed once; the peak frames.
fn whole_session(stream: &mut Stream) -> Vec<usize> {
    stream.hold(90);
    PROMPT_ORDER
        .iter()
        .map(|s| stream.bump(&[*s], 0.9))
        .collect()
}

fn run(capture: &mut GuidedCapture, frames: Vec<Frame>) -> Vec<CaptureEvent> {
    let mut events = capture.start();
    for f in frames {
        events.extend(capture.push(f).expect("valid frame"));
    }
    events
}

#[test]
fn a_whole_session_captures_every_prompt_at_its_peak_in_order() {
    let mut stream = Stream::default();
    let peaks = whole_session(&mut stream);
    let mut capture = GuidedCapture::new(config());
    let events = run(&mut capture, stream.frames());
    assert_eq!(events[0], CaptureEvent::Started(Step::Neutral));
    assert!(matches!(
        events[1],
        CaptureEvent::Captured {
            step: Step::Neutral,
            frame: 60,
            ..
        }
    ));
    for (i, shape) in PROMPT_ORDER.iter().enumerate() {
        assert_eq!(
            events[2 + 2 * i],
            CaptureEvent::Started(Step::Expression(*shape))
        );
        let CaptureEvent::Captured {
            step,
            frame,
            quality,
        } = events[3 + 2 * i]
        else {
            panic!("{:?}", events[3 + 2 * i]);
        };
        assert_eq!(step, Step::Expression(*shape));
        assert_eq!(frame, peaks[i] as u64, "{shape}");
        assert!(quality.is_clean(), "{shape}: {quality:?}");
    }
    assert_eq!(
        events.last(),
        Some(&CaptureEvent::Finished {
            captured: 53,
            skipped: 0
        })
    );
    let p = capture.progress();
    assert_eq!(
        (p.total, p.captured, p.skipped, p.current),
        (53, 53, 0, None)
    );
    assert_eq!(p.fraction(), 1.0);
    let c = capture
        .capture_of(Step::Expression(Blendshape::JawOpen))
        .unwrap();
    assert_eq!(c.weights.get(Blendshape::JawOpen), 0.9);
    assert_eq!(c.vertices.as_ref().map(Vec::len), Some(4));
}

#[test]
fn the_same_stream_gives_the_same_events() {
    let mut stream = Stream::default();
    whole_session(&mut stream);
    let a = run(&mut GuidedCapture::new(config()), stream.frames());
    let b = run(&mut GuidedCapture::new(config()), stream.frames());
    assert_eq!(a, b);
}

#[test]
fn a_prompt_not_performed_times_out_and_the_next_one_goes_on() {
    let mut stream = Stream::default();
    stream.hold(90);
    stream.hold(11 * 60); // the first prompt is never performed
    let peak = stream.bump(&[PROMPT_ORDER[1]], 0.9);
    let mut capture = GuidedCapture::new(config());
    let events = run(&mut capture, stream.frames());
    assert!(events.contains(&CaptureEvent::Skipped {
        step: Step::Expression(PROMPT_ORDER[0]),
        reason: SkipReason::TimedOut
    }));
    assert!(events.iter().any(|e| matches!(e,
        CaptureEvent::Captured { step: Step::Expression(s), frame, .. }
            if *s == PROMPT_ORDER[1] && *frame == peak as u64)));
    assert_eq!(capture.skipped(), &[Step::Expression(PROMPT_ORDER[0])]);
    assert!(SkipReason::TimedOut.description().starts_with("timed out"));
}

#[test]
fn skipping_moves_on_but_not_past_the_neutral_scan() {
    let mut capture = GuidedCapture::new(config());
    capture.start();
    assert_eq!(capture.skip(), Err(GuidedCaptureError::NeutralNotSkippable));
    let mut stream = Stream::default();
    stream.hold(90);
    run(&mut capture, stream.frames());
    let events = capture.skip().unwrap();
    assert_eq!(
        events,
        vec![
            CaptureEvent::Skipped {
                step: Step::Expression(PROMPT_ORDER[0]),
                reason: SkipReason::Requested
            },
            CaptureEvent::Started(Step::Expression(PROMPT_ORDER[1]))
        ]
    );
    assert_eq!(capture.progress().skipped, 1);
    // The neutral scan and one skipped prompt of 53 steps.
    assert!((capture.progress().fraction() - 2.0 / 53.0).abs() < 1e-12);
}

#[test]
fn a_retake_after_finishing_replaces_the_capture_and_finishes_again() {
    let mut stream = Stream::default();
    whole_session(&mut stream);
    let mut capture = GuidedCapture::new(config());
    run(&mut capture, stream.frames());
    let first = capture
        .capture_of(Step::Expression(Blendshape::JawOpen))
        .unwrap()
        .frame;
    let events = capture
        .retake(Step::Expression(Blendshape::JawOpen))
        .unwrap();
    assert_eq!(
        events,
        vec![CaptureEvent::Started(Step::Expression(Blendshape::JawOpen))]
    );
    let mut more = Stream::default();
    more.hold(20);
    let peak = more.bump(&[Blendshape::JawOpen], 0.8);
    let offset = stream.weights.len();
    let frames = more.frames().into_iter().map(|f| Frame {
        timestamp: f.timestamp + offset as f64 / RATE,
        ..f
    });
    let events = run(&mut capture, frames.collect());
    let second = capture
        .capture_of(Step::Expression(Blendshape::JawOpen))
        .unwrap();
    assert_ne!(second.frame, first);
    assert_eq!(second.frame, (offset + peak) as u64);
    assert!(matches!(
        events.last(),
        Some(CaptureEvent::Finished { captured: 53, .. })
    ));
}

#[test]
fn a_retake_mid_session_resumes_the_interrupted_prompt() {
    let mut capture = GuidedCapture::new(config());
    let mut stream = Stream::default();
    stream.hold(90);
    run(&mut capture, stream.frames());
    let events = capture.retake(Step::Neutral).unwrap();
    assert_eq!(events, vec![CaptureEvent::Started(Step::Neutral)]);
    let mut later = Stream::default();
    later.hold(90);
    let frames = later.frames().into_iter().map(|f| Frame {
        timestamp: f.timestamp + 2.0,
        ..f
    });
    let events = run(&mut capture, frames.collect());
    assert_eq!(
        events.get(1),
        Some(&CaptureEvent::Started(Step::Expression(PROMPT_ORDER[0])))
    );
    assert!(capture.retake(Step::Test(0)).is_err());
}

#[test]
fn quality_flags_weak_dominated_and_tracking_lost() {
    use Blendshape::*;
    let mut stream = Stream::default();
    stream.hold(90);
    stream.bump(&[PROMPT_ORDER[0]], 0.55); // weak
    let second = stream.bump(&[PROMPT_ORDER[1], MouthSmileLeft], 0.8);
    for w in &mut stream.weights[second - 30..second + 30] {
        // Another shape dominates the whole expression.
        w.set(MouthSmileLeft, 1.15 * w.get(MouthSmileLeft));
    }
    let third = stream.bump(&[PROMPT_ORDER[2]], 0.9);
    stream.untracked = vec![third - 8];
    let mut capture = GuidedCapture::new(config());
    run(&mut capture, stream.frames());
    let q = |i: usize| {
        capture
            .capture_of(Step::Expression(PROMPT_ORDER[i]))
            .unwrap()
            .quality
    };
    assert!(q(0).weak && q(0).dominated_by.is_none());
    assert_eq!(q(1).dominated_by, Some(MouthSmileLeft));
    assert!(q(2).tracking_lost && !q(2).weak);
}

#[test]
fn test_expressions_are_captured_after_the_prompts() {
    use Blendshape::*;
    let mut c = config();
    c.tests = vec![
        TestPrompt {
            id: "smile".into(),
            instruction: "Smile".into(),
        },
        TestPrompt {
            id: "surprise".into(),
            instruction: "Look surprised".into(),
        },
    ];
    let mut stream = Stream::default();
    whole_session(&mut stream);
    let smile = stream.bump(&[MouthSmileLeft, MouthSmileRight], 0.6);
    let surprise = stream.bump(&[BrowInnerUp, EyeWideLeft, EyeWideRight, JawOpen], 0.5);
    let mut capture = GuidedCapture::new(c);
    let events = run(&mut capture, stream.frames());
    assert_eq!(
        capture.capture_of(Step::Test(0)).unwrap().frame,
        smile as u64
    );
    assert_eq!(
        capture.capture_of(Step::Test(1)).unwrap().frame,
        surprise as u64
    );
    assert!(matches!(
        events.last(),
        Some(CaptureEvent::Finished { captured: 55, .. })
    ));
    assert_eq!(
        Step::Test(1).instruction(capture.config()),
        "Look surprised"
    );
}

#[test]
fn bad_frames_are_refused_and_change_nothing() {
    let mut capture = GuidedCapture::new(config());
    let frame = |t: f64, n: usize| Frame {
        timestamp: t,
        weights: Weights([0.0; BLENDSHAPE_COUNT]),
        tracked: true,
        vertices: Some(vec![glam::Vec3::ZERO; n]),
    };
    for i in 0..61 {
        capture.push(frame(i as f64 / RATE, 4)).unwrap();
    }
    assert!(capture.capture_of(Step::Neutral).is_some());
    let seen = capture.frames_seen();
    assert!(matches!(
        capture.push(frame(0.5, 4)),
        Err(GuidedCaptureError::TimeWentBack { frame: 61, .. })
    ));
    assert!(matches!(
        capture.push(frame(f64::NAN, 4)),
        Err(GuidedCaptureError::BadTimestamp { .. })
    ));
    assert_eq!(
        capture.push(frame(2.0, 5)),
        Err(GuidedCaptureError::VertexCount {
            frame: 61,
            expected: 4,
            found: 5
        })
    );
    assert_eq!(capture.frames_seen(), seen);
}

/// A still, tracked neutral frame at `t` with a 4-vertex mesh.
fn stream_frame(t: f64) -> Frame {
    Frame {
        timestamp: t,
        weights: Weights::ZERO,
        tracked: true,
        vertices: Some(vec![glam::Vec3::ZERO; 4]),
    }
}

#[test]
fn arbitrary_frames_and_commands_never_panic() {
    use rand::{Rng, SeedableRng};
    let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(5);
    let odd = [f32::NAN, f32::INFINITY, f32::NEG_INFINITY, -3.0, 1e30, 1.0];
    let mut config = config();
    config.tests = vec![TestPrompt {
        id: "t".into(),
        instruction: "Pull a face".into(),
    }];
    config.step_timeout = 2.0;
    let mut capture = GuidedCapture::new(config);
    let (mut t, mut shape, mut most) = (0.0, Blendshape::JawOpen, 0);
    for k in 0..20_000 {
        if k < 120 {
            // A calm start, so that the neutral scan is taken.
            t = k as f64 / RATE;
            capture.push(stream_frame(t)).unwrap();
            continue;
        }
        // Mostly forward in time, sometimes repeated or going back.
        t += match rng.random_range(0..50) {
            0 => -0.1,
            1 => 0.0,
            _ => 1.0 / RATE,
        };
        // Quiet noise, one shape rising and falling, now and then nonsense.
        if k % 60 == 0 {
            shape = match capture.progress().current {
                Some(Step::Expression(asked)) if rng.random_range(0..4) != 0 => asked,
                _ => Blendshape::ALL[rng.random_range(0..BLENDSHAPE_COUNT)],
            };
        }
        let mut weights = Weights(std::array::from_fn(|_| rng.random_range(0.0..0.02)));
        weights.set(shape, (k as f32 * 0.05).sin().abs());
        if rng.random_range(0..20) == 0 {
            weights.0[rng.random_range(0..BLENDSHAPE_COUNT)] = odd[rng.random_range(0..odd.len())];
        }
        let vertices = match rng.random_range(0..10) {
            0 => None,
            1 => Some(vec![glam::Vec3::NAN; rng.random_range(0..6)]),
            _ => Some(vec![glam::Vec3::splat(rng.random_range(-1.0..1.0)); 4]),
        };
        let frame = Frame {
            timestamp: if rng.random_range(0..500) == 0 {
                f64::NAN
            } else {
                t
            },
            weights,
            tracked: rng.random_range(0..8) != 0,
            vertices,
        };
        let _ = capture.push(frame);
        match rng.random_range(0..1000) {
            0 => {
                let _ = capture.skip();
            }
            1 => {
                let shape = Blendshape::ALL[rng.random_range(0..BLENDSHAPE_COUNT)];
                let _ = capture.retake(Step::Expression(shape));
            }
            2 => {
                let _ = capture.retake(Step::Test(rng.random_range(0..3)));
            }
            _ => {}
        }
        let progress = capture.progress();
        assert!(progress.captured <= progress.total);
        most = most.max(progress.captured);
        for step in [Step::Neutral, Step::Test(0), Step::Test(7)] {
            let _ = capture.capture_of(step);
        }
    }
    // The stream got the capture going, so the steps were exercised.
    assert!(most > 20, "only {most} captures");
}
