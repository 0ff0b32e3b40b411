//! Fixtures shared by the crate's unit tests: small synthetic face masks.
//! The mesh itself comes from [`face_grid`], which the integration tests
//! (`rust-core/tests/`) and the benchmarks include by path, so every test
//! of the geometry sees the same face.

pub(crate) mod face_grid;

use crate::geometry::topology::Topology;
use face_grid::Grid;
pub(crate) use face_grid::Hole;
use glam::{DVec3, Vec3};

/// Cell size of [`grid_with_holes`] (m).
pub(crate) const CELL: f32 = 0.01;
/// Grid size of [`face_grid`].
pub(crate) const FACE_NX: usize = 22;
/// Grid size of [`face_grid`].
pub(crate) const FACE_NY: usize = 17;
/// Eye holes of [`face_grid`], person's left (+x) first: 6 × 2 cells.
pub(crate) const EYES: [Hole; 2] = [(13, 19, 10, 12), (2, 8, 10, 12)];
/// Mouth slit of [`face_grid`]: 9 × 1 cells.
pub(crate) const MOUTH: Hole = (6, 15, 4, 5);

fn checked(grid: Grid) -> (Topology, Vec<Vec3>, Vec<Option<u32>>) {
    let topology = Topology::new(grid.positions.len(), grid.triangles).expect("valid grid");
    (topology, grid.positions, grid.index)
}

/// The fixture's grid with [`CELL`] spacing and gentle bend.
pub(crate) fn grid_with_holes(
    nx: usize,
    ny: usize,
    holes: &[Hole],
    shift: impl Fn(usize, usize) -> Vec3,
) -> (Topology, Vec<Vec3>, Vec<Option<u32>>) {
    checked(face_grid::grid_with_holes(nx, ny, CELL, 2.0, holes, shift))
}

/// A face-like grid: outline, two eye holes and a mouth slit.
pub(crate) fn face_grid() -> (Topology, Vec<Vec3>, Vec<Option<u32>>) {
    checked(face_grid::face_grid(
        FACE_NX, FACE_NY, CELL, 2.0, EYES, MOUTH,
    ))
}

/// A session on `topology` whose template and person are both `neutral`,
/// every template shape and one captured jawOpen stretching it by 5% in y;
/// no stream.
pub(crate) fn stretch_session(topology: Topology, neutral: Vec<Vec3>) -> crate::Session {
    use crate::arkit::{Blendshape, Weights};
    use crate::session::{CapturedExpression, DeviceInfo, SessionParts, Template};
    let stretched: Vec<Vec3> = neutral
        .iter()
        .map(|p| *p * Vec3::new(1.0, 1.05, 1.0))
        .collect();
    let mut weights = Weights::ZERO;
    weights.set(Blendshape::JawOpen, 1.0);
    crate::Session::new(SessionParts {
        device: DeviceInfo::default(),
        frame_rate: 60.0,
        topology,
        template: Template {
            neutral: neutral.clone(),
            shapes: std::array::from_fn(|_| stretched.clone()),
        },
        neutral,
        frames: Vec::new(),
        captures: vec![CapturedExpression {
            prompt: Blendshape::JawOpen,
            frame: None,
            weights,
            vertices: stretched,
        }],
        tests: Vec::new(),
        truth: None,
    })
    .expect("valid session")
}

/// A flat sheet of `columns × rows` unit squares' corners in the
/// xy-plane, two triangles per square, vertex `(i, j)` at index
/// `j · columns + i`: the smallest surface to bend and smooth.
pub(crate) fn flat_sheet(columns: usize, rows: usize) -> (Vec<DVec3>, Vec<[u32; 3]>) {
    let at = |i: usize, j: usize| (j * columns + i) as u32;
    let mut triangles = Vec::new();
    for j in 0..rows - 1 {
        for i in 0..columns - 1 {
            triangles.push([at(i, j), at(i + 1, j), at(i + 1, j + 1)]);
            triangles.push([at(i, j), at(i + 1, j + 1), at(i, j + 1)]);
        }
    }
    let positions = (0..rows)
        .flat_map(|j| (0..columns).map(move |i| DVec3::new(i as f64, j as f64, 0.0)))
        .collect();
    (positions, triangles)
}
