//! The head's skin as the checks of the output see it: its edges and
//! triangles out of the eyeballs, which vertices are skin and which are
//! eyeballs, and the sphere round a set of vertices. Shared by the check of the output
//! ([`super::implant_check`]) and the inside showing through the skin
//! ([`super::showing_through`]).

use super::model::Avatar;
use super::registration::FaceRegistration;
use glam::DVec3;

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

/// The triangles of the avatar's face parts (the head's skin) with no
/// corner in an eyeball.
pub fn head_triangles(avatar: &Avatar, found: &FaceRegistration) -> Vec<[u32; 3]> {
    let in_eyeball = eyeball_flags(avatar, found);
    avatar
        .part_triangles(&found.face_parts())
        .into_iter()
        .filter(|t| t.iter().all(|&v| !in_eyeball[v as usize]))
        .collect()
}

/// Whether each avatar vertex lies in a part the face was found on (the
/// head's skin).
pub fn skin_flags(avatar: &Avatar, found: &FaceRegistration) -> Vec<bool> {
    let offsets = avatar.vertex_offsets();
    let mut flags = vec![false; avatar.vertex_count()];
    for &k in &found.face_parts() {
        if let Some((&a, &b)) = offsets.get(k).zip(offsets.get(k + 1)) {
            flags[a..b].fill(true);
        }
    }
    flags
}

/// Whether each avatar vertex is in an eyeball the registration found.
pub fn eyeball_flags(avatar: &Avatar, found: &FaceRegistration) -> Vec<bool> {
    let mut flags = vec![false; avatar.vertex_count()];
    for &v in found.eyeballs.iter().flatten() {
        if let Some(f) = flags.get_mut(v as usize) {
            *f = true;
        }
    }
    flags
}

/// The centroid of `vertices` at `rest` and their largest distance from
/// it.
pub fn bounding_sphere(rest: &[DVec3], vertices: &[u32]) -> (DVec3, f64) {
    let centre =
        vertices.iter().map(|&v| rest[v as usize]).sum::<DVec3>() / vertices.len().max(1) as f64;
    let radius = vertices
        .iter()
        .map(|&v| (rest[v as usize] - centre).length())
        .fold(0.0, f64::max);
    (centre, radius)
}
