//! The EBFR baseline: example-based facial rigging (Li, Weise & Pauly 2010),
//! its blendshape-optimization step, run as the paper's §4.1 ran it: with
//! ARKit's known weights, so without Li et al.'s alternation over weights.
//!
//! EBFR fits in gradient space, per triangle `t`. With `E_{i,t} = Q(B₀→S_i) − I`
//! the displacement gradient of captured expression `i` (Sumner's
//! deformation gradient, see [`crate::geometry::deformation_gradient`]),
//! `D*_{j,t} = Q(B₀→B₀+T_j) − I` that of the transferred template (the prior)
//! and `X_{j,t}` the unknown one of blendshape `j`, it minimizes
//!
//! ```text
//! Σ_i ‖E_{i,t} − Σ_j w_ij X_{j,t}‖²_F  +  β Σ_j ω_{j,t} ‖X_{j,t} − D*_{j,t}‖²_F
//! ω_{j,t} = ((1 + ‖M^A_{j,t}‖_F) / (κ + ‖M^A_{j,t}‖_F))^θ
//! ```
//!
//! where `M^A_{j,t}` is the template's own displacement gradient of shape `j`
//! (the template, not the transfer: a triangle the template does not deform
//! is held to the prior with `ω = (1/κ)^θ = 100`). Like the paper's fit, this
//! splits into one small system per triangle with a shared Gram matrix
//! (nine right-hand sides, the entries of the 3 × 3 gradient). The vertex
//! positions of each blendshape then follow from the same Poisson solve as
//! deformation transfer, which is the "indirect" step the paper (§3.2)
//! replaces by fitting positions directly.
//!
//! Closed eyes: the fitted gradients of a blink need not collapse the eye
//! (on the simulated subjects its lids stayed up to 0.8 mm apart), so, as in
//! DT, the lid pairs that the template closes in shape `j` (its contacts, see
//! [`crate::geometry::deformation_transfer`]) are closed in the result: the
//! positions are the Poisson step's minimizer under `x_a = x_b` for each
//! pair, the correction of least gradient energy
//! ([`crate::geometry::deformation_transfer::DeformationTransfer::close_contacts`]).
//!
//! Constants, from Li et al. 2010 §4: κ = 0.1 and θ = 2; β = 0.5, the value
//! their alternation starts from (they lower it as the weights improve; with
//! known weights there is one step).

use super::blendshape_fit::solve_shared_gram;
use super::error::{PersonalizeError, SingularFit, check_size};
use super::generic_blendshapes::{GenericBlendshapes, to_f64};
use crate::arkit::{BLENDSHAPE_COUNT, Blendshapes};
use crate::geometry::deformation_gradient::RestTriangle;
use crate::geometry::deformation_transfer::TransferError;
use crate::session::{Session, Template};
use faer::Mat;
use glam::{DMat3, DVec3};

/// κ of Li et al.'s weight.
pub const KAPPA: f64 = 0.1;

/// θ of Li et al.'s weight.
pub const THETA: f64 = 2.0;

/// β, the weight of the prior term.
pub const BETA: f64 = 0.5;

/// Li et al.'s per-triangle prior weight for a template displacement
/// gradient of Frobenius norm `norm`.
pub fn prior_weight(norm: f64) -> f64 {
    ((1.0 + norm) / (KAPPA + norm)).powf(THETA)
}

// Indexing, throughout this file: the transfer's triangles are checked
// against its vertex count, which `ebfr_blendshapes` checks is that of every
// mesh used (the session's own meshes are checked against its topology);
// per-triangle lists have one entry per triangle of the transfer, per-shape
// ones 52 (the lid contact lists too, checked there), shape indices are
// below 52, and the fitted `x` has `9k` values per triangle.

fn entries(m: DMat3) -> [f64; 9] {
    m.to_cols_array()
}

fn corners(p: &[DVec3], t: &[u32; 3]) -> [DVec3; 3] {
    t.map(|v| p[v as usize])
}

/// Per-triangle quantities indexed `[j * triangles + t]`.
struct PerShape<T> {
    values: Vec<T>,
    triangles: usize,
}

impl<T: Copy> PerShape<T> {
    fn get(&self, j: usize, t: usize) -> T {
        self.values[j * self.triangles + t]
    }
}

/// Every triangle (mesh and virtual) of `mesh`, prepared as a rest triangle.
fn rest_triangles(
    generic: &GenericBlendshapes,
    mesh: &[DVec3],
    name: &'static str,
) -> Result<Vec<RestTriangle>, TransferError> {
    let transfer = &generic.transfer;
    transfer
        .triangles()
        .iter()
        .enumerate()
        .map(|(t, tri)| {
            RestTriangle::new(corners(mesh, tri)).ok_or(TransferError::DegenerateTriangle {
                mesh: name,
                triangle: t,
                vertices: *tri,
                is_virtual: t >= transfer.mesh_triangle_count(),
            })
        })
        .collect()
}

/// The priors `D*_{j,t}` (displacement gradients of the transferred
/// template on `B₀`) and Li et al.'s weights `ω_{j,t}` (from the template's
/// own displacement gradients `M^A_{j,t}`).
fn priors_and_weights(
    generic: &GenericBlendshapes,
    template: &Template,
    rest: &[RestTriangle],
    template_rest: &[RestTriangle],
) -> (PerShape<DMat3>, PerShape<f64>) {
    let triangles = generic.transfer.triangles();
    let nt = triangles.len();
    let mut prior = vec![DMat3::ZERO; BLENDSHAPE_COUNT * nt];
    let mut omega = vec![0.0; BLENDSHAPE_COUNT * nt];
    for (j, template_shape) in template.shapes.iter().enumerate() {
        let shape: Vec<DVec3> = generic
            .shapes
            .neutral()
            .iter()
            .zip(&generic.shapes.deltas()[j])
            .map(|(p, d)| *p + *d)
            .collect();
        let template_shape = to_f64(template_shape);
        for (t, tri) in triangles.iter().enumerate() {
            prior[j * nt + t] = rest[t].displacement_gradient(corners(&shape, tri));
            let m_a = template_rest[t].displacement_gradient(corners(&template_shape, tri));
            let norm = entries(m_a).iter().map(|x| x * x).sum::<f64>().sqrt();
            omega[j * nt + t] = prior_weight(norm);
        }
    }
    (
        PerShape {
            values: prior,
            triangles: nt,
        },
        PerShape {
            values: omega,
            triangles: nt,
        },
    )
}

/// The examples `E_{i,t}` of the captures, minus the contribution of the
/// uncaptured shapes (which keep their prior): one row per capture, nine
/// columns per triangle.
fn example_gradients(
    session: &Session,
    generic: &GenericBlendshapes,
    rest: &[RestTriangle],
    prior: &PerShape<DMat3>,
    uncaptured: &[usize],
) -> Mat<f64> {
    let triangles = generic.transfer.triangles();
    let mut examples = Mat::<f64>::zeros(session.captures.len(), 9 * triangles.len());
    for (i, capture) in session.captures.iter().enumerate() {
        let mesh = to_f64(&capture.vertices);
        for (t, tri) in triangles.iter().enumerate() {
            let mut e = rest[t].displacement_gradient(corners(&mesh, tri));
            for &j in uncaptured {
                e -= f64::from(capture.weights.0[j]) * prior.get(j, t);
            }
            for (c, x) in entries(e).into_iter().enumerate() {
                examples[(i, 9 * t + c)] = x;
            }
        }
    }
    examples
}

/// EBFR's 52 delta blendshapes on the neutral of `generic`; shapes not
/// flagged in `captured` keep their generic shape. `generic` must be made
/// for `session`'s topology ([`PersonalizeError::Size`] otherwise).
pub fn ebfr_blendshapes(
    session: &Session,
    generic: &GenericBlendshapes,
    captured: &[bool; BLENDSHAPE_COUNT],
) -> Result<Blendshapes, PersonalizeError> {
    // These checks make every mesh here fit the transfer's triangles (see
    // the indexing note above).
    let n = generic.transfer.vertex_count();
    check_size(
        || "session vertices".to_string(),
        n,
        session.topology.vertex_count(),
    )?;
    check_size(
        || "generic blendshape vertices".to_string(),
        n,
        generic.shapes.vertex_count(),
    )?;
    check_size(
        || "lid contact lists".to_string(),
        BLENDSHAPE_COUNT,
        generic.contacts.len(),
    )?;
    let rest = rest_triangles(generic, generic.shapes.neutral(), "neutral scan")?;
    let template_rest = rest_triangles(generic, &to_f64(&session.template.neutral), "template")?;
    let (prior, omega) = priors_and_weights(generic, &session.template, &rest, &template_rest);
    let unknowns: Vec<usize> = (0..BLENDSHAPE_COUNT).filter(|j| captured[*j]).collect();
    let uncaptured: Vec<usize> = (0..BLENDSHAPE_COUNT).filter(|j| !captured[*j]).collect();
    let examples = example_gradients(session, generic, &rest, &prior, &uncaptured);

    // Per triangle: (WᵀW + β ω) X = WᵀE + β ω D*, over the captured shapes.
    let w = Mat::from_fn(session.captures.len(), unknowns.len(), |i, a| {
        f64::from(session.captures[i].weights.0[unknowns[a]])
    });
    let gram = w.transpose() * &w;
    let cross = w.transpose() * &examples;
    let nt = prior.triangles;
    let x = solve_shared_gram(
        &gram,
        nt,
        9,
        |t, a| BETA * omega.get(unknowns[a], t),
        |t, a, c| cross[(a, 9 * t + c)],
        |t, a, c| entries(prior.get(unknowns[a], t))[c],
    )
    .map_err(|triangle| SingularFit {
        vertex: triangle,
        lambda: BETA,
    })?;
    let mut gradients: Vec<Vec<DMat3>> = prior.values.chunks(nt).map(<[DMat3]>::to_vec).collect();
    let k = unknowns.len();
    for t in 0..nt {
        for (a, &j) in unknowns.iter().enumerate() {
            let e = &x[(t * k + a) * 9..(t * k + a) * 9 + 9];
            gradients[j][t] = DMat3::from_cols_slice(e);
        }
    }

    // Positions from the fitted gradients: the Poisson solve of DT.
    let mut deltas = generic
        .transfer
        .solve_displacement_gradients(&gradients, generic.shapes.deltas())?;
    // Uncaptured shapes are exactly the generic ones, not their re-solve.
    for &j in &uncaptured {
        deltas[j].clone_from(&generic.shapes.deltas()[j]);
    }
    // Closed eyes: the lid pairs the template closes, closed by the Poisson
    // step's own minimizer under them (module docs).
    for &j in &unknowns {
        generic
            .transfer
            .close_contacts(&mut deltas[j], &generic.contacts[j])?;
    }
    Ok(generic.shapes.with_deltas(deltas)?)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::arkit::Blendshape;
    use crate::geometry::topology::Topology;
    use crate::personalize::generic_blendshapes;
    use crate::test_support::{face_grid, stretch_session};
    use glam::Vec3;

    #[test]
    fn generic_blendshapes_of_another_face_are_an_error_not_a_panic() {
        let (topology, neutral, _) = face_grid();
        let face = stretch_session(topology, neutral);
        let generic = generic_blendshapes(&face).unwrap();
        let mut captured = [false; BLENDSHAPE_COUNT];
        captured[Blendshape::JawOpen.index()] = true;
        assert!(ebfr_blendshapes(&face, &generic, &captured).is_ok());

        let triangle = vec![Vec3::ZERO, Vec3::X * 0.01, Vec3::Y * 0.01];
        let tiny = stretch_session(Topology::new(3, vec![[0, 1, 2]]).unwrap(), triangle);
        assert!(matches!(
            ebfr_blendshapes(&tiny, &generic, &captured),
            Err(PersonalizeError::Size { found: 3, .. })
        ));
    }
}
