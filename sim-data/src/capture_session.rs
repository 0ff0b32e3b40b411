//! A whole simulated capture session, as the app would record it.
//!
//! A subject (from [`crate::subject`]) performs the timeline of
//! [`crate::performance`]; the tracker of [`crate::tracker`] reports every
//! frame at 60 fps. The app keeps:
//! - the neutral scan: the tracked mesh at [`NEUTRAL_SCAN_AT`];
//! - for each prompt, the frame of its counted attempt where the *tracked*
//!   weight of the requested shape is largest (an ideal peak detector that
//!   sees only what the phone sees, ignoring the injected one-frame spike);
//! - each test expression at its peak.
//!
//! The ground truth kept with it: the true peak frames, the noise-free faces
//! at the neutral, captures and tests, the true activations of the tests,
//! and the subject's own linear blendshapes.

use crate::face_mask::face_mask;
use crate::performance::{NEUTRAL_SCAN_AT, perform_session};
use crate::subject::Subject;
use crate::template::{generic_template, to_f32};
use crate::tracker::Tracker;
use likeness::{
    BLENDSHAPE_COUNT, Blendshape, CapturedExpression, DeviceInfo, Frame, GroundTruth, Session,
    TestExpression, Weights,
};

/// Version of the simulation model, recorded in every session it makes; bump
/// it whenever a change alters what a seed produces.
pub const SIMULATOR_VERSION: u32 = 1;

/// Frame rate of ARKit face tracking (Hz).
pub const FRAME_RATE: f64 = 60.0;

/// Seconds of geometry the committed sample sessions keep on either side of
/// each capture, test expression and the neutral scan (see
/// [`SimulationOptions::geometry_window`]).
pub const SAMPLE_GEOMETRY_WINDOW: f64 = 0.4;

/// Choices of the simulated app.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct SimulationOptions {
    /// `None`: store every frame's mesh. `Some(s)`: store meshes only within
    /// `s` seconds of a capture, a test expression or the neutral scan, as an
    /// app that keeps a ring buffer of recent frames would; the other frames
    /// keep their weights. Sessions with every mesh are 7–9 MB; the committed
    /// samples use [`SAMPLE_GEOMETRY_WINDOW`] to stay within the
    /// repository's budget.
    pub geometry_window: Option<f64>,
}

/// Simulates the full session of the subject drawn from `seed`, with every
/// frame's mesh.
pub fn simulate_session(seed: u64) -> Session {
    simulate_session_with(seed, SimulationOptions::default(), &mut |_, _| {})
}

/// As [`simulate_session`], with `options`, calling `progress(done, total)`
/// as frames are made.
pub fn simulate_session_with(
    seed: u64,
    options: SimulationOptions,
    progress: &mut dyn FnMut(usize, usize),
) -> Session {
    let mask = face_mask();
    let subject = Subject::from_seed(seed);
    let timeline = perform_session(seed, FRAME_RATE);
    let mut tracker = Tracker::new(seed, &mask.uv, FRAME_RATE);
    let total = timeline.activations.len();
    let mut frames: Vec<Frame> = Vec::with_capacity(total);
    let mut true_faces = Vec::new();
    let keep: Vec<usize> = std::iter::once(timeline.neutral_frame)
        .chain(timeline.tests.iter().map(|t| t.frame))
        .collect();
    for (f, a) in timeline.activations.iter().enumerate() {
        let face = subject.model.evaluate(a);
        let (mut weights, vertices) = tracker.observe(a, &face);
        let lost = timeline.tracking_lost.iter().any(|r| r.contains(&f));
        if let Some(p) = timeline
            .prompts
            .iter()
            .find(|p| p.spike.is_some_and(|(sf, _)| sf == f))
        {
            weights.set(p.shape, p.spike.map(|s| s.1).unwrap_or(0.0));
        }
        let frame = match (lost, frames.last()) {
            // ARKit keeps the last estimate while the face is not tracked.
            (true, Some(last)) => Frame {
                timestamp: f as f64 / FRAME_RATE,
                tracked: false,
                ..last.clone()
            },
            _ => Frame {
                timestamp: f as f64 / FRAME_RATE,
                weights,
                tracked: !lost,
                vertices: Some(vertices),
            },
        };
        frames.push(frame);
        true_faces.push(
            if keep.contains(&f) || timeline.prompts.iter().any(|p| p.attempt.contains(&f)) {
                Some(to_f32(&face))
            } else {
                None
            },
        );
        if f % 256 == 0 || f + 1 == total {
            progress(f + 1, total);
        }
    }
    let mut captures = Vec::new();
    let mut true_captures = Vec::new();
    for p in &timeline.prompts {
        let j = p.shape.index();
        let best = p
            .attempt
            .clone()
            .filter(|f| frames[*f].tracked && p.spike.is_none_or(|(sf, _)| sf != *f))
            .max_by(|a, b| frames[*a].weights.0[j].total_cmp(&frames[*b].weights.0[j]));
        let Some(f) = best else { continue };
        captures.push(CapturedExpression {
            prompt: p.shape,
            frame: Some(f as u32),
            weights: frames[f].weights,
            vertices: frames[f].vertices.clone().unwrap_or_default(),
        });
        true_captures.push(true_faces[f].clone().unwrap_or_default());
    }
    let tests: Vec<TestExpression> = timeline
        .tests
        .iter()
        .map(|t| TestExpression {
            id: t.id.clone(),
            frame: Some(t.frame as u32),
            weights: frames[t.frame].weights,
            vertices: frames[t.frame].vertices.clone().unwrap_or_default(),
        })
        .collect();
    let neutral_frame = timeline.neutral_frame;
    let neutral = frames[neutral_frame].vertices.clone().unwrap_or_default();
    if let Some(window) = options.geometry_window {
        let reach = (window * FRAME_RATE).round() as usize;
        let centres: Vec<usize> = captures
            .iter()
            .filter_map(|c| c.frame.map(|f| f as usize))
            .chain(timeline.tests.iter().map(|t| t.frame))
            .chain(std::iter::once(neutral_frame))
            .collect();
        for (f, frame) in frames.iter_mut().enumerate() {
            if !centres.iter().any(|c| c.abs_diff(f) <= reach) {
                frame.vertices = None;
            }
        }
    }
    debug_assert_eq!(
        neutral_frame,
        (NEUTRAL_SCAN_AT * FRAME_RATE).round() as usize
    );
    let truth = GroundTruth {
        seed,
        peak_frames: timeline
            .prompts
            .iter()
            .map(|p| (p.shape, p.true_peak as u32))
            .collect(),
        neutral: to_f32(&subject.model.neutral),
        blendshapes: Blendshape::ALL
            .iter()
            .map(|s| to_f32(&subject.model.shape(*s)))
            .collect(),
        captures: true_captures,
        tests: timeline
            .tests
            .iter()
            .map(|t| true_faces[t.frame].clone().unwrap_or_default())
            .collect(),
        test_activations: timeline
            .tests
            .iter()
            .map(|t| {
                Weights(std::array::from_fn::<f32, BLENDSHAPE_COUNT, _>(|j| {
                    timeline.activations[t.frame][j] as f32
                }))
            })
            .collect(),
    };
    Session {
        device: DeviceInfo {
            model: "likeness-sim".into(),
            system_version: format!("simulated subject {seed}"),
            app_version: format!("likeness-sim model {SIMULATOR_VERSION}"),
            recorded_at: String::new(),
        },
        frame_rate: FRAME_RATE as f32,
        topology: mask.topology.clone(),
        template: generic_template(),
        neutral,
        frames,
        captures,
        tests,
        truth: Some(truth),
    }
}
