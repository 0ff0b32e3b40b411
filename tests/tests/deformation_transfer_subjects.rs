//! Deformation transfer of the generic template onto simulated faces (the
//! paper's generic blendshapes `T_j`, §3.2), with virtual eye triangles.

//!
//! This crate does not depend on `glam`, so the helpers below work on
//! `[f64; 3]` arrays and let inference name the vector types.

use likeness::geometry::deformation_transfer::{DeformationTransfer, TransferError};
use likeness::geometry::mesh_boundary::eye_hole_triangles;
use likeness::geometry::topology::GeometryError;
use likeness::personalize::generic_blendshapes::transfer_template;
use likeness::{BLENDSHAPE_COUNT, Blendshape, Template};
use likeness_sim::face_mask::face_mask;
use likeness_sim::subject::Subject;
use likeness_sim::template::generic_template;

type P = [f64; 3];

fn sub(a: P, b: P) -> P {
    [a[0] - b[0], a[1] - b[1], a[2] - b[2]]
}

fn add(a: P, b: P) -> P {
    [a[0] + b[0], a[1] + b[1], a[2] + b[2]]
}

fn norm(a: P) -> f64 {
    (a[0] * a[0] + a[1] * a[1] + a[2] * a[2]).sqrt()
}

/// The template's delta blendshapes in f64.
fn template_deltas(template: &Template) -> Vec<Vec<P>> {
    template
        .shapes
        .iter()
        .map(|s| {
            s.iter()
                .zip(&template.neutral)
                .map(|(a, b)| sub(a.as_dvec3().to_array(), b.as_dvec3().to_array()))
                .collect()
        })
        .collect()
}

/// max_i ‖a_i − b_i‖ / max_i ‖b_i‖ (the plain error when `b` is zero).
fn relative_error(a: &[P], b: &[P]) -> f64 {
    let err = a
        .iter()
        .zip(b)
        .map(|(x, y)| norm(sub(*x, *y)))
        .fold(0.0, f64::max);
    let size = b.iter().map(|y| norm(*y)).fold(0.0, f64::max);
    if size == 0.0 { err } else { err / size }
}

/// The template's 52 shapes transferred onto `$neutral` (a `Vec<DVec3>`,
/// with the virtual eye triangles, contacts on or off), as `[f64; 3]` deltas.
/// A macro, so that the vector type need not be named.
macro_rules! transfer_onto {
    ($neutral:expr) => {
        transfer_onto!($neutral, true)
    };
    ($neutral:expr, $contacts:expr) => {{
        let mask = face_mask();
        let eyes =
            eye_hole_triangles(&mask.topology, &mask.neutral).expect("the mask has two eyes");
        let dt = DeformationTransfer::new(&mask.topology, &eyes, &$neutral)
            .expect("factors")
            .with_contacts($contacts);
        transfer_template(&dt, &generic_template())
            .expect("transfers")
            .iter()
            .map(|d| d.iter().map(|p| p.to_array()).collect::<Vec<P>>())
            .collect::<Vec<_>>()
    }};
}

#[test]
fn the_mask_has_two_eyes_of_virtual_triangles() {
    let mask = face_mask();
    let eyes = likeness::geometry::mesh_boundary::eye_holes(&mask.topology, &mask.neutral).unwrap();
    for (side, eye) in eyes.iter().enumerate() {
        // Lids of 9 vertices plus the two corners; the loop of 20 gives 18.
        assert_eq!(eye.upper.len(), 11);
        assert_eq!(eye.lower.len(), 11);
        assert_eq!(eye.triangles.len(), 18);
        let corners = [
            mask.landmarks.eye_inner[side],
            mask.landmarks.eye_outer[side],
        ];
        let ends = [eye.upper[0], eye.upper[10]];
        assert!(corners.contains(&ends[0]) && corners.contains(&ends[1]));
        let mut upper = eye.upper[1..10].to_vec();
        let mut expected = mask.landmarks.upper_lid[side].clone();
        upper.sort_unstable();
        expected.sort_unstable();
        assert_eq!(upper, expected, "side {side}");
        for t in &eye.triangles {
            let [a, b, c] = t.map(|v| mask.neutral[v as usize]);
            assert!((b - a).cross(c - a).z > 0.0, "{t:?} faces away");
        }
    }
}

#[test]
fn transfer_onto_the_template_itself_reproduces_its_deltas() {
    let template = generic_template();
    let neutral: Vec<_> = template.neutral.iter().map(|p| p.as_dvec3()).collect();
    let deltas = transfer_onto!(neutral);
    let expected = template_deltas(&template);
    let worst = deltas
        .iter()
        .zip(&expected)
        .map(|(d, e)| relative_error(d, e))
        .fold(0.0, f64::max);
    eprintln!("template onto itself: worst relative error {worst:.2e}");
    assert!(worst < 1e-9, "worst relative error {worst:e}");
}

#[test]
fn a_uniformly_scaled_target_gets_scaled_deltas() {
    let template = generic_template();
    let s = 1.25;
    let scaled: Vec<_> = template.neutral.iter().map(|p| s * p.as_dvec3()).collect();
    let deltas = transfer_onto!(scaled);
    let worst = deltas
        .iter()
        .zip(template_deltas(&template))
        .map(|(d, e)| {
            let e: Vec<P> = e.iter().map(|v| v.map(|c| s * c)).collect();
            relative_error(d, &e)
        })
        .fold(0.0, f64::max);
    eprintln!("template scaled by {s}: worst relative error {worst:.2e}");
    assert!(worst < 1e-9, "worst relative error {worst:e}");
}

#[test]
fn zero_deltas_transfer_to_zero() {
    let mask = face_mask();
    let eyes = eye_hole_triangles(&mask.topology, &mask.neutral).unwrap();
    let subject = Subject::from_seed(3).model.neutral;
    let dt = DeformationTransfer::new(&mask.topology, &eyes, &subject).unwrap();
    let neutral: Vec<_> = mask.neutral.iter().map(|p| p.as_dvec3()).collect();
    let delta = dt.transfer(&neutral, &neutral).unwrap();
    assert!(delta.iter().all(|d| d.to_array() == [0.0; 3]));
}

/// Widest distance between an upper-lid vertex and its lower-lid partner
/// (the vertex the simulator's own blink puts it on) after `delta`.
fn widest_lid_gap(side: usize, rest: &[P], delta: &[P]) -> f64 {
    let lm = &face_mask().landmarks;
    let closed = |v: u32| add(rest[v as usize], delta[v as usize]);
    lm.upper_lid[side]
        .iter()
        .zip(&lm.lower_lid[side])
        .map(|(&u, &l)| norm(sub(closed(u), closed(l))))
        .fold(0.0, f64::max)
}

#[test]
fn a_transferred_blink_closes_a_subjects_eye() {
    let blinks = [Blendshape::EyeBlinkLeft, Blendshape::EyeBlinkRight];
    let mut worst = 0.0_f64;
    for seed in [1, 2, 3, 4, 5] {
        let neutral = Subject::from_seed(seed).model.neutral;
        let rest: Vec<P> = neutral.iter().map(|p| p.to_array()).collect();
        let deltas = transfer_onto!(neutral);
        let plain = transfer_onto!(neutral, false);
        for (side, shape) in blinks.into_iter().enumerate() {
            let open = widest_lid_gap(side, &rest, &vec![[0.0; 3]; rest.len()]);
            let gap = widest_lid_gap(side, &rest, &deltas[shape.index()]);
            let plain_gap = widest_lid_gap(side, &rest, &plain[shape.index()]);
            eprintln!(
                "subject {seed} {shape}: widest lid gap {:.2e} mm, {:.3} mm without contacts \
                 (open {:.2} mm)",
                gap * 1e3,
                plain_gap * 1e3,
                open * 1e3
            );
            assert!(gap < 1e-4, "subject {seed} {shape}: lid gap {gap:e} m");
            worst = worst.max(gap);
        }
        // Contacts change the blinks only.
        for (j, (d, p)) in deltas.iter().zip(&plain).enumerate() {
            if !blinks.contains(&Blendshape::ALL[j]) {
                assert_eq!(d, p, "{}", Blendshape::ALL[j]);
            }
        }
    }
    eprintln!("worst lid gap over five subjects: {:.2e} mm", worst * 1e3);
}

#[test]
fn all_52_shapes_transfer_to_finite_deltas_that_keep_still_regions_nearly_still() {
    let template = generic_template();
    let neutral = Subject::from_seed(2).model.neutral;
    let deltas = transfer_onto!(neutral);
    assert_eq!(deltas.len(), BLENDSHAPE_COUNT);
    for (j, (delta, source)) in deltas.iter().zip(template_deltas(&template)).enumerate() {
        assert!(delta.iter().flatten().all(|c| c.is_finite()));
        let largest = source.iter().map(|d| norm(*d)).fold(0.0, f64::max);
        // Where the template does not move at all, the transfer moves little.
        let drift = source
            .iter()
            .zip(delta)
            .filter(|(s, _)| **s == [0.0; 3])
            .map(|(_, d)| norm(*d))
            .fold(0.0, f64::max);
        eprintln!(
            "{}: largest template motion {:.2} mm, largest drift where it is still {:.3} mm",
            Blendshape::ALL[j],
            largest * 1e3,
            drift * 1e3
        );
        assert!(drift < 0.1 * largest, "{}", Blendshape::ALL[j]);
    }
}

#[test]
fn nan_positions_are_typed_errors() {
    let mask = face_mask();
    let eyes = eye_hole_triangles(&mask.topology, &mask.neutral).unwrap();
    let mut neutral = Subject::from_seed(1).model.neutral;
    neutral[600].x = f64::NAN;
    let err = DeformationTransfer::new(&mask.topology, &eyes, &neutral).unwrap_err();
    assert_eq!(
        err,
        TransferError::Geometry(GeometryError::NotFinite {
            what: "target rest".into(),
            vertex: 600
        })
    );
    let mut template = generic_template();
    template.shapes[5][42].y = f32::INFINITY;
    neutral[600].x = 0.0;
    let dt = DeformationTransfer::new(&mask.topology, &eyes, &neutral).unwrap();
    let err = transfer_template(&dt, &template).unwrap_err();
    assert_eq!(
        err.to_string(),
        "source shape 5: vertex 42 has a NaN or infinite coordinate"
    );
}
