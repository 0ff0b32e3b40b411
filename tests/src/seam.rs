//! The seam statistics: how much a change of an avatar's skin
//! stretches and bends it along the border of the face region, against
//! just inside and just outside it.

use glam::Vec3;
use likeness::avatar::registration::FaceRegistration;

/// Edge-length strain and dihedral-angle change of `shape` (displacement
/// per avatar vertex) against the rest, over the skin edges of three bands:
/// the face border (one end in the face region, one not), the ring just
/// inside (both ends in the face, one of them next to the border) and the
/// ring just outside. Mean absolute values per band.
pub fn seam_statistics(
    positions: &[Vec3],
    triangles: &[[u32; 3]],
    face: &[bool],
    shape: &[Vec3],
) -> [(f64, f64); 3] {
    seam_statistics_where(
        positions,
        triangles,
        face,
        shape,
        &vec![true; positions.len()],
    )
}

/// [`seam_statistics`] over the border edges whose ends are both `near`
/// (and the bands next to those edges).
pub fn seam_statistics_where(
    positions: &[Vec3],
    triangles: &[[u32; 3]],
    face: &[bool],
    shape: &[Vec3],
    near: &[bool],
) -> [(f64, f64); 3] {
    use std::collections::HashMap;
    let mut next_to_border = vec![false; positions.len()];
    let mut edges: HashMap<(u32, u32), Vec<usize>> = HashMap::new();
    for (t, tri) in triangles.iter().enumerate() {
        for k in 0..3 {
            let (a, b) = (tri[k], tri[(k + 1) % 3]);
            edges.entry((a.min(b), a.max(b))).or_default().push(t);
            if face[a as usize] != face[b as usize] && near[a as usize] && near[b as usize] {
                next_to_border[a as usize] = true;
                next_to_border[b as usize] = true;
            }
        }
    }
    let normal = |t: usize, moved: bool| {
        let p = |i: u32| positions[i as usize] + if moved { shape[i as usize] } else { Vec3::ZERO };
        let [a, b, c] = triangles[t];
        (p(b) - p(a)).cross(p(c) - p(a)).normalize_or_zero()
    };
    let mut sums = [(0.0f64, 0.0f64, 0usize); 3];
    for ((a, b), ts) in &edges {
        let (fa, fb) = (face[*a as usize], face[*b as usize]);
        let band = if fa != fb {
            if !(near[*a as usize] && near[*b as usize]) {
                continue;
            }
            0
        } else if fa && (next_to_border[*a as usize] || next_to_border[*b as usize]) {
            1
        } else if !fa && (next_to_border[*a as usize] || next_to_border[*b as usize]) {
            2
        } else {
            continue;
        };
        let rest = (positions[*b as usize] - positions[*a as usize]).length();
        let moved = (positions[*b as usize] + shape[*b as usize]
            - positions[*a as usize]
            - shape[*a as usize])
            .length();
        let strain = ((moved - rest) / rest).abs() as f64;

        let bend = if ts.len() == 2 {
            let before = normal(ts[0], false).angle_between(normal(ts[1], false));
            let after = normal(ts[0], true).angle_between(normal(ts[1], true));
            (after - before).abs() as f64
        } else {
            0.0
        };
        sums[band].0 += strain;
        sums[band].1 += bend;
        sums[band].2 += 1;
    }
    sums.map(|(s, b, n)| (s / n.max(1) as f64, b / n.max(1) as f64))
}

/// The skin vertices (of part `skin`) nearer to the registered mask's
/// outline than to its eye and mouth rims.
pub fn outline_vertices(
    found: &FaceRegistration,
    mask: &likeness::Topology,
    avatar: &likeness::avatar::Avatar,
    skin: usize,
) -> Vec<bool> {
    let loops = likeness::geometry::mesh_boundary::boundary_loops(mask).expect("a mask");
    let outline = (0..loops.len())
        .max_by_key(|&i| loops[i].len())
        .expect("loops");
    let rims: Vec<(glam::DVec3, bool)> = loops
        .iter()
        .enumerate()
        .flat_map(|(i, l)| l.iter().map(move |&v| (v, i == outline)))
        .map(|(v, is_outline)| (found.mask_on_avatar[v as usize], is_outline))
        .collect();
    avatar.parts()[skin]
        .positions
        .iter()
        .map(|p| {
            let p = p.as_dvec3();
            rims.iter()
                .min_by(|a, b| (a.0 - p).length().total_cmp(&(b.0 - p).length()))
                .is_some_and(|r| r.1)
        })
        .collect()
}
