//! What a user sees wrong in an implanted avatar, measured against the
//! avatar's own shapes, summed up for the tests and the studies. The
//! measures are the product's own check
//! ([`likeness::avatar::implant_check`]); each compares the personalized
//! shape with the avatar's own shape of the same name, so a rig's own
//! choices (a lid tucked under a cornea shell, a stretchy lip) are never
//! counted against the implant:
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
use likeness::avatar::head_skin::skin_flags;
use likeness::avatar::partial_transfer::Implanted;
use likeness::avatar::registration::FaceRegistration;
use likeness::avatar::registration::find_face::arkit_displacement;
use likeness::avatar::showing_through::InsideProbe;

pub use likeness::avatar::implant_check::{
    OWN_STRETCH, TORN_STRETCH, deepest_lid, eyeball_flags, eyeball_seen_share, head_edges, on_left,
    own_shape, torn_edges,
};
pub use likeness::geometry::ray_cover::ray_hits;

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
    /// The most places (vertices, triangles' centres) from behind the skin
    /// one shape brings out in front of it, at any depth, where the own shape keeps them behind
    /// ([`likeness::avatar::showing_through`]), the farthest of them (mm,
    /// mask scale) and that shape.
    pub most_showing: (usize, f64, Blendshape),
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
        let torn = torn_edges(&rest, &own, got, &edges).len();
        if torn > most_torn.0 {
            most_torn = (torn, b);
        }
        if torn as f64 > 0.005 * edges.len() as f64 {
            over += 1;
        }
        for eye in &found.eyeballs {
            let d = deepest_lid(avatar, found, eye, &own, got).0 * to_mm;
            if d > deepest.0 {
                deepest = (d, b);
            }
        }
    }
    let inside = InsideProbe::new(avatar, found);
    let most_showing = Blendshape::ALL
        .iter()
        .map(|&b| {
            let s = inside.showing(&own_shape(avatar, b), &implanted.shapes[b.index()], 0.0);
            (s.points, s.depth * to_mm, b)
        })
        .fold(
            (0, 0.0, Blendshape::JawOpen),
            |a, b| if b.0 > a.0 { b } else { a },
        );
    let forward = found.similarity.rotation * DVec3::Z;
    let on_left = |eye: &Vec<u32>| on_left(&rest, found, eye);
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
    let face_parts = skin_flags(avatar, found);
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
        most_showing,
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
         most torn {} of {} head edges ({}), {} shapes over 0.5%; {} lip vertices swapped in jawOpen;{blinks} deepest lid {:.2} mm ({}); \
         most showing through the skin {} points, {:.2} mm ({}); {} eyeballs",
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
        f.most_showing.0,
        f.most_showing.1,
        f.most_showing.2,
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
