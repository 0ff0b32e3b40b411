//! A synthetic capture session for the benchmark: 2 minutes at 60 fps
//! (7,200 frames), every frame with a 1,220-vertex mesh, moving smoothly.
//!
//! The face is a 35 × 35 grid patch (the first 1,220 vertices) bulging
//! towards the camera. The 52 template shapes are smooth Gaussian bumps of
//! 2–12 mm. The stream prompts the 52 expressions one after another: the
//! prompted weight rises and falls over 2.3 s while every weight also wanders
//! smoothly by a few percent; the mesh is the neutral scan plus the weighted
//! shapes plus temporally smooth noise of 0.2 mm RMS per coordinate (two
//! sinusoids of 0.2–1.5 Hz with random phases per coordinate). Captures
//! are the prompts' peak frames; ground truth is filled in too.

use glam::Vec3;
use likeness::{
    BLENDSHAPE_COUNT, Blendshape, CapturedExpression, DeviceInfo, Frame, GroundTruth, Session,
    SessionParts, Template, TestExpression, Topology, TruePeak, Weights,
};
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;
use std::f64::consts::TAU;

/// Vertices per mesh (ARKit's face mesh has 1,220).
pub const VERTICES: usize = 1220;
/// Frames in the stream: 2 minutes at 60 fps.
pub const FRAMES: usize = 7200;
const FPS: f64 = 60.0;
const GRID: usize = 35;
const NOISE_RMS: f64 = 0.2e-3;

fn grid_topology() -> Topology {
    let mut triangles = Vec::new();
    for r in 0..GRID - 1 {
        for c in 0..GRID - 1 {
            let a = r * GRID + c;
            if a + GRID + 1 < VERTICES {
                let (a, g) = (a as u32, GRID as u32);
                triangles.push([a, a + 1, a + g]);
                triangles.push([a + 1, a + g + 1, a + g]);
            }
        }
    }
    Topology::new(VERTICES, triangles).expect("grid topology is valid")
}

fn bump(rng: &mut ChaCha8Rng, base: &[[f64; 3]], amplitude: f64) -> Vec<[f64; 3]> {
    let centre = base[rng.random_range(0..base.len())];
    let radius: f64 = rng.random_range(0.015..0.04);
    let mut dir = [0.0f64; 3];
    for d in &mut dir {
        *d = rng.random_range(-1.0..1.0);
    }
    let norm = (dir[0] * dir[0] + dir[1] * dir[1] + dir[2] * dir[2])
        .sqrt()
        .max(1e-9);
    base.iter()
        .map(|p| {
            let d2: f64 = (0..3).map(|k| (p[k] - centre[k]).powi(2)).sum();
            let g = amplitude * (-d2 / (2.0 * radius * radius)).exp() / norm;
            [g * dir[0], g * dir[1], g * dir[2]]
        })
        .collect()
}

fn to_mesh(points: &[[f64; 3]]) -> Vec<Vec3> {
    points
        .iter()
        .map(|p| Vec3::new(p[0] as f32, p[1] as f32, p[2] as f32))
        .collect()
}

fn add(a: &[[f64; 3]], b: &[[f64; 3]], s: f64) -> Vec<[f64; 3]> {
    a.iter()
        .zip(b)
        .map(|(p, q)| [p[0] + s * q[0], p[1] + s * q[1], p[2] + s * q[2]])
        .collect()
}

/// The synthetic session, the same every call.
pub fn session() -> Session {
    let mut rng = ChaCha8Rng::seed_from_u64(2024);
    let base: Vec<[f64; 3]> = (0..VERTICES)
        .map(|i| {
            let x = ((i % GRID) as f64 / (GRID - 1) as f64 - 0.5) * 0.15;
            let y = ((i / GRID) as f64 / (GRID - 1) as f64 - 0.5) * 0.2;
            let z = 0.05 * (1.0 - 0.5 * (x / 0.075).powi(2) - 0.5 * (y / 0.1).powi(2));
            [x, y, z]
        })
        .collect();
    let deltas: Vec<Vec<[f64; 3]>> = (0..BLENDSHAPE_COUNT)
        .map(|_| {
            let amplitude = rng.random_range(0.002..0.012);
            bump(&mut rng, &base, amplitude)
        })
        .collect();
    let identity = bump(&mut rng, &base, 0.004);
    let neutral = add(&base, &identity, 1.0);
    let wander: Vec<(f64, f64)> = (0..BLENDSHAPE_COUNT)
        .map(|_| (rng.random_range(0.05..0.5), rng.random_range(0.0..TAU)))
        .collect();
    let noise: Vec<[(f64, f64); 2]> = (0..3 * VERTICES)
        .map(|_| {
            let mut wave = || (TAU * rng.random_range(0.2..1.5), rng.random_range(0.0..TAU));
            [wave(), wave()]
        })
        .collect();
    let prompt_len = FRAMES as f64 / FPS / BLENDSHAPE_COUNT as f64;
    let weights_at = |t: f64| {
        let mut w = [0.0f64; BLENDSHAPE_COUNT];
        for (j, (f, phase)) in wander.iter().enumerate() {
            w[j] = 0.03 * (1.0 + (TAU * f * t + phase).sin());
        }
        let prompt = ((t / prompt_len) as usize).min(BLENDSHAPE_COUNT - 1);
        let s = (std::f64::consts::PI * (t / prompt_len).fract()).sin();
        w[prompt] = (w[prompt] + s * s).min(1.0);
        w
    };
    let mesh_at = |t: f64, w: &[f64; BLENDSHAPE_COUNT], with_noise: bool| {
        let mut m = neutral.clone();
        for (delta, &wj) in deltas.iter().zip(w) {
            for (p, d) in m.iter_mut().zip(delta) {
                for k in 0..3 {
                    p[k] += wj * d[k];
                }
            }
        }
        if with_noise {
            for (i, p) in m.iter_mut().enumerate() {
                for (k, x) in p.iter_mut().enumerate() {
                    let [(f1, p1), (f2, p2)] = noise[3 * i + k];
                    *x += NOISE_RMS * ((f1 * t + p1).sin() + (f2 * t + p2).sin());
                }
            }
        }
        m
    };
    let as_weights = |w: &[f64; BLENDSHAPE_COUNT]| Weights(w.map(|x| x as f32));

    let frames: Vec<Frame> = (0..FRAMES)
        .map(|k| {
            let t = k as f64 / FPS;
            let w = weights_at(t);
            Frame {
                timestamp: t,
                weights: as_weights(&w),
                tracked: true,
                vertices: Some(to_mesh(&mesh_at(t, &w, true))),
            }
        })
        .collect();
    let peaks: Vec<usize> = (0..BLENDSHAPE_COUNT)
        .map(|p| (((p as f64 + 0.5) * prompt_len * FPS) as usize).min(FRAMES - 1))
        .collect();
    let captures: Vec<CapturedExpression> = Blendshape::ALL
        .iter()
        .zip(&peaks)
        .map(|(&prompt, &k)| CapturedExpression {
            prompt,
            frame: Some(k as u32),
            weights: frames[k].weights,
            vertices: frames[k].vertices.clone().unwrap_or_default(),
        })
        .collect();
    let tests: Vec<TestExpression> = (0..5)
        .map(|k| {
            let frame = 700 + 1300 * k;
            TestExpression {
                id: format!("test-{k}"),
                frame: Some(frame as u32),
                weights: frames[frame].weights,
                vertices: frames[frame].vertices.clone().unwrap_or_default(),
            }
        })
        .collect();
    let truth = GroundTruth {
        seed: 2024,
        peak_frames: Blendshape::ALL
            .iter()
            .zip(&peaks)
            .map(|(&prompt, &k)| TruePeak {
                prompt,
                frame: k as u32,
            })
            .collect(),
        neutral: to_mesh(&neutral),
        blendshapes: std::array::from_fn(|j| to_mesh(&add(&neutral, &deltas[j], 1.0))),
        captures: peaks
            .iter()
            .map(|&k| to_mesh(&mesh_at(k as f64 / FPS, &weights_at(k as f64 / FPS), false)))
            .collect(),
        tests: tests
            .iter()
            .filter_map(|t| t.frame)
            .map(|k| to_mesh(&mesh_at(k as f64 / FPS, &weights_at(k as f64 / FPS), false)))
            .collect(),
        test_activations: tests.iter().map(|t| t.weights).collect(),
    };
    let parts = SessionParts {
        device: DeviceInfo {
            model: "likeness-bench".into(),
            system_version: "synthetic".into(),
            app_version: env!("CARGO_PKG_VERSION").into(),
            recorded_at: String::new(),
        },
        frame_rate: FPS as f32,
        topology: grid_topology(),
        template: Template {
            neutral: to_mesh(&base),
            shapes: std::array::from_fn(|j| to_mesh(&add(&base, &deltas[j], 1.0))),
        },
        neutral: to_mesh(&neutral),
        frames,
        captures,
        tests,
        truth: Some(truth),
    };
    Session::new(parts).expect("the synthetic session is consistent")
}

/// Bytes of f32 and f64 data the session holds in memory (positions,
/// weights, timestamps): the unit of the benchmark's throughput.
pub fn data_bytes(s: &Session) -> u64 {
    let mesh = 12 * s.topology.vertex_count() as u64;
    let weights = 4 * BLENDSHAPE_COUNT as u64;
    let stream: u64 = s
        .frames
        .iter()
        .map(|f| 8 + weights + if f.vertices.is_some() { mesh } else { 0 })
        .sum();
    let expressions = (s.captures.len() + s.tests.len()) as u64 * (mesh + weights);
    let template = (1 + s.template.shapes.len() as u64) * mesh;
    let truth = s.truth.as_ref().map_or(0, |t| {
        let meshes = 1 + t.blendshapes.len() + t.captures.len() + t.tests.len();
        meshes as u64 * mesh + t.test_activations.len() as u64 * weights
    });
    stream + expressions + template + mesh + truth
}
