//! The full-body avatar's body and clothes: plain generated tubes (rings
//! of an ellipse swept along a path) for torso, arms, legs and feet of a
//! 1.75 m adult standing in an A-pose, and the skeleton that skins them.
//!
//! Lengths are rounded adult means (Winter, *Biomechanics and Motor
//! Control of Human Movement*: segment lengths as fractions of height H =
//! 1.75 m: upper arm 0.186 H ≈ 0.30 m (here 0.30), forearm 0.146 H ≈
//! 0.26 m, hand 0.108 H ≈ 0.18 m, thigh 0.245 H ≈ 0.43 m, shank 0.246 H ≈
//! 0.42 m). Girths are plausible, not measured. The head (the default
//! avatar, its eyes at 1.63 m, its shoulders' cut at 1.41 m) sits on the
//! torso's top, which reaches into the shoulders' dome.

use crate::glb_edit::Joint;
use glam::{DVec3, Quat, Vec3};
use std::f64::consts::TAU;

/// Where the default avatar's head goes (m): its eye centres (y = 28 mm)
/// at 1.628 m, a 1.75 m adult's eye height.
pub const HEAD_OFFSET: Vec3 = Vec3::new(0.0, 1.60, 0.0);
/// The arms' angle from the vertical in the bind pose (A-pose, degrees):
/// many avatar exporters (Ready Player Me, VRoid) bind at 30–45°.
pub const ARM_ANGLE_DEGREES: f64 = 35.0;
/// Vertices around a torso or leg ring; arms take 3/4 of it.
pub const SEGMENTS: usize = 24;
/// Ring spacing along a path (m): 2 cm keeps the body near 4,000 vertices.
pub const RING_SPACING: f64 = 0.02;

/// One cross-section of a tube: its centre and the ellipse's half axes
/// (the first across the body, the second front to back).
#[derive(Clone, Copy, Debug)]
pub struct Section {
    /// Centre (m).
    pub centre: DVec3,
    /// Half axes (m).
    pub radii: [f64; 2],
}

fn s(x: f64, y: f64, z: f64, a: f64, b: f64) -> Section {
    Section {
        centre: DVec3::new(x, y, z),
        radii: [a, b],
    }
}

/// A mesh: positions and triangles.
pub type Mesh = (Vec<DVec3>, Vec<[u32; 3]>);

/// A tube through `sections` (refined to rings about [`RING_SPACING`]
/// apart, centres and radii interpolated linearly) with `segments` vertices
/// per ring and a fan closing each end; `grow` is added to every radius.
/// Rings lie across the path; the first half axis lies along
/// `across × tangent`, `across` the body's front (+z) unless the path runs
/// along it.
pub fn tube(sections: &[Section], segments: usize, grow: f64) -> Mesh {
    let mut rings: Vec<Section> = Vec::new();
    for w in sections.windows(2) {
        let n = ((w[1].centre - w[0].centre).length() / RING_SPACING)
            .ceil()
            .max(1.0) as usize;
        for k in 0..n {
            let t = k as f64 / n as f64;
            rings.push(Section {
                centre: w[0].centre.lerp(w[1].centre, t),
                radii: [0, 1].map(|i| w[0].radii[i] + t * (w[1].radii[i] - w[0].radii[i])),
            });
        }
    }
    rings.push(*sections.last().expect("a tube has sections"));
    let mut p = Vec::new();
    let n = rings.len();
    for (k, r) in rings.iter().enumerate() {
        let t = (rings[(k + 1).min(n - 1)].centre - rings[k.saturating_sub(1)].centre).normalize();
        let across = if t.z.abs() > 0.9 { DVec3::Y } else { DVec3::Z };
        let u = across.cross(t).normalize();
        let v = t.cross(u);
        for j in 0..segments {
            let a = TAU * j as f64 / segments as f64;
            p.push(
                r.centre + u * (r.radii[0] + grow) * a.cos() + v * (r.radii[1] + grow) * a.sin(),
            );
        }
    }
    let seg = segments as u32;
    let at = |k: usize, j: u32| (k as u32) * seg + j % seg;
    let mut t = Vec::new();
    for k in 0..n - 1 {
        for j in 0..seg {
            let (a, b, c, d) = (at(k, j), at(k, j + 1), at(k + 1, j), at(k + 1, j + 1));
            t.push([a, c, d]);
            t.push([a, d, b]);
        }
    }
    let (first, last) = (p.len() as u32, p.len() as u32 + 1);
    // The caps' centres stand `grow` beyond the end rings, so a grown
    // tube's caps cover the plain one's.
    let ends = [
        rings[0].centre - rings[1].centre,
        rings[n - 1].centre - rings[n - 2].centre,
    ];
    p.push(rings[0].centre + ends[0].normalize() * grow);
    p.push(rings[n - 1].centre + ends[1].normalize() * grow);
    for j in 0..seg {
        t.push([first, at(0, j + 1), at(0, j)]);
        t.push([last, at(n - 1, j), at(n - 1, j + 1)]);
    }
    (p, t)
}

/// Concatenates meshes.
pub fn join(meshes: &[Mesh]) -> Mesh {
    let mut out: Mesh = (Vec::new(), Vec::new());
    for (p, t) in meshes {
        let o = out.0.len() as u32;
        out.0.extend(p);
        out.1.extend(t.iter().map(|tri| tri.map(|i| i + o)));
    }
    out
}

/// Unit vector down an arm of `side` (+1 the person's left, +x).
fn arm_direction(side: f64) -> DVec3 {
    let a = ARM_ANGLE_DEGREES.to_radians();
    DVec3::new(side * a.sin(), -a.cos(), 0.0)
}

/// Shoulder joint of `side` (m): 0.38 m apart, an adult's biacromial
/// breadth (≈ 0.22 H), just under the head's shoulder dome.
fn shoulder(side: f64) -> DVec3 {
    DVec3::new(side * 0.19, 1.37, -0.01)
}

/// Hip joint of `side` (m): 0.18 m apart (the hip joints' spacing, about
/// half the pelvis' 0.3 m width), at 0.53 H.
fn hip(side: f64) -> DVec3 {
    DVec3::new(side * 0.09, 0.92, 0.0)
}

/// The torso: from inside the shoulders' dome (y = 1.43 m, above its cut
/// at 1.41 m) down to the crotch; chest 33 × 20 cm, waist 28 × 18 cm, hips
/// 34 × 20 cm (girths near 0.9, 0.75 and 0.95 m).
pub fn torso() -> Vec<Section> {
    vec![
        s(0.0, 1.43, -0.01, 0.15, 0.085),
        s(0.0, 1.30, 0.0, 0.165, 0.10),
        s(0.0, 1.12, 0.0, 0.14, 0.09),
        s(0.0, 0.98, 0.0, 0.17, 0.10),
        s(0.0, 0.86, 0.0, 0.15, 0.09),
    ]
}

/// An arm of `side`: shoulder, elbow, wrist, fingertips.
pub fn arm(side: f64) -> Vec<Section> {
    let (o, d) = (shoulder(side), arm_direction(side));
    let at = |l: f64, a: f64, b: f64| Section {
        centre: o + d * l,
        radii: [a, b],
    };
    vec![
        at(0.0, 0.05, 0.05),
        at(0.30, 0.04, 0.04),
        at(0.56, 0.03, 0.025),
        at(0.64, 0.045, 0.018),
        at(0.74, 0.03, 0.012),
    ]
}

/// A leg of `side`: hip, knee, ankle.
pub fn leg(side: f64) -> Vec<Section> {
    let h = hip(side);
    vec![
        s(h.x, h.y, 0.0, 0.075, 0.075),
        s(h.x + side * 0.01, 0.50, 0.0, 0.05, 0.05),
        s(h.x + side * 0.01, 0.08, -0.01, 0.035, 0.035),
    ]
}

/// A foot of `side`: heel to toes.
pub fn foot(side: f64) -> Vec<Section> {
    let x = hip(side).x + side * 0.01;
    vec![
        s(x, 0.045, -0.05, 0.04, 0.035),
        s(x, 0.035, 0.16, 0.045, 0.025),
    ]
}

/// Both sides of a limb.
fn both(limb: fn(f64) -> Vec<Section>, segments: usize, grow: f64) -> Vec<Mesh> {
    [1.0, -1.0]
        .map(|side| tube(&limb(side), segments, grow))
        .to_vec()
}

/// The body: torso, arms, legs, feet.
pub fn body() -> Mesh {
    let mut parts = vec![tube(&torso(), SEGMENTS, 0.0)];
    parts.extend(both(arm, SEGMENTS * 3 / 4, 0.0));
    parts.extend(both(leg, SEGMENTS, 0.0));
    parts.extend(both(foot, SEGMENTS * 3 / 4, 0.0));
    join(&parts)
}

/// How far clothes stand off the body (m).
pub const CLOTH_GAP: f64 = 0.012;

/// The outfit's primitives: a shirt (torso to the hips, sleeves to the
/// elbows), trousers (hips to ankles) and shoes.
pub fn outfit() -> [Mesh; 3] {
    let sleeve = |side: f64| arm(side)[..2].to_vec();
    let shirt = join(&[
        tube(&torso()[..4], SEGMENTS, CLOTH_GAP),
        tube(&sleeve(1.0), SEGMENTS * 3 / 4, CLOTH_GAP),
        tube(&sleeve(-1.0), SEGMENTS * 3 / 4, CLOTH_GAP),
    ]);
    let mut trousers = vec![tube(&torso()[3..], SEGMENTS, 1.5 * CLOTH_GAP)];
    trousers.extend(both(leg, SEGMENTS, CLOTH_GAP));
    let shoes = join(&both(foot, SEGMENTS * 3 / 4, 0.01));
    [shirt, join(&trousers), shoes]
}

/// Joint indices the head's parts are skinned to.
pub const HEAD_JOINT: u16 = 4;
/// Left and right eye joints.
pub const EYE_JOINTS: [u16; 2] = [5, 6];

/// The skeleton, in the bind pose (parents first): hips, spine, chest,
/// neck, head, eyes, then each arm (upper, lower, hand; turned into the
/// A-pose, so their rotations are not the identity) and each leg (upper,
/// lower, foot).
pub fn skeleton(eye_centres: [Vec3; 2]) -> Vec<Joint> {
    let head = (DVec3::new(0.0, 0.0, -0.05)).as_vec3() + HEAD_OFFSET;
    let neck = Vec3::new(0.0, 1.45, -0.03);
    let mut j = vec![
        Joint::at("Hips", None, Vec3::new(0.0, 0.95, 0.0)),
        Joint::at("Spine", Some(0), Vec3::new(0.0, 0.15, 0.0)),
        Joint::at("Chest", Some(1), Vec3::new(0.0, 0.18, 0.0)),
        Joint::at("Neck", Some(2), neck - Vec3::new(0.0, 1.28, 0.0)),
        Joint::at("Head", Some(3), head - neck),
        Joint::at("LeftEye", Some(4), eye_centres[0] + HEAD_OFFSET - head),
        Joint::at("RightEye", Some(4), eye_centres[1] + HEAD_OFFSET - head),
    ];
    let names = [
        ["LeftUpperArm", "LeftLowerArm", "LeftHand"],
        ["RightUpperArm", "RightLowerArm", "RightHand"],
    ];
    for (k, side) in [1.0f64, -1.0].into_iter().enumerate() {
        let first = j.len();
        let turn = Quat::from_rotation_z((side * ARM_ANGLE_DEGREES).to_radians() as f32);
        let mut at = Joint::at(
            names[k][0],
            Some(2),
            shoulder(side).as_vec3() - Vec3::new(0.0, 1.28, 0.0),
        );
        at.rotation = turn;
        j.push(at);
        j.push(Joint::at(
            names[k][1],
            Some(first),
            Vec3::new(0.0, -0.30, 0.0),
        ));
        j.push(Joint::at(
            names[k][2],
            Some(first + 1),
            Vec3::new(0.0, -0.26, 0.0),
        ));
    }
    let legs = [
        ["LeftUpperLeg", "LeftLowerLeg", "LeftFoot"],
        ["RightUpperLeg", "RightLowerLeg", "RightFoot"],
    ];
    for (k, side) in [1.0f64, -1.0].into_iter().enumerate() {
        let first = j.len();
        let h = hip(side).as_vec3();
        j.push(Joint::at(
            legs[k][0],
            Some(0),
            h - Vec3::new(0.0, 0.95, 0.0),
        ));
        j.push(Joint::at(
            legs[k][1],
            Some(first),
            Vec3::new(side as f32 * 0.01, 0.50 - h.y, 0.0),
        ));
        j.push(Joint::at(
            legs[k][2],
            Some(first + 1),
            Vec3::new(0.0, -0.42, -0.01),
        ));
    }
    j
}

/// The bones as segments `(joint, from, to)` in the bind pose: each joint
/// to its child (hands, feet and the head to a point beyond them).
pub fn bones(joints: &[Joint]) -> Vec<(u16, Vec3, Vec3)> {
    let worlds = crate::glb_edit::joint_worlds(joints);
    let at = |k: usize| worlds[k].transform_point3(Vec3::ZERO);
    let mut out = Vec::new();
    for k in 0..joints.len() {
        let children: Vec<usize> = (0..joints.len())
            .filter(|&c| joints[c].parent == Some(k))
            .collect();
        let name = joints[k].name;
        if name.ends_with("Eye") {
            continue;
        }
        let end = match children.iter().find(|&&c| !joints[c].name.ends_with("Eye")) {
            Some(&c) if !name.starts_with("Chest") => at(c),
            _ if name.ends_with("Hand") => worlds[k].transform_point3(Vec3::new(0.0, -0.18, 0.0)),
            _ if name.ends_with("Foot") => at(k) + Vec3::new(0.0, -0.01, 0.18),
            _ if name == "Chest" => at(3),
            _ => at(k) + Vec3::Y * 0.12,
        };
        out.push((k as u16, at(k), end));
    }
    out
}

/// The joint of the bone nearest `p` (rigid skinning).
pub fn nearest_joint(bones: &[(u16, Vec3, Vec3)], p: Vec3) -> u16 {
    let distance = |(_, a, b): &(u16, Vec3, Vec3)| {
        let ab = *b - *a;
        let t = ((p - *a).dot(ab) / ab.length_squared()).clamp(0.0, 1.0);
        p.distance(*a + ab * t)
    };
    bones
        .iter()
        .min_by(|x, y| distance(x).total_cmp(&distance(y)))
        .map_or(0, |b| b.0)
}
