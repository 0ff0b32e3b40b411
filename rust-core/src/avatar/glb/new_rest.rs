//! A new rest written back into a read file (the person's face taken onto
//! the avatar, [`crate::avatar::person_face`]): each primitive's
//! `POSITION` replaced, and its `NORMAL` and `TANGENT`, if it has them,
//! turned with the surface.
//!
//! The artist's normals are kept, not recomputed: a hard edge, a normal
//! map's tangent frame and a deliberately bent normal survive. Each vertex's
//! normal and tangent turn by the shortest rotation `q_v` that takes the
//! surface's smooth normal at rest to its smooth normal on the new rest
//! (area-weighted, both computed with the vertices that share a position
//! welded, so the two sides of a UV seam turn alike: `surface_turn.rs`).
//! In the primitive's own space a normal `n` placed by
//! the linear part `L` of its node becomes `Lᵀ q_v (L⁻ᵀ n)`, normalized; a
//! tangent `t` becomes `L⁻¹ q_v (L t)`, normalized, its handedness `w`
//! kept. Vertices the new rest does not move keep theirs exactly.

use super::GlbError;
use super::accessor::Source;
use super::encode::Builder;
use super::surface_turn::{Placed, WeldedSurface};
use glam::{Mat3, Mat4, Quat, Vec3};
use serde_json::{Value, json};

/// The shortest rotation per vertex taking the welded smooth normal of
/// `stock` to that of `moved` (same `triangles`); identity where a vertex
/// did not move or has no normal.
pub fn surface_turns(stock: &[Vec3], moved: &[Vec3], triangles: &[[u32; 3]]) -> Vec<Quat> {
    let turns = WeldedSurface::new(stock, triangles).turns(moved);
    turns
        .into_iter()
        .enumerate()
        .map(|(v, q)| match stock.get(v) == moved.get(v) {
            true => Quat::IDENTITY,
            false => q,
        })
        .collect()
}

/// Replaces primitive `prim`'s `POSITION` by `moved` (world space, one per
/// vertex; `stock` the rest as read, `triangles` the primitive's) taken to
/// the primitive's space by `world`, and turns its `NORMAL` and `TANGENT`
/// (module docs); new accessors go to `b`, numbered after
/// `old_accessors`. `document` and `source` read the old attributes.
/// Returns the normals written (the primitive's space), if it has them.
#[allow(clippy::too_many_arguments)]
pub(crate) fn write_rest(
    prim: &mut Value,
    primitive: &gltf::Primitive,
    source: &Source,
    b: &mut Builder,
    old_accessors: usize,
    world: Mat4,
    stock: &[Vec3],
    moved: &[Vec3],
    triangles: &[[u32; 3]],
) -> Result<Option<Vec<Vec3>>, GlbError> {
    let to_local = world.inverse();
    let local: Vec<Vec3> = moved
        .iter()
        .map(|p| to_local.transform_point3(*p))
        .collect();
    prim["attributes"]["POSITION"] = json!(old_accessors + b.vec3(&local));
    let turns = surface_turns(stock, moved, triangles);
    let linear = Mat3::from_mat4(world);
    let inverse = linear.inverse();
    let mut written = None;
    if let Some(accessor) = primitive.get(&gltf::Semantic::Normals) {
        let normals = source.vec3(&accessor, Some(stock.len()))?;
        let placed = Placed::new(linear);
        let turned: Vec<Vec3> = normals
            .iter()
            .zip(&turns)
            .map(|(n, q)| placed.turned(*n, *q))
            .collect();
        prim["attributes"]["NORMAL"] = json!(old_accessors + b.vec3(&turned));
        written = Some(turned);
    }
    if let Some(accessor) = primitive.get(&gltf::Semantic::Tangents) {
        let tangents = source.floats(&accessor)?;
        let turned: Vec<[f32; 4]> = tangents
            .chunks_exact(4)
            .zip(&turns)
            .map(|(t, q)| {
                let v = Vec3::new(t[0], t[1], t[2]);
                let v = match *q == Quat::IDENTITY {
                    true => v,
                    false => (inverse * (*q * (linear * v))).try_normalize().unwrap_or(v),
                };
                [v.x, v.y, v.z, t[3]]
            })
            .collect();
        if turned.len() == stock.len() {
            prim["attributes"]["TANGENT"] = json!(old_accessors + b.vec4(&turned));
        }
    }
    Ok(written)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_turned_patch_turns_its_normals_and_a_still_one_keeps_them() {
        // Lifting one far corner of the seam square turns the surface
        // there, and both halves of the seam turn alike.
        let (stock, triangles) = super::super::surface_turn::seam_square();
        let mut moved = stock.clone();
        let still = surface_turns(&stock, &moved, &triangles);
        assert!(still.iter().all(|q| *q == Quat::IDENTITY));
        moved[3].z = 0.5;
        moved[1].z = 0.1;
        moved[4].z = 0.1;
        let turns = surface_turns(&stock, &moved, &triangles);
        assert_eq!(turns[1], turns[4], "both halves of the seam turn alike");
        assert!(turns[3].angle_between(Quat::IDENTITY) > 0.1);
        assert_eq!(turns[0], Quat::IDENTITY);
    }
}
