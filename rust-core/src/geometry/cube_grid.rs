//! Cubes over a box of vertices: which cube each vertex lies in, and a
//! set of cubes grown by whole cubes along each axis (a separable
//! dilation of a dense grid). Used to keep a per-shape test to where the
//! shape moves (`crate::avatar::showing_through`) and to the skin near a
//! set of points.

use glam::DVec3;

/// Cubes over the box of some vertices, and the cube of each.
pub struct CubeGrid {
    /// Cubes along x, y and z.
    size: [usize; 3],
    /// Each vertex's cube (`None` off the box's vertices), row-major.
    cell: Vec<Option<usize>>,
}

impl CubeGrid {
    /// Cubes of side `side` over the box of `vertices` of `rest`.
    pub fn new<'a>(
        rest: &[DVec3],
        vertices: impl Iterator<Item = &'a u32> + Clone,
        side: f64,
    ) -> CubeGrid {
        let side = side.max(f64::MIN_POSITIVE);
        let at = |v: &u32| rest.get(*v as usize).copied().filter(|p| p.is_finite());
        let (lo, hi) = vertices.clone().filter_map(at).fold(
            (DVec3::splat(f64::INFINITY), DVec3::splat(f64::NEG_INFINITY)),
            |(lo, hi), p| (lo.min(p), hi.max(p)),
        );
        if lo.x > hi.x {
            return CubeGrid {
                size: [0; 3],
                cell: vec![None; rest.len()],
            };
        }
        // At most 64 cubes along a side: a box far larger than a face
        // takes larger cubes.
        let side = side.max((hi - lo).max_element() / 64.0);
        let size = ((hi - lo) / side)
            .floor()
            .as_uvec3()
            .to_array()
            .map(|n| n as usize + 1);
        let mut cell = vec![None; rest.len()];
        for v in vertices {
            if let (Some(p), Some(slot)) = (at(v), cell.get_mut(*v as usize)) {
                let [x, y, z] = ((p - lo) / side)
                    .floor()
                    .as_uvec3()
                    .to_array()
                    .map(|n| n as usize);
                let [x, y, z] = [x.min(size[0] - 1), y.min(size[1] - 1), z.min(size[2] - 1)];
                *slot = Some((x * size[1] + y) * size[2] + z);
            }
        }
        CubeGrid { size, cell }
    }

    /// How many cubes.
    pub fn cells(&self) -> usize {
        self.size.iter().product()
    }

    /// Vertex `v`'s cube.
    pub fn cell(&self, v: u32) -> Option<usize> {
        self.cell.get(v as usize).copied().flatten()
    }

    /// Marks every cube within `by` cubes (along each axis) of a marked one.
    pub fn grow(&self, marked: &mut [bool], by: usize) {
        let [nx, ny, nz] = self.size;
        let stride = [ny * nz, nz, 1];
        let len = [nx, ny, nz];
        for _ in 0..by {
            for axis in 0..3 {
                let before = marked.to_vec();
                for (c, m) in marked.iter_mut().enumerate() {
                    let i = (c / stride[axis]) % len[axis];
                    *m |= (i > 0 && before[c - stride[axis]])
                        || (i + 1 < len[axis] && before[c + stride[axis]]);
                }
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn vertices_fall_in_their_cubes_and_marks_grow_by_whole_cubes() {
        let rest: Vec<DVec3> = (0..5)
            .map(|i| DVec3::new(10.0 * i as f64, 0.0, 0.0))
            .collect();
        let grid = CubeGrid::new(&rest, [0u32, 1, 2, 3, 4].iter(), 10.0);
        assert_eq!(grid.cells(), 5);
        let cells: Vec<usize> = (0..5).map(|v| grid.cell(v).unwrap()).collect();
        assert_eq!(cells, vec![0, 1, 2, 3, 4]);
        assert_eq!(grid.cell(9), None);
        let mut marked = vec![false; 5];
        marked[0] = true;
        grid.grow(&mut marked, 2);
        assert_eq!(marked, vec![true, true, true, false, false]);
    }

    #[test]
    fn no_vertex_no_cube() {
        let grid = CubeGrid::new(&[DVec3::ZERO], [].iter(), 1.0);
        assert_eq!(grid.cells(), 0);
        assert_eq!(grid.cell(0), None);
    }
}
