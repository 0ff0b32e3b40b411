//! A whole simulated capture session, as the app would record it.
//!
//! A subject (from [`crate::subject`]) performs the [`Timeline`] drawn by
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

use crate::face_basis::FaceBasis;
use crate::performance::{NEUTRAL_SCAN_AT, perform_session};
use crate::subject::Subject;
use crate::template::to_f32;
use crate::timeline::{PromptTrack, Timeline, frame_at};
use crate::tracker::{Tracker, high_rest_offsets};
use glam::Vec3;
use likeness::{
    BLENDSHAPE_COUNT, Blendshape, CapturedExpression, DeviceInfo, Frame, GroundTruth, Session,
    SessionParts, TestExpression, TruePeak, Weights,
};

/// Version of the simulation model, recorded in every session it makes; bump
/// it whenever a change alters what a seed produces.
pub const SIMULATOR_VERSION: u32 = 3;

/// Frame rate of ARKit face tracking (Hz).
pub const FRAME_RATE: f64 = 60.0;

/// Seconds of geometry the committed sample sessions keep on either side of
/// each capture, test expression and the neutral scan (see
/// [`SimulationOptions::geometry_window`]).
pub const SAMPLE_GEOMETRY_WINDOW: f64 = 0.4;

/// Choices of the simulated app.
#[derive(Clone, Copy, Debug, Default)]
pub struct SimulationOptions {
    /// The face the person is simulated on: the simulator's own mask (the
    /// default, every committed session) or ARKit's own mesh
    /// ([`crate::face_basis`]).
    pub face: FaceBasis,
    /// `None`: store every frame's mesh. `Some(s)`: store meshes only within
    /// `s` seconds of a capture, a test expression or the neutral scan, as an
    /// app that keeps a ring buffer of recent frames would; the other frames
    /// keep their weights. Sessions with every mesh are 7–9 MB; the committed
    /// samples use [`SAMPLE_GEOMETRY_WINDOW`] to stay within the
    /// repository's budget.
    pub geometry_window: Option<f64>,
    /// Groups of shapes (a shape and its mirror) on which the person's
    /// relaxed face rests high, at 0.3–0.5, as ARKit reports some real
    /// faces (a brow that rests low reads as browDown); 0, the default, for
    /// none. See [`crate::tracker::high_rest_offsets`].
    pub high_rest_groups: usize,
    /// `None`: the subject's own session. `Some(p)`: the same person (face,
    /// and the tracker's distortion of it) on another sitting: the
    /// performance (attempts, test expressions) drawn from `p` and the
    /// tracker's noise drawn afresh. A second sitting's test expressions
    /// are independent evidence of how a person's fitted shapes generalize
    /// (`examples/lambda_study.rs`).
    pub performance: Option<u64>,
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
    let mask = options.face.mask();
    let subject = Subject::on(options.face, seed);
    let timeline = perform_session(options.performance.unwrap_or(seed), FRAME_RATE);
    let mut tracker = Tracker::new(seed, &mask.uv, FRAME_RATE)
        .with_rest_offsets(high_rest_offsets(seed, options.high_rest_groups));
    if let Some(performance) = options.performance {
        tracker = tracker.with_noise_seed(performance);
    }
    let Recording {
        mut frames,
        true_faces,
    } = track_every_frame(&subject, &timeline, tracker, progress);
    let (captures, true_captures) = choose_captures(&timeline, &frames, &true_faces);
    let tests = record_tests(&timeline, &frames);
    let neutral_frame = timeline.neutral_frame;
    let neutral = frames[neutral_frame].vertices.clone().unwrap_or_default();
    if let Some(window) = options.geometry_window {
        let centres: Vec<usize> = captures
            .iter()
            .filter_map(|c| c.frame.map(|f| f as usize))
            .chain(timeline.tests.iter().map(|t| t.frame))
            .chain(std::iter::once(neutral_frame))
            .collect();
        keep_geometry_near(&mut frames, &centres, window);
    }
    debug_assert_eq!(neutral_frame, frame_at(NEUTRAL_SCAN_AT, FRAME_RATE));
    let truth = ground_truth(seed, &subject, &timeline, true_captures, &true_faces);
    let parts = SessionParts {
        device: simulated_device(seed),
        frame_rate: FRAME_RATE as f32,
        topology: mask.topology.clone(),
        template: options.face.template(),
        neutral,
        frames,
        captures,
        tests,
        truth: Some(truth),
    };
    // Every mesh comes from the mask's own topology and every value from
    // finite arithmetic: a failure here is a bug in the simulator, not bad
    // input, and the physics tests exercise every seed they draw.
    Session::new(parts).expect("the simulator makes valid sessions")
}

/// What the phone recorded, frame by frame, with the noise-free faces the
/// ground truth needs.
struct Recording {
    /// The frames as the app stores them.
    frames: Vec<Frame>,
    /// The noise-free face of each frame that is the neutral scan, a test
    /// expression or part of a prompt's counted attempt; `None` elsewhere.
    true_faces: Vec<Option<Vec<Vec3>>>,
}

/// Tracks every frame: the subject's face at the frame's true activations,
/// as the tracker reports it, with the timeline's spikes and tracking
/// losses, calling `progress(done, total)` as it goes.
fn track_every_frame(
    subject: &Subject,
    timeline: &Timeline,
    mut tracker: Tracker,
    progress: &mut dyn FnMut(usize, usize),
) -> Recording {
    let total = timeline.activations.len();
    let mut frames: Vec<Frame> = Vec::with_capacity(total);
    let mut true_faces = Vec::new();
    let keep: Vec<usize> = std::iter::once(timeline.neutral_frame)
        .chain(timeline.tests.iter().map(|t| t.frame))
        .collect();
    for (f, a) in timeline.activations.iter().enumerate() {
        let face = subject.model.evaluate(a);
        let (mut weights, vertices) = tracker.observe(a, &face);
        if let Some((shape, value)) = spike_at(timeline, f) {
            weights.set(shape, value);
        }
        let lost = timeline.tracking_lost.iter().any(|r| r.contains(&f));
        frames.push(recorded_frame(f, weights, vertices, lost, frames.last()));
        let needed = keep.contains(&f) || timeline.prompts.iter().any(|p| p.attempt.contains(&f));
        true_faces.push(needed.then(|| to_f32(&face)));
        if f % 256 == 0 || f + 1 == total {
            progress(f + 1, total);
        }
    }
    Recording { frames, true_faces }
}

/// The one-frame tracker spike at frame `f`, if a prompt has one there: the
/// prompted shape and the value the tracker reports for it.
fn spike_at(timeline: &Timeline, f: usize) -> Option<(Blendshape, f32)> {
    timeline.prompts.iter().find_map(|p| match p.spike {
        Some((frame, value)) if frame == f => Some((p.shape, value)),
        _ => None,
    })
}

/// The frame the app stores at index `f` from the tracker's `weights` and
/// `vertices`; while the face is `lost`, ARKit keeps its `last` estimate.
fn recorded_frame(
    f: usize,
    weights: Weights,
    vertices: Vec<Vec3>,
    lost: bool,
    last: Option<&Frame>,
) -> Frame {
    let timestamp = f as f64 / FRAME_RATE;
    match (lost, last) {
        (true, Some(last)) => Frame {
            timestamp,
            tracked: false,
            ..last.clone()
        },
        _ => Frame {
            timestamp,
            weights,
            tracked: !lost,
            vertices: Some(vertices),
        },
    }
}

/// Chooses the capture frames, one per prompt that has a tracked frame in
/// its counted attempt (see [`capture_frame`]); returns the captures and the
/// noise-free faces at them.
fn choose_captures(
    timeline: &Timeline,
    frames: &[Frame],
    true_faces: &[Option<Vec<Vec3>>],
) -> (Vec<CapturedExpression>, Vec<Vec<Vec3>>) {
    let mut captures = Vec::new();
    let mut true_captures = Vec::new();
    for p in &timeline.prompts {
        let Some(f) = capture_frame(p, frames) else {
            continue;
        };
        captures.push(CapturedExpression {
            prompt: p.shape,
            frame: Some(f as u32),
            weights: frames[f].weights,
            vertices: frames[f].vertices.clone().unwrap_or_default(),
        });
        true_captures.push(true_faces[f].clone().unwrap_or_default());
    }
    (captures, true_captures)
}

/// The app's capture of prompt `p`: the tracked frame of its counted attempt
/// where the *tracked* weight of the requested shape is largest, ignoring the
/// injected spike.
fn capture_frame(p: &PromptTrack, frames: &[Frame]) -> Option<usize> {
    let j = p.shape.index();
    p.attempt
        .clone()
        .filter(|f| frames[*f].tracked && p.spike.is_none_or(|(sf, _)| sf != *f))
        .max_by(|a, b| frames[*a].weights.0[j].total_cmp(&frames[*b].weights.0[j]))
}

/// Records each test expression at its true peak frame.
fn record_tests(timeline: &Timeline, frames: &[Frame]) -> Vec<TestExpression> {
    timeline
        .tests
        .iter()
        .map(|t| TestExpression {
            id: t.id.clone(),
            frame: Some(t.frame as u32),
            weights: frames[t.frame].weights,
            vertices: frames[t.frame].vertices.clone().unwrap_or_default(),
        })
        .collect()
}

/// Drops the mesh of every frame more than `window` seconds from all of the
/// `centres` (frame indices); the frames keep their weights.
fn keep_geometry_near(frames: &mut [Frame], centres: &[usize], window: f64) {
    let reach = frame_at(window, FRAME_RATE);
    for (f, frame) in frames.iter_mut().enumerate() {
        if !centres.iter().any(|c| c.abs_diff(f) <= reach) {
            frame.vertices = None;
        }
    }
}

/// Assembles the ground truth: the true peak frames, the noise-free neutral,
/// the subject's linear blendshapes, the noise-free faces at the captures
/// (`true_captures`) and tests, and the tests' true activations.
fn ground_truth(
    seed: u64,
    subject: &Subject,
    timeline: &Timeline,
    true_captures: Vec<Vec<Vec3>>,
    true_faces: &[Option<Vec<Vec3>>],
) -> GroundTruth {
    GroundTruth {
        seed,
        peak_frames: timeline
            .prompts
            .iter()
            .map(|p| TruePeak {
                prompt: p.shape,
                frame: p.true_peak as u32,
            })
            .collect(),
        neutral: to_f32(&subject.model.neutral),
        blendshapes: Blendshape::ALL.map(|s| to_f32(&subject.model.shape(s))),
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
    }
}

/// The device a simulated session names: the simulator, the subject's seed
/// and the model version.
fn simulated_device(seed: u64) -> DeviceInfo {
    DeviceInfo {
        model: "likeness-sim".into(),
        system_version: format!("simulated subject {seed}"),
        app_version: format!("likeness-sim model {SIMULATOR_VERSION}"),
        recorded_at: String::new(),
    }
}
