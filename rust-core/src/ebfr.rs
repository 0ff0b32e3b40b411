//! The EBFR baseline: example-based facial rigging (Li, Weise & Pauly 2010),
//! its blendshape-optimization step, run as the paper's §4.1 ran it: with
//! ARKit's known weights, so without Li et al.'s alternation over weights.
//!
//! EBFR fits in gradient space, per triangle `t`. With `E_{i,t} = Q(B₀→S_i) − I`
//! the displacement gradient of captured expression `i` (Sumner's
//! deformation gradient, see [`crate::deformation_gradient`]),
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
//! Constants, from Li et al. 2010 §4: κ = 0.1 and θ = 2; β = 0.5, the value
//! their alternation starts from (they lower it as the weights improve; with
//! known weights there is one step).

use crate::arkit_names::BLENDSHAPE_COUNT;
use crate::blendshape_fit::solve_shared_gram;
use crate::deformation_gradient::RestFrame;
use crate::personalization::{GenericBlendshapes, PersonalizeError};
use crate::session::Session;
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

fn entries(m: DMat3) -> [f64; 9] {
    m.to_cols_array()
}

/// EBFR's 52 delta blendshapes on `generic.neutral`; shapes not flagged in
/// `free` keep their generic shape.
pub fn ebfr_blendshapes(
    session: &Session,
    generic: &GenericBlendshapes,
    free: &[bool; BLENDSHAPE_COUNT],
) -> Result<Vec<Vec<DVec3>>, PersonalizeError> {
    let triangles = generic.transfer.triangles();
    let b0 = &generic.neutral;
    let template_neutral: Vec<DVec3> = session
        .template
        .neutral
        .iter()
        .map(|p| p.as_dvec3())
        .collect();
    let corners = |p: &[DVec3], t: &[u32; 3]| t.map(|v| p[v as usize]);
    let degenerate = |mesh: &'static str, t: usize| {
        crate::deformation_transfer::TransferError::DegenerateTriangle {
            mesh,
            triangle: t,
            vertices: triangles[t],
            is_virtual: t >= generic.transfer.mesh_triangle_count(),
        }
    };
    let mut rest = Vec::with_capacity(triangles.len());
    let mut template_rest = Vec::with_capacity(triangles.len());
    for (t, tri) in triangles.iter().enumerate() {
        rest.push(RestFrame::new(corners(b0, tri)).ok_or_else(|| degenerate("neutral scan", t))?);
        template_rest.push(
            RestFrame::new(corners(&template_neutral, tri))
                .ok_or_else(|| degenerate("template", t))?,
        );
    }
    let free_shapes: Vec<usize> = (0..BLENDSHAPE_COUNT).filter(|j| free[*j]).collect();
    let fixed: Vec<usize> = (0..BLENDSHAPE_COUNT).filter(|j| !free[*j]).collect();
    let nt = triangles.len();
    // Priors D*_{j,t} and weights ω_{j,t}.
    let mut prior = vec![DMat3::ZERO; BLENDSHAPE_COUNT * nt];
    let mut omega = vec![0.0; BLENDSHAPE_COUNT * nt];
    for j in 0..BLENDSHAPE_COUNT {
        let shape: Vec<DVec3> = b0
            .iter()
            .zip(&generic.deltas[j])
            .map(|(p, d)| *p + *d)
            .collect();
        let template_shape: Vec<DVec3> = session.template.shapes[j]
            .iter()
            .map(|p| p.as_dvec3())
            .collect();
        for (t, tri) in triangles.iter().enumerate() {
            prior[j * nt + t] = rest[t].displacement_gradient(corners(&shape, tri));
            let m_a = template_rest[t].displacement_gradient(corners(&template_shape, tri));
            let norm = entries(m_a).iter().map(|x| x * x).sum::<f64>().sqrt();
            omega[j * nt + t] = prior_weight(norm);
        }
    }
    // Examples E_{i,t}, minus the fixed shapes' prior contribution.
    let m = session.captures.len();
    let mut examples = Mat::<f64>::zeros(m, 9 * nt);
    for (i, capture) in session.captures.iter().enumerate() {
        let mesh: Vec<DVec3> = capture.vertices.iter().map(|p| p.as_dvec3()).collect();
        for (t, tri) in triangles.iter().enumerate() {
            let mut e = rest[t].displacement_gradient(corners(&mesh, tri));
            for &j in &fixed {
                e -= f64::from(capture.weights.0[j]) * prior[j * nt + t];
            }
            for (c, x) in entries(e).into_iter().enumerate() {
                examples[(i, 9 * t + c)] = x;
            }
        }
    }
    let w = Mat::from_fn(m, free_shapes.len(), |i, a| {
        f64::from(session.captures[i].weights.0[free_shapes[a]])
    });
    let gram = w.transpose() * &w;
    let cross = w.transpose() * &examples;
    let mut gradients: Vec<Vec<DMat3>> = (0..BLENDSHAPE_COUNT)
        .map(|j| prior[j * nt..(j + 1) * nt].to_vec())
        .collect();
    let k = free_shapes.len();
    let x = solve_shared_gram(
        &gram,
        nt,
        9,
        |t, a| BETA * omega[free_shapes[a] * nt + t],
        |t, a, c| cross[(a, 9 * t + c)],
        |t, a, c| entries(prior[free_shapes[a] * nt + t])[c],
    )
    .map_err(|triangle| crate::blendshape_fit::SingularFit {
        vertex: triangle,
        lambda: BETA,
    })?;
    for t in 0..nt {
        for (a, &j) in free_shapes.iter().enumerate() {
            let e = &x[(t * k + a) * 9..(t * k + a) * 9 + 9];
            gradients[j][t] = DMat3::from_cols_slice(e);
        }
    }
    let mut deltas = generic
        .transfer
        .solve_displacement_gradients(&gradients, &generic.deltas);
    // Uncaptured shapes are exactly the generic ones, not their re-solve.
    for &j in &fixed {
        deltas[j].clone_from(&generic.deltas[j]);
    }
    Ok(deltas)
}
