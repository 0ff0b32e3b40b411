//! What a user sees wrong in an implanted avatar, measured against the
//! avatar's own shapes. Each measure compares the
//! personalized shape with the avatar's own shape of the same name, so a
//! rig's own choices (a lid tucked under a cornea shell, a stretchy lip)
//! are never counted against the implant:
//!
//! - [`torn_edges`]: head edges stretched more than [`TORN_STRETCH`] times
//!   their rest length where the avatar's own shape stretches them less
//!   than [`OWN_STRETCH`] times;
//! - [`eyeball_seen_share`]: the share of an eyeball's front half seen
//!   from straight ahead (a ray towards the viewer that no skin triangle
//!   stops), for how far a blink closes;
//! - [`deepest_lid`]: the deepest a skin vertex goes inside an eyeball
//!   where the avatar's own shape keeps it outside.

use glam::{DVec3, Vec3};
use likeness::Blendshape;
use likeness::avatar::Avatar;
use likeness::avatar::partial_transfer::Implanted;
use likeness::avatar::registration::FaceRegistration;
use likeness::avatar::registration::find_face::arkit_displacement;
use likeness::geometry::closest_point::TriangleGrid;

/// An edge counts as torn when the shape stretches it more than this many
/// times its rest length …
pub const TORN_STRETCH: f32 = 2.0;

/// … where the avatar's own shape stretches it less than this.
pub const OWN_STRETCH: f32 = 1.5;

/// The unique edges of the avatar's face parts (the head's skin) whose
/// ends are in no eyeball.
pub fn head_edges(avatar: &Avatar, found: &FaceRegistration) -> Vec<(u32, u32)> {
    let in_eyeball = eyeball_flags(avatar, found);
    let mut edges: Vec<(u32, u32)> = avatar
        .part_triangles(&found.face_parts())
        .iter()
        .flat_map(|t| [(t[0], t[1]), (t[1], t[2]), (t[2], t[0])])
        .filter(|(a, b)| !in_eyeball[*a as usize] && !in_eyeball[*b as usize])
        .map(|(a, b)| (a.min(b), a.max(b)))
        .collect();
    edges.sort_unstable();
    edges.dedup();
    edges
}

/// Whether each avatar vertex is in an eyeball the registration found.
pub fn eyeball_flags(avatar: &Avatar, found: &FaceRegistration) -> Vec<bool> {
    let mut flags = vec![false; avatar.vertex_count()];
    for &v in found.eyeballs.iter().flatten() {
        flags[v as usize] = true;
    }
    flags
}

/// Edges of `edges` torn by `got` where `own` does not tear them (module
/// docs); `rest` the avatar's rest positions, the shapes displacements.
pub fn torn_edges(rest: &[Vec3], own: &[Vec3], got: &[Vec3], edges: &[(u32, u32)]) -> usize {
    let stretch = |d: &[Vec3], a: usize, b: usize| {
        let at_rest = (rest[a] - rest[b]).length();
        ((rest[a] + d[a]) - (rest[b] + d[b])).length() / at_rest.max(f32::MIN_POSITIVE)
    };
    edges
        .iter()
        .map(|&(a, b)| (a as usize, b as usize))
        .filter(|&(a, b)| stretch(got, a, b) > TORN_STRETCH && stretch(own, a, b) < OWN_STRETCH)
        .count()
}

/// Möller–Trumbore: whether the ray `o + s d`, `s > 0`, crosses triangle
/// `abc`.
pub fn ray_hits(o: DVec3, d: DVec3, [a, b, c]: [DVec3; 3]) -> bool {
    let (e1, e2) = (b - a, c - a);
    let p = d.cross(e2);
    let det = e1.dot(p);
    if det.abs() < 1e-18 {
        return false;
    }
    let t = o - a;
    let u = t.dot(p) / det;
    let q = t.cross(e1);
    let v = d.dot(q) / det;
    u >= 0.0 && v >= 0.0 && u + v <= 1.0 && e2.dot(q) / det > 0.0
}

/// The share of eyeball `eye`'s vertices on its front half (towards
/// `forward` from its centre, at rest) that are seen from straight ahead
/// under displacement `d`: no triangle of the avatar's other vertices
/// within three eyeball radii crosses the ray from the vertex along
/// `forward`.
pub fn eyeball_seen_share(
    avatar: &Avatar,
    found: &FaceRegistration,
    eye: &[u32],
    d: &[Vec3],
    forward: DVec3,
) -> f64 {
    let rest: Vec<DVec3> = avatar.positions().iter().map(|p| p.as_dvec3()).collect();
    let posed = |v: usize| rest[v] + d[v].as_dvec3();
    let (centre, radius) = bounding_sphere(&rest, eye);
    let in_eyeball = eyeball_flags(avatar, found);
    let cover: Vec<[DVec3; 3]> = avatar
        .triangles()
        .iter()
        .filter(|t| t.iter().all(|&v| !in_eyeball[v as usize]))
        .map(|t| t.map(|v| posed(v as usize)))
        .filter(|t| t.iter().any(|p| (*p - centre).length() < 3.0 * radius))
        .collect();
    let front: Vec<usize> = eye
        .iter()
        .map(|&v| v as usize)
        .filter(|&v| (rest[v] - centre).dot(forward) > 0.0)
        .collect();
    let seen = front
        .iter()
        .filter(|&&v| {
            let o = posed(v) + forward * 1e-6 * radius;
            !cover.iter().any(|t| ray_hits(o, forward, *t))
        })
        .count();
    seen as f64 / front.len().max(1) as f64
}

/// The centroid of `vertices` at `rest` and their largest distance from
/// it.
fn bounding_sphere(rest: &[DVec3], vertices: &[u32]) -> (DVec3, f64) {
    let centre =
        vertices.iter().map(|&v| rest[v as usize]).sum::<DVec3>() / vertices.len().max(1) as f64;
    let radius = vertices
        .iter()
        .map(|&v| (rest[v as usize] - centre).length())
        .fold(0.0, f64::max);
    (centre, radius)
}

/// The deepest (avatar units) a skin vertex near eyeball `eye` lies
/// inside it under `got` where it lies outside under `own` (module docs).
/// Inside is judged by the eyeball's closest triangle as displaced by
/// the same shape, facing outwards.
pub fn deepest_lid(
    avatar: &Avatar,
    found: &FaceRegistration,
    eye: &[u32],
    own: &[Vec3],
    got: &[Vec3],
) -> f64 {
    let rest: Vec<DVec3> = avatar.positions().iter().map(|p| p.as_dvec3()).collect();
    let in_eye: Vec<bool> = {
        let mut f = vec![false; rest.len()];
        eye.iter().for_each(|&v| f[v as usize] = true);
        f
    };
    let triangles: Vec<[u32; 3]> = avatar
        .triangles()
        .iter()
        .copied()
        .filter(|t| t.iter().all(|&v| in_eye[v as usize]))
        .collect();
    let (centre, radius) = bounding_sphere(&rest, eye);
    let in_eyeball = eyeball_flags(avatar, found);
    let depth = |d: &[Vec3]| {
        let posed: Vec<DVec3> = rest.iter().zip(d).map(|(p, x)| *p + x.as_dvec3()).collect();
        let grid = TriangleGrid::new(&posed, &triangles);
        move |v: usize| -> f64 {
            let p = posed[v];
            match grid.closest(p) {
                Some(c) if (p - c.point).dot(grid.triangle_normal(c.triangle)) < 0.0 => c.distance,
                _ => 0.0,
            }
        }
    };
    let (own_depth, got_depth) = (depth(own), depth(got));
    (0..rest.len())
        .filter(|&v| !in_eyeball[v] && (rest[v] - centre).length() < 1.5 * radius)
        .filter(|&v| own_depth(v) == 0.0)
        .map(got_depth)
        .fold(0.0, f64::max)
}

/// Issue 21's figures for one implanted avatar.
#[derive(Clone, Debug)]
pub struct Figures {
    /// Head edges (of the face parts, out of the eyeballs).
    pub head_edges: usize,
    /// The most edges one shape tears, and that shape.
    pub most_torn: (usize, Blendshape),
    /// Shapes that tear more than half a per cent of the head's edges.
    pub shapes_over_half_percent: usize,
    /// For each blink (left, right) that has an eyeball on its side: the
    /// share of the eyeball's front seen under the avatar's own blink, then
    /// under the person's.
    pub blinks: Vec<(Blendshape, f64, f64)>,
    /// The deepest lid inside an eyeball where the avatar's own shape
    /// keeps out (mm, mask scale), and its shape.
    pub deepest_lid_mm: (f64, Blendshape),
    /// Face vertices jawOpen takes to the other lip ([`lip_swaps`]).
    pub lip_swaps: usize,
}

/// Vertices of the face parts that the avatar's own jawOpen (`own`) moves
/// by less than a fifth of its largest motion `L` (the upper lip, the face
/// above the mouth) and that the implanted jawOpen (`got`) moves more than
/// `L/4` away from it: a vertex of the upper lip given the lower lip's
/// motion. A person's jawOpen differs from an avatar's there by a few
/// millimetres (on every generated variant, committed subject 1: at most
/// 0.16 L, 6.5 mm of 40); the upper lip of other proportions torn into a
/// saw-tooth of spikes between the lips was 0.32 L off, with 113 torn
/// edges, under the torn-edge limit of 185.
pub fn lip_swaps(own: &[Vec3], got: &[Vec3], face_parts: &[bool]) -> usize {
    let largest = own
        .iter()
        .zip(face_parts)
        .filter(|(_, f)| **f)
        .map(|(d, _)| d.length())
        .fold(0.0, f32::max);
    own.iter()
        .zip(got)
        .zip(face_parts)
        .filter(|((o, g), f)| {
            **f && o.length() < 0.2 * largest && (**g - **o).length() > 0.25 * largest
        })
        .count()
}

/// The avatar's own displacement for ARKit shape `b` (zero without one).
pub fn own_shape(avatar: &Avatar, b: Blendshape) -> Vec<Vec3> {
    arkit_displacement(avatar, b)
        .map(|d| d.iter().map(|x| x.as_vec3()).collect())
        .unwrap_or_else(|| vec![Vec3::ZERO; avatar.vertex_count()])
}

/// Measures `implanted` on `avatar` found as `found` (module docs).
pub fn figures(avatar: &Avatar, found: &FaceRegistration, implanted: &Implanted) -> Figures {
    let rest = avatar.positions();
    let edges = head_edges(avatar, found);
    let to_mm = 1000.0 / found.similarity.scale;
    let mut most_torn = (0, Blendshape::JawOpen);
    let mut over = 0;
    let mut deepest = (0.0f64, Blendshape::JawOpen);
    for b in Blendshape::ALL {
        let (own, got) = (own_shape(avatar, b), &implanted.shapes[b.index()]);
        let torn = torn_edges(&rest, &own, got, &edges);
        if torn > most_torn.0 {
            most_torn = (torn, b);
        }
        if torn as f64 > 0.005 * edges.len() as f64 {
            over += 1;
        }
        for eye in &found.eyeballs {
            let d = deepest_lid(avatar, found, eye, &own, got) * to_mm;
            if d > deepest.0 {
                deepest = (d, b);
            }
        }
    }
    let forward = found.similarity.rotation * DVec3::Z;
    // ARKit's +x is the person's left.
    let on_left = |eye: &Vec<u32>| {
        let c = eye
            .iter()
            .map(|&v| rest[v as usize].as_dvec3())
            .sum::<DVec3>()
            / eye.len() as f64;
        (found.similarity.rotation.transpose() * (c - found.similarity.translation)).x > 0.0
    };
    let blinks = [
        (true, Blendshape::EyeBlinkLeft),
        (false, Blendshape::EyeBlinkRight),
    ]
    .into_iter()
    .filter_map(|(left, b)| {
        let eye = found.eyeballs.iter().find(|e| on_left(e) == left)?;
        let own = eyeball_seen_share(avatar, found, eye, &own_shape(avatar, b), forward);
        let got = eyeball_seen_share(avatar, found, eye, &implanted.shapes[b.index()], forward);
        Some((b, own, got))
    })
    .collect();
    let offsets = avatar.vertex_offsets();
    let mut face_parts = vec![false; avatar.vertex_count()];
    for &i in &found.face_parts() {
        face_parts[offsets[i]..offsets[i + 1]].fill(true);
    }
    let jaw = Blendshape::JawOpen;
    let swaps = lip_swaps(
        &own_shape(avatar, jaw),
        &implanted.shapes[jaw.index()],
        &face_parts,
    );
    Figures {
        head_edges: edges.len(),
        most_torn,
        shapes_over_half_percent: over,
        blinks,
        deepest_lid_mm: deepest,
        lip_swaps: swaps,
    }
}

/// One line of `found`'s and `f`'s figures, for the study and the tests'
/// logs.
pub fn summary(found: &FaceRegistration, f: &Figures) -> String {
    let blinks: String = f
        .blinks
        .iter()
        .map(|(b, own, got)| {
            format!(
                " {b} {:.1}% seen own, {:.1}% personalized;",
                100.0 * own,
                100.0 * got
            )
        })
        .collect();
    format!(
        "coverage {:.1}%, residual {:.3} mm mean, registration {:.2} s ({} stages, {} steps); \
         most torn {} of {} head edges ({}), {} shapes over 0.5%; {} lip vertices swapped in jawOpen;{blinks} deepest lid {:.2} mm ({}); {} eyeballs",
        100.0 * found.coverage,
        found.residual_mean_mm,
        found.seconds,
        found.nonrigid_steps.0,
        found.nonrigid_steps.1,
        f.most_torn.0,
        f.head_edges,
        f.most_torn.1,
        f.shapes_over_half_percent,
        f.lip_swaps,
        f.deepest_lid_mm.0,
        f.deepest_lid_mm.1,
        found.eyeballs.len(),
    )
}

/// The round trip: the avatar's own shapes, seen through the
/// registration, given to the pipeline as the person, compared with the
/// avatar's own targets.
#[derive(Clone, Debug, PartialEq)]
pub struct RoundTrip {
    /// The largest, over the shapes, RMSE over the face region, as a share
    /// of that shape's largest own motion; and its shape.
    pub face_rmse_share: (f64, Blendshape),
    /// The largest, over the shapes and every vertex, distance from the
    /// own target, as a share of that shape's largest own motion; and its
    /// shape.
    pub vertex_share: (f64, Blendshape),
    /// That vertex.
    pub worst_vertex: u32,
    /// Per blink with an eyeball on its side: the eyeball's front seen
    /// under the own blink and under the round trip's.
    pub blinks: Vec<(Blendshape, f64, f64)>,
}

/// Measures a round trip's `implanted` shapes against `avatar`'s own
/// (shapes the avatar lacks are skipped: nothing to give back).
pub fn round_trip(avatar: &Avatar, found: &FaceRegistration, implanted: &Implanted) -> RoundTrip {
    let mut face_rmse = (0.0f64, Blendshape::JawOpen);
    let mut vertex = (0.0f64, Blendshape::JawOpen);
    let mut worst_vertex = 0;
    for b in Blendshape::ALL {
        let Some(own) = arkit_displacement(avatar, b) else {
            continue;
        };
        let got = &implanted.shapes[b.index()];
        let largest = own.iter().map(|d| d.length()).fold(0.0, f64::max);
        if largest == 0.0 {
            continue;
        }
        let error = |v: usize| (got[v].as_dvec3() - own[v]).length();
        let sum: f64 = found
            .map
            .face
            .iter()
            .map(|f| error(f.vertex as usize).powi(2))
            .sum();
        let rmse = (sum / found.map.face.len().max(1) as f64).sqrt() / largest;
        if rmse > face_rmse.0 {
            face_rmse = (rmse, b);
        }
        for v in 0..own.len() {
            let share = error(v) / largest;
            if share > vertex.0 {
                vertex = (share, b);
                worst_vertex = v as u32;
            }
        }
    }
    let f = figures(avatar, found, implanted);
    RoundTrip {
        face_rmse_share: face_rmse,
        vertex_share: vertex,
        worst_vertex,
        blinks: f.blinks,
    }
}
