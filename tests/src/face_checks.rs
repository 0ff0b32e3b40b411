//! Issue 22's checks of an avatar that took the person's face at rest
//! ([`likeness::avatar::person_face`]): how near the new rest passes to
//! the scanned neutral, whether the border of the face region is strained
//! more than its inside, whether the skin cuts through itself, whether a
//! lid or a tooth shows where it must not, and whether the blinks close.

use crate::avatar_quality::figures;
use crate::bend::{Bend, largest_bend};
use crate::seam::{outline_vertices, seam_statistics};
use glam::{DVec3, Vec3};
use likeness::avatar::Avatar;
use likeness::avatar::own_shapes::{face_part_triangles, skin_points};
use likeness::avatar::personal_avatar::PersonalAvatar;
use likeness::avatar::registration::FaceRegistration;
use likeness::geometry::closest_point::TriangleTree;
use likeness::geometry::inside_surface::{depth, is_open};
use likeness::geometry::mesh_boundary::boundary_loops;
pub use likeness::geometry::self_intersection::intersecting_pairs;
use likeness::{Blendshape, Blendshapes, Topology};

/// The person's-face figures for one person's avatar: fit, strain at
/// the border and inside, self-intersections, lids in eyeballs, blinks,
/// teeth in front.
#[derive(Clone, Debug)]
pub struct FaceChecks {
    /// Largest distance of the scanned neutral from the new rest's skin
    /// (its closest point), over the mask's vertices on the skin (mm, mask
    /// scale).
    pub fit_max_mm: f64,
    /// Mean edge strain of the rest change along the face region's border,
    /// and in the ring just inside it.
    pub border_strain: f64,
    /// See `border_strain`.
    pub inside_strain: f64,
    /// Pairs of skin triangles that cut through each other at rest.
    pub self_intersections: usize,
    /// Deepest a skin vertex lies inside an eyeball at rest (mm).
    pub lid_in_eyeball_rest_mm: f64,
    /// Deepest a lid lies inside an eyeball in any shape where the
    /// avatar's own shape keeps it out (mm), and the shape.
    pub deepest_lid_mm: (f64, Blendshape),
    /// Per blink: the share of the eyeball's front seen.
    pub blinks: Vec<(Blendshape, f64)>,
    /// Vertices of the teeth in front of the lips at rest
    /// ([`teeth_in_front`]).
    pub teeth_in_front: usize,
    /// The sharpest bend the person's jawOpen makes at a skin edge with an
    /// end beyond the face region's outline (not its eye or mouth holes),
    /// in the lower half of the head: under the chin, down the neck, over
    /// the jaw's angle.
    pub neck_bend: Option<Bend>,
    /// The same bend under `A_j`, the avatar's own shapes at the weights
    /// the retargeting gave the person's jawOpen (Eq. 4): what the rig
    /// itself does at the person's opening, before the implant corrects it.
    pub neck_bend_rig: Option<Bend>,
}

/// Measures `made` (the person's avatar on `stock`, which must have taken
/// the face, `mask` the session's topology) against `person` (their
/// personalized shapes); `teeth` are the
/// avatar vertices of the teeth and gums.
pub fn face_checks(
    stock: &Avatar,
    mask: &Topology,
    made: &PersonalAvatar,
    person: &Blendshapes,
    teeth: &[u32],
) -> FaceChecks {
    let taken = made.taken_face.as_ref().expect("the face was taken");
    let avatar = &taken.avatar;
    let found = &taken.registration;
    let s = found.similarity;
    let to_mm = 1000.0 / s.scale;
    let stock_rest: Vec<DVec3> = stock.positions().iter().map(|p| p.as_dvec3()).collect();
    let rest: Vec<DVec3> = avatar.positions().iter().map(|p| p.as_dvec3()).collect();
    let triangles = face_part_triangles(avatar, found);

    // The fit: how far the scanned neutral lies from the new skin (its
    // closest point), at the mask's vertices the stock registration put
    // on the skin. Where along the skin a point lands is the
    // registration's guess, so the fit is across it.
    let points = skin_points(&made.registration, &stock_rest, &triangles, f64::INFINITY);
    let new_skin = TriangleTree::new(&rest, &triangles);
    let fit_max_mm = points
        .iter()
        .zip(person.neutral())
        .filter(|(p, _)| p.is_some())
        .filter_map(|(_, q)| Some(new_skin.closest(s.apply(*q))?.distance * to_mm))
        .fold(0.0, f64::max);

    // Strain of the rest change along the face's border.
    let change: Vec<Vec3> = taken.moved.iter().map(|d| d.as_vec3()).collect();
    let stock32: Vec<Vec3> = stock.positions();
    let mut face = vec![false; rest.len()];
    for f in &found.map.face {
        face[f.vertex as usize] = true;
    }
    let bands = seam_statistics(&stock32, &triangles, &face, &change);

    let eyeball_grids: Vec<(TriangleTree, bool)> = found
        .eyeballs
        .iter()
        .map(|e| {
            let triangles = avatar.triangles_within(e);
            (TriangleTree::new(&rest, &triangles), is_open(&triangles))
        })
        .collect();
    let in_eyeball: Vec<bool> = {
        let mut f = vec![false; rest.len()];
        for e in &found.eyeballs {
            for &v in e {
                f[v as usize] = true;
            }
        }
        f
    };
    let skin: Vec<u32> = triangles.iter().flatten().copied().collect();
    let lid_in_eyeball_rest_mm = skin
        .iter()
        .filter(|&&v| !in_eyeball[v as usize])
        .flat_map(|&v| {
            let p = rest[v as usize];
            eyeball_grids
                .iter()
                .map(move |(g, open)| depth(g, p, *open))
        })
        .fold(0.0, f64::max)
        * to_mm;

    let implanted = made.implanted.as_ref().expect("personalized shapes");
    let f = figures(avatar, found, implanted);
    let teeth_in_front = teeth_in_front(&rest, found, mask, teeth);
    let rest32: Vec<Vec3> = avatar.positions();
    let offsets = avatar.vertex_offsets();
    let mut by_outline = vec![false; rest.len()];
    for &part in &found.face_parts() {
        let near = outline_vertices(found, mask, avatar, part);
        by_outline[offsets[part]..offsets[part + 1]].copy_from_slice(&near);
    }
    // The lower half of the head (the avatar is +y up): below the middle
    // of the face region's height.
    let (low, high) = found
        .map
        .face
        .iter()
        .fold((f32::MAX, f32::MIN), |(l, h), f| {
            let y = rest32[f.vertex as usize].y;
            (l.min(y), h.max(y))
        });
    let lower = |v: usize| rest32[v].y < 0.5 * (low + high);
    let neck = |shape: &[Vec3]| {
        largest_bend(&rest32, &triangles, shape, |a, b| {
            let (a, b) = (a as usize, b as usize);
            !(face[a] && face[b]) && by_outline[a] && by_outline[b] && lower(a) && lower(b)
        })
    };
    let neck_bend = neck(&implanted.shapes[Blendshape::JawOpen.index()]);
    let neck_bend_rig = neck(&made.retargeting.displacement(avatar, Blendshape::JawOpen));
    FaceChecks {
        fit_max_mm,
        border_strain: bands[0].0,
        inside_strain: bands[1].0,
        self_intersections: self_intersections(&rest, &triangles),
        lid_in_eyeball_rest_mm,
        deepest_lid_mm: f.deepest_lid_mm,
        blinks: f.blinks.iter().map(|(b, _, got)| (*b, *got)).collect(),
        teeth_in_front,
        neck_bend,
        neck_bend_rig,
    }
}

/// The avatar's teeth and gums (avatar vertex indices): its parts whose
/// names start with `teeth` or `gums`, as the default avatar names them.
pub fn teeth_and_gums(avatar: &Avatar) -> Vec<u32> {
    let offsets = avatar.vertex_offsets();
    avatar
        .parts()
        .iter()
        .enumerate()
        .filter(|(_, p)| p.name.starts_with("teeth") || p.name.starts_with("gums"))
        .flat_map(|(k, _)| offsets[k] as u32..offsets[k + 1] as u32)
        .collect()
}

/// Pairs of `triangles` that cut through each other at `positions`
/// ([`likeness::geometry::self_intersection`]).
pub fn self_intersections(positions: &[DVec3], triangles: &[[u32; 3]]) -> usize {
    intersecting_pairs(positions, triangles).len()
}

/// Teeth vertices (avatar indices, `rest` the avatar's rest) in front of
/// the lips: in the mask's frame (`found` the registration on this rest),
/// further forward (+z) than the nearer of the two lips where they meet,
/// the rim of the mask's mouth hole, at the same height across the face
/// (rim vertices within 3 mm in x). Teeth beyond the mouth's corners (no
/// rim vertex that near) are behind the cheeks and are not counted.
pub fn teeth_in_front(
    rest: &[DVec3],
    found: &FaceRegistration,
    mask: &Topology,
    teeth: &[u32],
) -> usize {
    let s = found.similarity;
    let to_mask = |p: DVec3| s.rotation.transpose() * (p - s.translation) / s.scale;
    let loops = boundary_loops(mask).expect("a mask with boundary loops");
    let outline = (0..loops.len()).max_by_key(|&i| loops[i].len());
    // The mouth: the lowest of the holes inside the outline.
    let rim_at = |l: &Vec<u32>| {
        l.iter()
            .map(|&v| to_mask(found.mask_on_avatar[v as usize]))
            .collect::<Vec<_>>()
    };
    let mouth = loops
        .iter()
        .enumerate()
        .filter(|(i, _)| Some(*i) != outline)
        .map(|(_, l)| rim_at(l))
        .min_by(|a, b| {
            let y = |r: &Vec<DVec3>| r.iter().map(|p| p.y).sum::<f64>() / r.len() as f64;
            y(a).total_cmp(&y(b))
        })
        .expect("a mouth hole");
    teeth
        .iter()
        .filter(|&&v| {
            let t = to_mask(rest[v as usize]);
            let front = mouth
                .iter()
                .filter(|r| (r.x - t.x).abs() < 0.003)
                .map(|r| r.z)
                .fold(f64::INFINITY, f64::min);
            front.is_finite() && t.z > front
        })
        .count()
}
