//! Small flat avatars for the glTF tests and benchmarks: grids of
//! vertices in a plane, each a part with whatever morph targets the test
//! needs. They exercise the reader and the writer, not the face: no face
//! is found on them.

use glam::Vec3;
use likeness::avatar::{Avatar, AvatarMesh, AvatarPart};

/// A grid of `columns × rows` vertices `spacing` apart in the xy plane at
/// depth `z`, row after row, with two triangles per cell (counter-clockwise
/// seen from +z): its positions and triangles.
pub fn grid(columns: u32, rows: u32, spacing: f32, z: f32) -> (Vec<Vec3>, Vec<[u32; 3]>) {
    let positions = (0..rows)
        .flat_map(|y| {
            (0..columns).map(move |x| Vec3::new(x as f32 * spacing, y as f32 * spacing, z))
        })
        .collect();
    let mut triangles = Vec::new();
    for y in 0..rows.saturating_sub(1) {
        for x in 0..columns.saturating_sub(1) {
            let i = y * columns + x;
            triangles.push([i, i + 1, i + columns + 1]);
            triangles.push([i, i + columns + 1, i + columns]);
        }
    }
    (positions, triangles)
}

/// The part `mesh {mesh}` (primitive 0 of mesh `mesh`) of `geometry`
/// (positions and triangles), with `targets` morph targets: target `t`
/// moves vertex `v` at rest position `p` by `displacement(t, v, p)`.
pub fn part(
    mesh: usize,
    (positions, triangles): (Vec<Vec3>, Vec<[u32; 3]>),
    targets: usize,
    displacement: impl Fn(usize, usize, Vec3) -> Vec3,
) -> AvatarPart {
    let targets = (0..targets)
        .map(|t| {
            positions
                .iter()
                .enumerate()
                .map(|(v, p)| displacement(t, v, *p))
                .collect()
        })
        .collect();
    AvatarPart {
        name: format!("mesh {mesh}"),
        mesh,
        primitive: 0,
        positions,
        triangles,
        targets,
    }
}

/// The avatar of `meshes` (each a name and its targets' names) and
/// `parts`; panics if they do not make one (a mistake in the test).
pub fn avatar<S: AsRef<str>>(meshes: &[(&str, &[S])], parts: Vec<AvatarPart>) -> Avatar {
    let meshes = meshes
        .iter()
        .map(|(name, targets)| AvatarMesh {
            name: Some(name.to_string()),
            target_names: targets.iter().map(|t| t.as_ref().to_string()).collect(),
        })
        .collect();
    Avatar::new(meshes, parts).expect("a test avatar's parts fit its meshes")
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_grid_has_two_triangles_per_cell_all_facing_plus_z() {
        let (positions, triangles) = grid(4, 3, 0.01, 0.0);
        assert_eq!(positions.len(), 12);
        assert_eq!(triangles.len(), 2 * 3 * 2);
        for t in &triangles {
            let [a, b, c] = t.map(|i| positions[i as usize]);
            assert!((b - a).cross(c - a).z > 0.0, "{t:?} faces away");
        }
    }
}
