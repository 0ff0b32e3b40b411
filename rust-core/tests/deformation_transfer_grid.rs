//! Deformation transfer on a small synthetic face: a curved grid with two
//! eye holes (6 × 2 cells) and a mouth slit (9 × 1 cells). The simulated
//! ARKit mask is exercised in `tests/tests/deformation_transfer.rs`.

use glam::{DMat3, DVec3, Vec3};
use likeness::geometry::deformation_transfer::{Contacts, DeformationTransfer, TransferError};
use likeness::geometry::mesh_boundary::{EyeHole, eye_holes};
use likeness::{GeometryError, SessionError, Template, Topology, TopologyError};

#[path = "../src/test_support/face_grid.rs"]
mod face_grid;

/// Grid size (vertices) and cell size (m).
const NX: usize = 22;
const NY: usize = 17;
const CELL: f64 = 0.01;
/// Eye holes as cells `i0..i1 × j0..j1`, the person's left (+x) first.
const EYES: [(usize, usize, usize, usize); 2] = [(13, 19, 10, 12), (2, 8, 10, 12)];
const MOUTH: (usize, usize, usize, usize) = (6, 15, 4, 5);

struct Face {
    topology: Topology,
    rest: Vec<DVec3>,
    eyes: [EyeHole; 2],
    virtual_triangles: Vec<[u32; 3]>,
    /// Index of grid vertex (i, j), if used.
    index: Vec<Option<u32>>,
}

/// The synthetic face of the shared fixture.
fn face() -> Face {
    let grid = face_grid::face_grid(NX, NY, CELL as f32, 2.0, EYES, MOUTH);
    let rest: Vec<DVec3> = grid.positions.iter().map(|p| p.as_dvec3()).collect();
    let index = grid.index;
    let topology = Topology::new(rest.len(), grid.triangles).unwrap();
    let rest_f32: Vec<Vec3> = rest.iter().map(|p| p.as_vec3()).collect();
    let eyes = eye_holes(&topology, &rest_f32).unwrap();
    let virtual_triangles = eyes.iter().flat_map(|e| e.triangles.clone()).collect();
    Face {
        topology,
        rest,
        eyes,
        virtual_triangles,
        index,
    }
}

/// A smooth bulge: a displacement fading over 3 cm around a point.
fn bulge(rest: &[DVec3]) -> Vec<DVec3> {
    let centre = DVec3::new(0.03, -0.02, 0.0);
    rest.iter()
        .map(|p| {
            let t = ((p.truncate() - centre.truncate()).length() / 0.03).min(1.0);
            *p + (1.0 - t * t).powi(3) * DVec3::new(0.004, 0.006, 0.003)
        })
        .collect()
}

/// Closes the left eye: each upper-lid vertex moves onto the lower-lid
/// vertex below it; the skin above follows for three rows, less and less.
fn blink(face: &Face, rest: &[DVec3]) -> Vec<DVec3> {
    blink_to(face, rest, 1.0)
}

/// [`blink`], with the upper lid travelling only the fraction `closed` of
/// the way down.
fn blink_to(face: &Face, rest: &[DVec3], closed: f64) -> Vec<DVec3> {
    let (i0, i1, j0, j1) = EYES[0];
    let at = |i: usize, j: usize| face.index[j * NX + i].unwrap() as usize;
    let mut out = rest.to_vec();
    for i in i0..=i1 {
        let travel = closed * (rest[at(i, j0)] - rest[at(i, j1)]);
        for j in j1..j1 + 3 {
            let w = 1.0 - (j - j1) as f64 / 3.0;
            out[at(i, j)] += w * travel;
        }
    }
    out
}

fn displacement(shape: &[DVec3], rest: &[DVec3]) -> Vec<DVec3> {
    shape.iter().zip(rest).map(|(s, r)| *s - *r).collect()
}

/// max ‖a − b‖ / max ‖b‖.
fn relative_error(a: &[DVec3], b: &[DVec3]) -> f64 {
    let err = a
        .iter()
        .zip(b)
        .map(|(x, y)| x.distance(*y))
        .fold(0.0, f64::max);
    err / b.iter().map(|y| y.length()).fold(0.0, f64::max)
}

#[test]
fn transfer_onto_the_source_itself_reproduces_the_source() {
    let face = face();
    let dt = DeformationTransfer::new(&face.topology, &face.virtual_triangles, &face.rest).unwrap();
    let shapes = [bulge(&face.rest), blink(&face, &face.rest)];
    let deltas = dt.transfer_many(&face.rest, &shapes).unwrap();
    for (delta, shape) in deltas.iter().zip(&shapes) {
        let err = relative_error(delta, &displacement(shape, &face.rest));
        eprintln!("relative error {err:.2e}");
        assert!(err < 1e-9, "relative error {err:e}");
    }
}

#[test]
fn zero_deformation_gives_exactly_zero() {
    let face = face();
    let dt = DeformationTransfer::new(&face.topology, &face.virtual_triangles, &face.rest).unwrap();
    let delta = dt.transfer(&face.rest, &face.rest).unwrap();
    assert!(delta.iter().all(|d| *d == DVec3::ZERO));
}

#[test]
fn a_scaled_and_moved_target_gets_scaled_displacements() {
    let face = face();
    let s = 1.7;
    let target: Vec<DVec3> = face
        .rest
        .iter()
        .map(|p| s * *p + DVec3::new(0.1, -0.2, 0.3))
        .collect();
    let dt = DeformationTransfer::new(&face.topology, &face.virtual_triangles, &target).unwrap();
    for shape in [bulge(&face.rest), blink(&face, &face.rest)] {
        let delta = dt.transfer(&face.rest, &shape).unwrap();
        let expected: Vec<DVec3> = displacement(&shape, &face.rest)
            .iter()
            .map(|d| s * *d)
            .collect();
        let err = relative_error(&delta, &expected);
        eprintln!("relative error {err:.2e}");
        assert!(err < 1e-9, "relative error {err:e}");
    }
}

/// Widest distance between an upper-lid vertex and the lower-lid vertex
/// below it after `delta`, and the widest opening before.
fn lid_gap(face: &Face, target: &[DVec3], delta: &[DVec3]) -> (f64, f64) {
    let eye = &face.eyes[0];
    let moved = |v: u32| target[v as usize] + delta[v as usize];
    let pairs = || (1..eye.upper.len() - 1).map(|k| (eye.upper[k], eye.lower[k]));
    let gap = pairs()
        .map(|(u, l)| moved(u).distance(moved(l)))
        .fold(0.0, f64::max);
    let open = pairs()
        .map(|(u, l)| target[u as usize].distance(target[l as usize]))
        .fold(0.0, f64::max);
    (gap, open)
}

/// Another face: other proportions, turned a little, with ripples.
fn other_face(face: &Face) -> Vec<DVec3> {
    let turn = DMat3::from_rotation_y(0.1) * DMat3::from_diagonal(DVec3::new(1.08, 0.93, 1.2));
    face.rest
        .iter()
        .map(|p| {
            turn * *p + DVec3::new(0.002 * (40.0 * p.y).sin(), 0.0, 0.004 * (30.0 * p.x).sin())
        })
        .collect()
}

#[test]
fn a_blink_closes_the_eye_of_a_different_face() {
    let face = face();
    let target = other_face(&face);
    let dt = DeformationTransfer::new(&face.topology, &face.virtual_triangles, &target).unwrap();
    let source = blink(&face, &face.rest);
    let delta = dt.transfer(&face.rest, &source).unwrap();
    let (gap, open) = lid_gap(&face, &target, &delta);
    eprintln!("with contacts: lid gap {gap:.2e} m of {open:.2e} m");
    assert!(gap < 1e-9 * open, "gap {gap:e} m of {open:e} m");
    // The other eye stays nearly put.
    let right = &face.eyes[1];
    let largest = delta.iter().map(|d| d.length()).fold(0.0, f64::max);
    let drift = right
        .upper
        .iter()
        .chain(&right.lower)
        .map(|&v| delta[v as usize].length())
        .fold(0.0, f64::max);
    eprintln!("other eye moves {drift:.2e} m, largest motion {largest:.2e} m");
    assert!(drift < 0.02 * largest);

    // Without contacts the virtual triangles alone leave it a little open.
    let plain = dt
        .with_contacts(false)
        .transfer(&face.rest, &source)
        .unwrap();
    let (plain_gap, _) = lid_gap(&face, &target, &plain);
    eprintln!("without contacts: lid gap {plain_gap:.2e} m of {open:.2e} m");
    assert!(plain_gap > gap);
}

#[test]
fn an_eye_closes_when_the_source_lids_come_within_15_percent_of_its_opening() {
    // The grid's eye is 2 cm open; its lid pairs are the 7 columns. The rule
    // is a fraction of the opening, so it reads the same in centimetres.
    let face = face();
    for scale in [1.0, 100.0] {
        let rest: Vec<DVec3> = face.rest.iter().map(|p| scale * *p).collect();
        let target: Vec<DVec3> = other_face(&face).iter().map(|p| scale * *p).collect();
        let dt =
            DeformationTransfer::new(&face.topology, &face.virtual_triangles, &target).unwrap();
        for (closed, pairs) in [(1.0, 7), (0.95, 7), (0.86, 7), (0.84, 0), (0.5, 0)] {
            let source = blink_to(&face, &rest, closed);
            let contacts = dt.contacts(&rest, &source).unwrap();
            assert_eq!(
                contacts.pairs().len(),
                pairs,
                "closed {closed}, scale {scale}"
            );
            let delta = dt.transfer(&rest, &source).unwrap();
            let (gap, open) = lid_gap(&face, &target, &delta);
            eprintln!(
                "scale {scale}, lids {closed} closed: target lid gap {gap:.2e} of {open:.2e}"
            );
            if pairs > 0 {
                assert!(gap < 1e-9 * open, "gap {gap:e} of {open:e}");
            } else {
                assert!(gap > 0.1 * open, "gap {gap:e} of {open:e}");
            }
        }
    }
}

#[test]
fn close_contacts_closes_any_field_and_refuses_another_faces_contacts() {
    let face = face();
    let target = other_face(&face);
    let dt = DeformationTransfer::new(&face.topology, &face.virtual_triangles, &target).unwrap();
    let source = blink_to(&face, &face.rest, 0.97);
    let contacts = dt.contacts(&face.rest, &source).unwrap();
    let mut delta = dt
        .clone()
        .with_contacts(false)
        .transfer(&face.rest, &source)
        .unwrap();
    let (open_gap, open) = lid_gap(&face, &target, &delta);
    dt.close_contacts(&mut delta, &contacts).unwrap();
    let (gap, _) = lid_gap(&face, &target, &delta);
    eprintln!("plain transfer: lid gap {open_gap:.2e}, closed {gap:.2e} of {open:.2e}");
    assert!(open_gap > 1e-4 * open && gap < 1e-9 * open);
    // No contacts: nothing changes.
    let none = dt.contacts(&face.rest, &bulge(&face.rest)).unwrap();
    assert!(none.is_empty());
    let before = delta.clone();
    dt.close_contacts(&mut delta, &none).unwrap();
    assert_eq!(delta, before);
    // Contacts of a mesh with other vertices, and fields of the wrong size.
    let small = small_face_contacts();
    assert!(matches!(
        dt.close_contacts(&mut delta, &small),
        Err(TransferError::Geometry(GeometryError::VertexCount { .. }))
    ));
    assert!(dt.close_contacts(&mut delta[1..], &contacts).is_err());
    assert!(dt.contacts(&face.rest, &source[1..]).is_err());
}

/// The contacts of a smaller face's blink (a 12 × 10 grid with smaller
/// eyes).
fn small_face_contacts() -> Contacts {
    let eyes = [(7, 10, 5, 7), (1, 4, 5, 7)];
    let grid = face_grid::face_grid(12, 10, CELL as f32, 2.0, eyes, (3, 9, 2, 3));
    let rest: Vec<DVec3> = grid.positions.iter().map(|p| p.as_dvec3()).collect();
    let topology = Topology::new(rest.len(), grid.triangles).unwrap();
    let rest_f32: Vec<Vec3> = rest.iter().map(|p| p.as_vec3()).collect();
    let holes = eye_holes(&topology, &rest_f32).unwrap();
    let virtual_triangles: Vec<[u32; 3]> = holes.iter().flat_map(|e| e.triangles.clone()).collect();
    let dt = DeformationTransfer::new(&topology, &virtual_triangles, &rest).unwrap();
    // Close the left eye's lids onto each other.
    let mut shut = rest.clone();
    let eye = &holes[0];
    for (&u, &l) in eye.upper.iter().zip(&eye.lower) {
        shut[u as usize] = rest[l as usize];
    }
    let contacts = dt.contacts(&rest, &shut).unwrap();
    assert!(!contacts.is_empty());
    contacts
}

#[test]
fn separate_pieces_keep_their_own_translation() {
    // Two disjoint triangles, each moved rigidly by its own translation:
    // every vertex moves equally, so the least-moving vertex of each piece
    // fixes its translation.
    let topology = Topology::new(6, vec![[0, 1, 2], [3, 4, 5]]).unwrap();
    let rest = [
        DVec3::ZERO,
        DVec3::X,
        DVec3::Y,
        DVec3::Z,
        DVec3::ONE,
        DVec3::X,
    ];
    let t = [DVec3::new(0.1, 0.0, 0.0), DVec3::new(0.0, -0.2, 0.05)];
    let moved: Vec<DVec3> = rest
        .iter()
        .enumerate()
        .map(|(v, p)| *p + t[v / 3])
        .collect();
    let dt = DeformationTransfer::new(&topology, &[], &rest).unwrap();
    let delta = dt.transfer(&rest, &moved).unwrap();
    for (v, d) in delta.iter().enumerate() {
        assert!(d.distance(t[v / 3]) < 1e-15, "vertex {v}: {d}");
    }
}

#[test]
fn solving_the_transferred_gradients_gives_the_transfer_back() {
    let face = face();
    let target: Vec<DVec3> = face
        .rest
        .iter()
        .map(|p| *p * DVec3::new(1.1, 0.9, 1.0))
        .collect();
    let dt = DeformationTransfer::new(&face.topology, &face.virtual_triangles, &target)
        .unwrap()
        .with_contacts(false);
    let delta = dt.transfer(&face.rest, &bulge(&face.rest)).unwrap();
    let deformed: Vec<DVec3> = target.iter().zip(&delta).map(|(p, d)| *p + *d).collect();
    let gradients: Vec<DMat3> = dt
        .triangles()
        .iter()
        .map(|t| {
            let frame = likeness::geometry::deformation_gradient::RestTriangle::new(
                t.map(|v| target[v as usize]),
            )
            .unwrap();
            frame.displacement_gradient(t.map(|v| deformed[v as usize]))
        })
        .collect();
    let again = dt
        .solve_displacement_gradients(
            std::slice::from_ref(&gradients),
            std::slice::from_ref(&delta),
        )
        .unwrap();
    let err = relative_error(&again[0], &delta);
    eprintln!("relative error {err:.2e}");
    assert!(err < 1e-9, "relative error {err:e}");
}

#[test]
fn bad_input_gives_typed_errors() {
    let face = face();
    let dt = DeformationTransfer::new(&face.topology, &face.virtual_triangles, &face.rest).unwrap();
    let mut nan = face.rest.clone();
    nan[17].z = f64::NAN;
    let err = dt.transfer_many(&face.rest, &[face.rest.clone(), nan.clone()]);
    assert_eq!(
        err,
        Err(TransferError::Geometry(GeometryError::NotFinite {
            what: "source shape 1".into(),
            vertex: 17
        }))
    );
    assert!(matches!(
        DeformationTransfer::new(&face.topology, &[], &nan),
        Err(TransferError::Geometry(GeometryError::NotFinite {
            vertex: 17,
            ..
        }))
    ));
    let err = dt.transfer(&face.rest, &face.rest[1..]).unwrap_err();
    assert!(
        err.to_string().contains("vertices, but the topology has"),
        "{err}"
    );

    // A mesh triangle with zero area.
    let mut flat = face.rest.clone();
    let [a, b, _] = face.topology.triangles()[5];
    flat[a as usize] = flat[b as usize];
    let first = face
        .topology
        .triangles()
        .iter()
        .position(|t| t.contains(&a) && t.contains(&b))
        .unwrap();
    match DeformationTransfer::new(&face.topology, &[], &flat) {
        Err(TransferError::DegenerateTriangle {
            mesh: "target rest",
            triangle,
            is_virtual: false,
            ..
        }) => assert_eq!(triangle, first),
        other => panic!("{other:?}"),
    }
    // A virtual triangle with zero area: an upper-lid vertex on the lower lid.
    let mut shut = face.rest.clone();
    let eye = &face.eyes[0];
    shut[eye.upper[3] as usize] = shut[eye.lower[3] as usize];
    let err = DeformationTransfer::new(&face.topology, &face.virtual_triangles, &shut).unwrap_err();
    assert!(
        matches!(
            err,
            TransferError::DegenerateTriangle {
                is_virtual: true,
                ..
            }
        ),
        "{err}"
    );
    assert!(
        err.to_string().starts_with("target rest: virtual triangle"),
        "{err}"
    );
    // The same as a source rest mesh.
    let err = dt.transfer(&shut, &face.rest).unwrap_err();
    assert!(
        err.to_string().starts_with("source rest: virtual triangle"),
        "{err}"
    );

    // Virtual triangles must index existing vertices.
    let n = face.topology.vertex_count() as u32;
    assert!(matches!(
        DeformationTransfer::new(&face.topology, &[[0, 1, n]], &face.rest),
        Err(TransferError::Topology(
            TopologyError::IndexOutOfRange { .. }
        ))
    ));
    // A template must have 52 shapes.
    assert_eq!(
        Template::new(
            vec![Vec3::ZERO; n as usize],
            vec![vec![Vec3::ZERO; n as usize]; 3]
        ),
        Err(SessionError::TemplateShapeCount(3))
    );
    // Gradients for a Poisson solve: one per triangle, one reference per shape.
    let triangles = dt.triangles().len();
    let zero_field = vec![DVec3::ZERO; n as usize];
    assert_eq!(
        dt.solve_displacement_gradients(
            &[vec![DMat3::ZERO; triangles - 1]],
            std::slice::from_ref(&zero_field)
        ),
        Err(TransferError::ShapeMismatch {
            shape: 0,
            what: "gradients",
            expected: triangles,
            found: triangles - 1,
        })
    );
    assert!(matches!(
        dt.solve_displacement_gradients(&[vec![DMat3::ZERO; triangles]], &[]),
        Err(TransferError::ShapeMismatch { .. })
    ));
    assert!(matches!(
        dt.solve_displacement_gradients(&[vec![DMat3::ZERO; triangles]], &[vec![DVec3::ZERO; 3]]),
        Err(TransferError::Geometry(GeometryError::VertexCount { .. }))
    ));
}
