//! The `capture_ffi` target: the FFI's [`CaptureSession`] driven by calls
//! read from the fuzzer's bytes, in any order, as an app (or a broken one)
//! might make them.
//!
//! The input is a list of operations, each an opcode byte followed by the
//! bytes of its arguments (read from the front, so a seed is the plain
//! concatenation, see [`Op`]). Most frames are well formed, performing the
//! prompt under way, so that the state machine gets far (captures,
//! retakes, the finished session); some are hostile: time going back,
//! NaN and infinities, weights and meshes of the wrong size.
//!
//! What must hold: no panic, no error other than a typed [`LikenessError`]
//! that is not `Internal` (which means a panic was caught), progress within
//! its bounds, and a session that `finish` returns can be saved and loaded.

use crate::check_message;
use arbitrary::Unstructured;
use likeness_ffi::{CaptureSession, FaceTemplate, LikenessError, SessionHandle, arkit_names};
use std::sync::{Arc, OnceLock};

/// The committed session whose template the capture runs against.
pub const TEMPLATE_SESSION: &str = concat!(
    env!("CARGO_MANIFEST_DIR"),
    "/../../sim-data/sessions/subject-1.likeness"
);

/// Most operations run from one input (a bound on time per input).
const MAX_OPS: usize = 256;

/// Most frames one input may push (25 s at 60 fps: the neutral scan and
/// a dozen gestures; skips take the capture to its end).
const MAX_FRAMES: usize = 1_500;

/// Triangles of the committed template the capture keeps: the first this
/// many (and their 49 vertices). Every coordinate of the 53 template meshes
/// is checked by `CaptureSession::new`, and of every frame by `push_frame`:
/// with the whole 1,220-vertex face, most of the time would go to those
/// loops instead of the calls' order, on which the state machine depends
/// (not on the vertex count).
pub const TEMPLATE_TRIANGLES: usize = 64;

/// The template once, with its deltas flattened for making frames.
pub struct Face {
    /// The template as the app passes it.
    pub template: FaceTemplate,
    /// Each shape minus the neutral, xyz flattened, in `arkit_names()` order.
    pub deltas: Vec<Vec<f32>>,
    /// ARKit's names in the order of every weight array.
    pub names: Vec<String>,
}

/// The template of [`TEMPLATE_SESSION`], read once per process.
pub fn face() -> &'static Face {
    static FACE: OnceLock<Face> = OnceLock::new();
    FACE.get_or_init(|| {
        let handle = SessionHandle::load(TEMPLATE_SESSION.into()).expect("committed session");
        let template = patch(
            &handle.template().expect("its template"),
            TEMPLATE_TRIANGLES,
        );
        eprintln!(
            "capture_ffi: the template's first {TEMPLATE_TRIANGLES} triangles, {} vertices",
            template.neutral.len() / 3
        );
        let deltas = template
            .shapes
            .iter()
            .map(|s| {
                s.iter()
                    .zip(&template.neutral)
                    .map(|(a, b)| a - b)
                    .collect()
            })
            .collect();
        Face {
            template,
            deltas,
            names: arkit_names(),
        }
    })
}

/// The operations, by opcode (the byte modulo their number).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[repr(u8)]
pub enum Op {
    /// `CaptureSession::new`; argument: a byte choosing the template
    /// (mostly the good one, else a broken variant).
    New = 0,
    /// `start`.
    Start,
    /// One frame; arguments: time step, weights kind, mesh kind, flags.
    Frame,
    /// A gesture: argument: frames (8–71) performing the prompt under way.
    Gesture,
    /// `skip`.
    Skip,
    /// `retake`; argument: a u16 step index (sometimes far past the end).
    Retake,
    /// `progress`, `current_prompt`, `is_finished`.
    Query,
    /// `prompt_preview`; argument: a byte step index.
    Preview,
    /// `captures`.
    Captures,
    /// `finish`, keeping the handle.
    Finish,
    /// `skip` until finished (or refused).
    SkipAll,
    /// The handle's reads; argument: a frame index.
    Handle,
    /// The handle saved and loaded again (once an input).
    SaveLoad,
    /// Untracked frames; argument: how many (1–32).
    Untracked,
    /// A pause; argument: seconds (0–255), then one good frame.
    Pause,
}

impl Op {
    const ALL: [Op; 15] = [
        Op::New,
        Op::Start,
        Op::Frame,
        Op::Gesture,
        Op::Skip,
        Op::Retake,
        Op::Query,
        Op::Preview,
        Op::Captures,
        Op::Finish,
        Op::SkipAll,
        Op::Handle,
        Op::SaveLoad,
        Op::Untracked,
        Op::Pause,
    ];

    /// The operation of opcode `byte`.
    pub fn of(byte: u8) -> Op {
        Op::ALL[byte as usize % Op::ALL.len()]
    }
}

/// The state of one run: the capture, its clock and the handle `finish`
/// returned.
struct Run<'a> {
    face: &'a Face,
    capture: Option<Arc<CaptureSession>>,
    handle: Option<Arc<SessionHandle>>,
    clock: f64,
    frames: usize,
    saved: bool,
}

/// Runs the operations in `data`.
pub fn run(data: &[u8]) {
    let mut u = Unstructured::new(data);
    let face = face();
    let mut run = Run {
        face,
        capture: CaptureSession::new(face.template.clone(), "iPhone13,3".into()).ok(),
        handle: None,
        clock: 100.0,
        frames: 0,
        saved: false,
    };
    // `Unstructured` gives zeros once the input is used up: stop there.
    for _ in 0..MAX_OPS {
        if u.is_empty() || run.frames > MAX_FRAMES {
            break;
        }
        run.op(Op::of(byte(&mut u)), &mut u);
    }
    if std::env::var_os("LIKENESS_FUZZ_TRACE").is_some() {
        let progress = run.capture.as_ref().map(|c| c.progress());
        let finished = run.handle.is_some();
        eprintln!("capture_ffi: {progress:?}, finished into a session: {finished}");
    }
}

/// A call's result: an error must be typed, and not a caught panic.
fn checked<T>(result: Result<T, LikenessError>) -> Option<T> {
    match result {
        Ok(value) => Some(value),
        Err(e) => {
            assert!(
                !matches!(e, LikenessError::Internal { .. }),
                "internal error: {e}"
            );
            check_message(&e);
            if std::env::var_os("LIKENESS_FUZZ_TRACE").is_some() {
                eprintln!("capture_ffi: {e}");
            }
            None
        }
    }
}

/// A byte from the input, 0 once it is used up.
fn byte(u: &mut Unstructured) -> u8 {
    u.arbitrary().unwrap_or(0)
}

impl Run<'_> {
    /// Runs one operation.
    fn op(&mut self, op: Op, u: &mut Unstructured) {
        match op {
            Op::New => {
                let template = broken_template(&self.face.template, byte(u));
                self.capture = checked(CaptureSession::new(template, "iPhone13,3".into()));
            }
            Op::Start => self.with(|c| c.start().map(drop)),
            Op::Frame => self.hostile_frame(u),
            Op::Gesture => {
                let n = 8 + byte(u) as usize / 4;
                let packed = n.is_multiple_of(2);
                self.gesture(n, packed);
            }
            Op::Skip => self.with(|c| c.skip().map(drop)),
            Op::Retake => {
                let index = u16::from_le_bytes([byte(u), byte(u)]);
                let index = if index > 0xff00 {
                    u32::MAX - u32::from(index & 0xff)
                } else {
                    u32::from(index % 80)
                };
                self.with(|c| c.retake(index).map(drop));
            }
            Op::Query => self.query(),
            Op::Preview => {
                let index = u32::from(byte(u));
                self.with(|c| c.prompt_preview(index).map(drop));
            }
            Op::Captures => self.with(|c| c.captures().map(drop)),
            Op::Finish => {
                if let Some(c) = &self.capture
                    && let Some(handle) = checked(c.finish())
                {
                    self.handle = Some(handle);
                }
            }
            Op::SkipAll => {
                for _ in 0..60 {
                    match &self.capture {
                        Some(c) if checked(c.is_finished()) == Some(false) => {
                            if checked(c.skip()).is_none() {
                                break;
                            }
                        }
                        _ => break,
                    }
                }
            }
            Op::Handle => self.read_handle(u32::from(byte(u)) * 37),
            Op::SaveLoad if !self.saved => {
                self.saved = true;
                self.save_load();
            }
            Op::SaveLoad => {}
            Op::Untracked => {
                let n = 1 + byte(u) as usize % 32;
                for _ in 0..n {
                    self.clock += 1.0 / 60.0;
                    self.push(self.clock, Weights::Neutral, Mesh::Good(0.0), false, false);
                }
            }
            Op::Pause => {
                self.clock += f64::from(byte(u));
                self.push(self.clock, Weights::Neutral, Mesh::Good(0.0), true, true);
            }
        }
    }

    /// Calls `f` on the capture, if there is one.
    fn with(&self, f: impl FnOnce(&CaptureSession) -> Result<(), LikenessError>) {
        if let Some(c) = &self.capture {
            checked(f(c));
        }
    }

    /// Progress, prompt and finished flag agree and stay within bounds.
    fn query(&self) {
        let Some(c) = &self.capture else { return };
        let Some(p) = checked(c.progress()) else {
            return;
        };
        assert!(
            (0.0..=1.0).contains(&p.fraction),
            "progress fraction {}",
            p.fraction
        );
        assert!(p.captured + p.skipped <= p.total, "progress {p:?}");
        if let Some(Some(prompt)) = checked(c.current_prompt()) {
            assert!(prompt.index < prompt.total, "prompt {prompt:?}");
            let finished = checked(c.is_finished());
            assert_ne!(finished, Some(true), "a prompt under way once finished");
        }
    }

    /// Reads everything the handle offers.
    fn read_handle(&self, index: u32) {
        let Some(h) = &self.handle else { return };
        checked(h.quality_summary()).expect("a session's summary");
        let template = checked(h.template()).expect("a session's template");
        assert_eq!(
            template.neutral.len(),
            self.face.template.neutral.len(),
            "the session's template"
        );
        let count = h.recorded_frame_count();
        checked(h.recorded_frame(index));
        if count > 0 {
            checked(h.recorded_frame(count - 1)).expect("the last frame");
        }
    }

    /// The finished session is saved and loads back the same.
    fn save_load(&self) {
        let Some(h) = &self.handle else { return };
        let path = crate::scratch().join("capture.likeness");
        let path = path.to_string_lossy().into_owned();
        // Saving may be refused (a capture past a session file's limits,
        // e.g. longer than ten minutes, finishes but is not written).
        if checked(h.save(path.clone())).is_some() {
            let loaded = checked(SessionHandle::load(path)).expect("a saved capture can be loaded");
            assert_eq!(loaded.recorded_frame_count(), h.recorded_frame_count());
        }
    }

    /// `n` frames of the prompt under way: the neutral face held still, or
    /// the prompted weight rising to 0.95 and falling back.
    fn gesture(&mut self, n: usize, packed: bool) {
        let Some(c) = &self.capture else { return };
        // Before the start and once finished, the neutral face.
        let shape = checked(c.current_prompt()).flatten().and_then(|p| {
            let found = self.face.names.iter().position(|name| *name == p.name);
            found.filter(|_| !p.is_neutral)
        });
        for k in 0..n {
            self.clock += 1.0 / 60.0;
            let w = match shape {
                Some(_) => 0.95 * (std::f32::consts::PI * k as f32 / (n - 1) as f32).sin(),
                None => 0.0,
            };
            let weights = shape.map_or(Weights::Neutral, |s| Weights::One(s, w));
            self.push(self.clock, weights, Mesh::Good(w), true, packed);
        }
    }

    /// One frame whose every part the input chooses.
    fn hostile_frame(&mut self, u: &mut Unstructured) {
        let (step, weights, mesh, flags) = (byte(u), byte(u), byte(u), byte(u));
        let timestamp = match step {
            0 => f64::NAN,
            1 => f64::INFINITY,
            2 => f64::NEG_INFINITY,
            3 => -1e300,
            4 => self.clock - 10.0,
            5 => self.clock,
            s => self.clock + f64::from(s as i8) / 60.0,
        };
        if timestamp.is_finite() && timestamp > self.clock {
            self.clock = timestamp;
        }
        let shape = weights as usize % 52;
        let weights = match weights / 52 {
            0 => Weights::One(shape, 0.9),
            1 => Weights::Bad(shape, [f32::NAN, f32::INFINITY, -3.0, 7.5][shape % 4]),
            2 => Weights::Len(shape * 2),
            _ => Weights::Neutral,
        };
        let mesh = match mesh % 8 {
            0 => Mesh::None,
            1 => Mesh::Len(mesh as usize * 3),
            2 => Mesh::Bad(mesh as usize, f32::NAN),
            3 => Mesh::Bad(mesh as usize, 1e30),
            4 => Mesh::Bytes(mesh as usize * 5),
            _ => Mesh::Good(0.9),
        };
        self.push(timestamp, weights, mesh, flags & 1 == 0, flags & 2 == 0);
    }

    /// Pushes one frame made from its parts.
    fn push(&mut self, timestamp: f64, weights: Weights, mesh: Mesh, tracked: bool, packed: bool) {
        let Some(c) = &self.capture else { return };
        self.frames += 1;
        let w = weights.values();
        let shape = match weights {
            Weights::One(s, _) => Some(s),
            _ => None,
        };
        let result = match (mesh.values(self.face, shape), packed) {
            (Vertices::Floats(v), false) => c.push_frame(timestamp, w, v, tracked),
            (Vertices::Floats(v), true) => {
                let bytes = v.iter().flat_map(|x| x.to_le_bytes()).collect();
                c.push_frame_packed(timestamp, w, bytes, tracked)
            }
            (Vertices::Bytes(b), _) => c.push_frame_packed(timestamp, w, b, tracked),
        };
        checked(result);
    }
}

/// The weights of a frame.
#[derive(Clone, Copy, Debug)]
enum Weights {
    /// All zero.
    Neutral,
    /// One shape at a value, the rest zero.
    One(usize, f32),
    /// One shape at a value that is no weight.
    Bad(usize, f32),
    /// Zeros, this many.
    Len(usize),
}

impl Weights {
    /// The 52 (or other) values.
    fn values(self) -> Vec<f32> {
        let mut w = vec![0.0; 52];
        match self {
            Weights::Neutral => {}
            Weights::One(s, v) | Weights::Bad(s, v) => w[s % 52] = v,
            Weights::Len(n) => w.resize(n, 0.0),
        }
        w
    }
}

/// The mesh of a frame.
#[derive(Clone, Copy, Debug)]
enum Mesh {
    /// No mesh.
    None,
    /// The template with the frame's shape at this weight.
    Good(f32),
    /// Floats, this many.
    Len(usize),
    /// The template with this coordinate (modulo the count) replaced.
    Bad(usize, f32),
    /// Packed bytes, this many (not a whole number of vertices, mostly).
    Bytes(usize),
}

/// A mesh as floats or packed bytes.
enum Vertices {
    Floats(Vec<f32>),
    Bytes(Vec<u8>),
}

impl Mesh {
    /// The vertices, for a frame weighting `shape`.
    fn values(self, face: &Face, shape: Option<usize>) -> Vertices {
        let neutral = &face.template.neutral;
        let posed = |w: f32| -> Vec<f32> {
            match shape.and_then(|s| face.deltas.get(s)) {
                Some(d) => neutral.iter().zip(d).map(|(n, d)| n + w * d).collect(),
                None => neutral.clone(),
            }
        };
        match self {
            Mesh::None => Vertices::Floats(Vec::new()),
            Mesh::Good(w) => Vertices::Floats(posed(w)),
            Mesh::Len(n) => Vertices::Floats(vec![0.01; n]),
            Mesh::Bad(k, x) => {
                let mut v = posed(0.0);
                let len = v.len();
                v[k % len] = x;
                Vertices::Floats(v)
            }
            Mesh::Bytes(n) => Vertices::Bytes(vec![0x3c; n]),
        }
    }
}

/// The good template, or for some `choice`s one broken in one way.
fn broken_template(good: &FaceTemplate, choice: u8) -> FaceTemplate {
    let mut t = good.clone();
    match choice {
        0..=199 => {}
        200..=209 => {
            t.shapes.truncate(choice as usize - 200);
        }
        210..=219 => t.shapes.push(t.neutral.clone()),
        220..=229 => t.neutral[choice as usize - 220] = f32::NAN,
        230..=239 => {
            t.triangles.pop();
        }
        240..=244 => t.triangles[1] = u32::MAX,
        245..=249 => t.triangles[4] = t.triangles[3],
        250 => t.neutral.clear(),
        251 => t.triangles.clear(),
        252 => t.shapes[7].truncate(30),
        253 => t.neutral.push(0.0),
        _ => {
            t.neutral.truncate(9);
            t.triangles = vec![0, 1, 2];
            for s in &mut t.shapes {
                s.truncate(9);
            }
        }
    }
    t
}

/// The part of `template` made of its first `triangles` triangles: their
/// vertices, renumbered in order of first use.
pub fn patch(template: &FaceTemplate, triangles: usize) -> FaceTemplate {
    let mut order: Vec<u32> = Vec::new();
    let mut new_index = std::collections::HashMap::new();
    let kept: Vec<u32> = template.triangles[..3 * triangles]
        .iter()
        .map(|&v| {
            *new_index.entry(v).or_insert_with(|| {
                order.push(v);
                order.len() as u32 - 1
            })
        })
        .collect();
    let pick = |mesh: &[f32]| -> Vec<f32> {
        order
            .iter()
            .flat_map(|&v| mesh[3 * v as usize..3 * v as usize + 3].iter().copied())
            .collect()
    };
    FaceTemplate {
        triangles: kept,
        neutral: pick(&template.neutral),
        shapes: template.shapes.iter().map(|s| pick(s)).collect(),
    }
}
