//! A tiny but complete session (a 3 × 3 grid face with every part a
//! session can have) and a tiny avatar, so that seeds are a few kilobytes
//! and still reach every field of every reader.

use glam::Vec3;
use likeness::avatar::{Avatar, AvatarMesh, AvatarPart};
use likeness::session::{
    CapturedExpression, DeviceInfo, Frame, GroundTruth, SessionParts, Template, TestExpression,
    TruePeak,
};
use likeness::{BLENDSHAPE_COUNT, Blendshape, Session, Topology, Weights};

/// Side of the grid.
const SIDE: usize = 3;

/// The grid's triangles, two per square.
pub fn triangles() -> Vec<[u32; 3]> {
    let mut triangles = Vec::new();
    for row in 0..SIDE - 1 {
        for col in 0..SIDE - 1 {
            let a = (row * SIDE + col) as u32;
            let (b, c, d) = (a + 1, a + SIDE as u32, a + SIDE as u32 + 1);
            triangles.push([a, b, d]);
            triangles.push([a, d, c]);
        }
    }
    triangles
}

/// The grid at rest, 1 cm apart, in metres.
pub fn neutral() -> Vec<Vec3> {
    (0..SIDE * SIDE)
        .map(|k| Vec3::new((k % SIDE) as f32 * 0.01, (k / SIDE) as f32 * 0.01, 0.0))
        .collect()
}

/// `neutral` with vertex `shape % 9` moved by 1–5 mm (each shape its own).
pub fn shape_mesh(shape: usize) -> Vec<Vec3> {
    let mut mesh = neutral();
    let offset = 0.001 * (1 + shape % 5) as f32;
    mesh[shape % (SIDE * SIDE)] += Vec3::new(offset * 0.5, -offset * 0.25, offset);
    mesh
}

/// `mesh` with every vertex moved by `d` in z.
fn lifted(mesh: &[Vec3], d: f32) -> Vec<Vec3> {
    mesh.iter().map(|p| *p + Vec3::new(0.0, 0.0, d)).collect()
}

/// Weights with `shape` at `value`, the rest zero.
fn one(shape: Blendshape, value: f32) -> Weights {
    let mut w = Weights::ZERO;
    w.set(shape, value);
    w
}

/// Three prompts captured in the tiny session.
const CAPTURED: [Blendshape; 3] = [
    Blendshape::EyeBlinkLeft,
    Blendshape::JawOpen,
    Blendshape::MouthSmileLeft,
];

/// The tiny session: 30 frames at 60 fps (a mesh on every third), three
/// captures, one test expression and, with `truth`, the ground truth.
pub fn session(truth: bool) -> Session {
    let template = Template::new(neutral(), (0..BLENDSHAPE_COUNT).map(shape_mesh).collect())
        .expect("52 shapes");
    let frames = (0..30)
        .map(|k| Frame {
            timestamp: 12.5 + k as f64 / 60.0,
            weights: one(CAPTURED[k / 10], (k % 10) as f32 / 9.0),
            tracked: k != 17,
            vertices: (k % 3 == 0).then(|| lifted(&neutral(), k as f32 * 1e-4)),
        })
        .collect();
    let captures = CAPTURED
        .iter()
        .enumerate()
        .map(|(j, &prompt)| CapturedExpression {
            prompt,
            frame: Some(9 + 10 * j as u32),
            weights: one(prompt, 1.0),
            vertices: shape_mesh(prompt.index()),
        })
        .collect();
    let tests = vec![TestExpression {
        id: "smile-squint".into(),
        frame: Some(29),
        weights: one(Blendshape::CheekSquintLeft, 0.6),
        vertices: lifted(&shape_mesh(3), 0.002),
    }];
    let truth = truth.then(|| GroundTruth {
        seed: 7,
        peak_frames: CAPTURED
            .iter()
            .enumerate()
            .map(|(j, &prompt)| TruePeak {
                prompt,
                frame: 9 + 10 * j as u32,
            })
            .collect(),
        neutral: neutral(),
        blendshapes: std::array::from_fn(|j| lifted(&shape_mesh(j), 1e-4)),
        captures: CAPTURED.iter().map(|s| shape_mesh(s.index())).collect(),
        tests: vec![shape_mesh(3)],
        test_activations: vec![one(Blendshape::CheekSquintLeft, 0.5)],
    });
    Session::new(SessionParts {
        device: DeviceInfo {
            model: "iPhone13,3".into(),
            system_version: "17.4".into(),
            app_version: "likeness-fuzz seeds".into(),
            recorded_at: "2026-01-02T03:04:05Z".into(),
        },
        frame_rate: 60.0,
        topology: Topology::new(SIDE * SIDE, triangles()).expect("grid"),
        template,
        neutral: lifted(&neutral(), 0.001),
        frames,
        captures,
        tests,
        truth,
    })
    .expect("a valid tiny session")
}

/// A tiny avatar: the grid as a head with a morph target per ARKit name
/// (the template's deltas), and a second mesh without targets.
pub fn avatar() -> Avatar {
    let deltas = (0..BLENDSHAPE_COUNT)
        .map(|j| {
            shape_mesh(j)
                .iter()
                .zip(neutral())
                .map(|(s, n)| *s - n)
                .collect()
        })
        .collect();
    let head = AvatarPart {
        name: "head".into(),
        mesh: 0,
        primitive: 0,
        positions: neutral(),
        triangles: triangles(),
        targets: deltas,
    };
    let eye = AvatarPart {
        name: "eye".into(),
        mesh: 1,
        primitive: 0,
        positions: lifted(&neutral(), 0.005),
        triangles: triangles(),
        targets: Vec::new(),
    };
    Avatar::new(
        vec![
            AvatarMesh {
                name: Some("head".into()),
                target_names: Blendshape::ALL.iter().map(|s| s.name().into()).collect(),
            },
            AvatarMesh {
                name: Some("eyeLeft".into()),
                target_names: Vec::new(),
            },
        ],
        vec![head, eye],
    )
    .unwrap()
}
