//! `lined-sockets`: lids that fold into the eye sockets, as in
//! ICT-FaceKit and most scanned or sculpted heads: the skin runs on past
//! each lid margin into a lining that cups the eyeball, so the eye
//! openings are no holes in the mesh (no boundary loops), and nothing in
//! the topology says where a lid ends.
//!
//! The default avatar with its socket lining (a bowl of
//! [`crate::default_avatar::eyes::SOCKET_RADIUS`] behind each eye, opening
//! 62° from the visual axis) merged into the skin's primitive, and each eye
//! opening's rim stitched to its bowl's rim by a strip of triangles (no
//! new vertices). The strip lies outside the globe: the lid margins
//! stand at least 0.35 mm off it, the bowl's rim 2.5 mm. The lining keeps
//! the default's targets (none: it stays still while the margins move
//! over the eyeball, and the strip stretches, as ICT's lining does).

use super::parts::{base, glb_of, plain_truth};
use super::truth::{Piece, VariantTruth};
use glam::Vec3;
use likeness::avatar::{Avatar, AvatarPart};
use likeness::geometry::Topology;
use likeness::geometry::mesh_boundary::boundary_loops;
use std::f64::consts::TAU;

/// The loop of `loops` whose centroid lies nearest `centre` (positions
/// `positions`).
fn nearest_loop<'a>(loops: &'a [Vec<u32>], positions: &[Vec3], centre: Vec3) -> &'a [u32] {
    let centroid = |l: &[u32]| -> Vec3 {
        l.iter().map(|&v| positions[v as usize]).sum::<Vec3>() / l.len() as f32
    };
    loops
        .iter()
        .min_by(|a, b| {
            centroid(a)
                .distance(centre)
                .total_cmp(&centroid(b).distance(centre))
        })
        .expect("the part has boundary loops")
}

/// The strip joining loop `a` (the lid margin, in the order its own
/// triangles use its edges) to loop `b` (the bowl's rim, the same): each
/// triangle uses the loops' edges against their own triangles, so the
/// stitched surface stays consistently oriented. `angle` is a vertex's
/// angle around the eye's visual axis.
fn strip(a: &[u32], b: &[u32], angle: impl Fn(u32) -> f64) -> Vec<[u32; 3]> {
    // The zipper below uses `a`'s edges forwards and `b`'s backwards, and
    // walks both the same way round the axis: `a` reversed (its own
    // triangles use it forwards), `b` as it is.
    let a: Vec<u32> = a.iter().rev().copied().collect();
    let b: Vec<u32> = b.to_vec();
    let turn = |l: &[u32]| {
        let mut total = 0.0;
        for k in 0..l.len() {
            let d = angle(l[(k + 1) % l.len()]) - angle(l[k]);
            total += (d + TAU / 2.0).rem_euclid(TAU) - TAU / 2.0;
        }
        total.signum()
    };
    assert_eq!(
        turn(&a),
        turn(&b),
        "the lid margin and the bowl's rim wind the same way"
    );
    let sign = turn(&a);
    // Unwrapped angles from a[0], increasing along each loop.
    let unwrap = |l: &[u32], start: f64| -> Vec<f64> {
        l.iter()
            .map(|&v| (sign * (angle(v) - start)).rem_euclid(TAU))
            .collect()
    };
    let a0 = angle(a[0]);
    let start_b = unwrap(&b, a0)
        .iter()
        .enumerate()
        .min_by(|x, y| x.1.min(TAU - x.1).total_cmp(&y.1.min(TAU - y.1)))
        .map(|(k, _)| k)
        .unwrap_or(0);
    let b: Vec<u32> = b[start_b..].iter().chain(&b[..start_b]).copied().collect();
    let ta = unwrap(&a, a0);
    let mut tb = unwrap(&b, a0);
    if tb[0] > TAU / 2.0 {
        tb[0] -= TAU;
    }
    let (n, m) = (a.len(), b.len());
    let at = |t: &[f64], k: usize, len: usize| {
        if k < len { t[k] } else { t[k - len] + TAU }
    };
    let (mut i, mut j) = (0, 0);
    let mut triangles = Vec::with_capacity(n + m);
    while i < n || j < m {
        let advance_a = j == m || (i < n && at(&ta, i + 1, n) <= at(&tb, j + 1, m));
        if advance_a {
            triangles.push([a[i % n], a[(i + 1) % n], b[j % m]]);
            i += 1;
        } else {
            triangles.push([a[i % n], b[(j + 1) % m], b[j % m]]);
            j += 1;
        }
    }
    triangles
}

/// The avatar: the default's, its socket lining merged into the skin and
/// stitched to the eye openings.
fn avatar() -> Avatar {
    let b = base();
    let (meshes, mut parts) = b.avatar.clone().into_parts();
    let skin = parts[b.skin].clone();
    let sockets = parts[b.sockets].clone();
    let o = skin.positions.len() as u32;
    let mut merged = AvatarPart {
        positions: skin
            .positions
            .iter()
            .chain(&sockets.positions)
            .copied()
            .collect(),
        triangles: skin
            .triangles
            .iter()
            .copied()
            .chain(sockets.triangles.iter().map(|t| t.map(|v| v + o)))
            .collect(),
        targets: skin
            .targets
            .iter()
            .zip(&sockets.targets)
            .map(|(s, t)| s.iter().chain(t).copied().collect())
            .collect(),
        ..skin.clone()
    };
    let loops_of = |p: &AvatarPart| {
        let topology =
            Topology::new(p.positions.len(), p.triangles.clone()).expect("a checked part");
        boundary_loops(&topology).expect("a manifold part")
    };
    let skin_loops = loops_of(&skin);
    let rims: Vec<Vec<u32>> = loops_of(&sockets)
        .into_iter()
        .map(|l| l.into_iter().map(|v| v + o).collect())
        .collect();
    for centre in b.eye_centres {
        let margin = nearest_loop(&skin_loops, &merged.positions, centre);
        let rim = nearest_loop(&rims, &merged.positions, centre);
        let positions = &merged.positions;
        let angle = |v: u32| {
            let d = positions[v as usize] - centre;
            f64::from(d.y).atan2(f64::from(d.x))
        };
        let stitched = strip(margin, rim, angle);
        merged.triangles.extend(stitched);
    }
    parts[b.skin] = merged;
    parts.remove(b.sockets);
    for p in parts
        .iter_mut()
        .filter(|p| p.mesh == 0 && p.primitive > sockets.primitive)
    {
        p.primitive -= 1;
    }
    Avatar::new(meshes, parts).expect("the lined-sockets variant's parts make an avatar")
}

/// The GLB and its truth.
pub fn lined_sockets() -> (Vec<u8>, VariantTruth) {
    let avatar = avatar();
    let mut truth = plain_truth(&avatar, 0, base().true_correspondence.len());
    // The sockets' part is gone into the skin's: the later parts move up one.
    truth.eyeballs = base().eyes.map(|e| Piece::whole(&avatar, e - 1));
    truth.teeth = Some(Piece::whole(&avatar, base().teeth[0] - 1));
    (glb_of(&avatar, None), truth)
}
