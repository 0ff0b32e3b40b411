use super::*;
use crate::arkit::{BLENDSHAPE_COUNT, Blendshapes};
use crate::personalize::blendshape_fit::Observation;
use faer::Mat;
use glam::{DVec3, Vec3};

/// A tiny problem: 6 vertices, 4 captured shapes, 7 observations with
/// unequal importances, Eq. (3)-like weights that differ per vertex.
struct Tiny {
    generic: Blendshapes,
    weights: Vec<Vec<f64>>,
    captured: [bool; BLENDSHAPE_COUNT],
    ws: Vec<[f64; BLENDSHAPE_COUNT]>,
    meshes: Vec<Vec<Vec3>>,
    importance: Vec<f64>,
}

fn wave(x: f64) -> f64 {
    (x * 12.9898).sin() * 0.5 + (x * 4.1414).cos() * 0.5
}

fn tiny() -> Tiny {
    let n = 6;
    let neutral: Vec<DVec3> = (0..n).map(|v| DVec3::splat(v as f64 * 0.01)).collect();
    let deltas: Vec<Vec<DVec3>> = (0..BLENDSHAPE_COUNT)
        .map(|j| {
            (0..n)
                .map(|v| {
                    let x = (j * 7 + v * 3) as f64;
                    DVec3::new(wave(x), wave(x + 0.3), wave(x + 0.7)) * 1e-3
                })
                .collect()
        })
        .collect();
    let generic = Blendshapes::new(neutral.clone(), deltas).unwrap();
    let weights: Vec<Vec<f64>> = (0..BLENDSHAPE_COUNT)
        .map(|j| (0..n).map(|v| 1.0 + ((j + 2 * v) % 5) as f64).collect())
        .collect();
    let mut captured = [false; BLENDSHAPE_COUNT];
    for j in [2, 5, 11, 30] {
        captured[j] = true;
    }
    let ws: Vec<[f64; BLENDSHAPE_COUNT]> = (0..7)
        .map(|i| std::array::from_fn(|j| 0.5 + 0.5 * wave((i * 52 + j) as f64)))
        .collect();
    let meshes: Vec<Vec<Vec3>> = (0..7)
        .map(|i| {
            (0..n)
                .map(|v| {
                    let x = (i * 13 + v * 5) as f64;
                    (neutral[v] + DVec3::new(wave(x), wave(x + 1.1), wave(x + 2.3)) * 2e-3)
                        .as_vec3()
                })
                .collect()
        })
        .collect();
    let importance = vec![1.0, 0.5, 2.0, 1.0, 0.25, 1.0, 1.5];
    Tiny {
        generic,
        weights,
        captured,
        ws,
        meshes,
        importance,
    }
}

/// Natural logarithm of the determinant of a symmetric positive definite
/// matrix, and the solution of `M x = b`, by plain Gaussian elimination.
fn log_det_and_solve(m: &Mat<f64>, b: &Mat<f64>) -> (f64, Mat<f64>) {
    let n = m.nrows();
    let mut a = m.clone();
    let mut x = b.clone();
    let mut log_det = 0.0;
    for p in 0..n {
        log_det += a[(p, p)].ln();
        for i in p + 1..n {
            let f = a[(i, p)] / a[(p, p)];
            for j in p..n {
                a[(i, j)] -= f * a[(p, j)];
            }
            for c in 0..x.ncols() {
                x[(i, c)] -= f * x[(p, c)];
            }
        }
    }
    for p in (0..n).rev() {
        for c in 0..x.ncols() {
            let mut s = x[(p, c)];
            for j in p + 1..n {
                s -= a[(p, j)] * x[(j, c)];
            }
            x[(p, c)] = s / a[(p, p)];
        }
    }
    (log_det, x)
}

/// Brute force: per vertex and axis, the m × m covariance `K = I + W
/// (λD²)⁻¹ Wᵀ` formed explicitly, `y'ᵀK⁻¹y'` and `ln det K` by
/// elimination; the hat matrix `H = W (WᵀW + λD²)⁻¹ Wᵀ` likewise.
fn brute_force(t: &Tiny, lambda: f64) -> RidgeTerms {
    let unknowns: Vec<usize> = (0..BLENDSHAPE_COUNT).filter(|j| t.captured[*j]).collect();
    let (m, k, n) = (t.ws.len(), unknowns.len(), t.generic.vertex_count());
    let w = Mat::from_fn(m, k, |i, a| t.importance[i].sqrt() * t.ws[i][unknowns[a]]);
    let mut terms = RidgeTerms {
        lambda,
        coordinates: 3 * n,
        observations: m,
        log_det: Some(0.0),
        ..RidgeTerms::default()
    };
    for v in 0..n {
        let d2: Vec<f64> = unknowns.iter().map(|&j| t.weights[j][v].powi(2)).collect();
        let k_mat = Mat::from_fn(m, m, |i, l| {
            let prior: f64 = (0..k)
                .map(|a| w[(i, a)] * w[(l, a)] / (lambda * d2[a]))
                .sum();
            prior + if i == l { 1.0 } else { 0.0 }
        });
        let a_mat = Mat::from_fn(k, k, |a, b| {
            (0..m).map(|i| w[(i, a)] * w[(i, b)]).sum::<f64>()
                + if a == b { lambda * d2[a] } else { 0.0 }
        });
        let (_, a_inv) = log_det_and_solve(&a_mat, &Mat::identity(k, k));
        let hat = &w * &a_inv * w.transpose();
        let mut vertex_energy = 0.0;
        for axis in 0..3 {
            let y = Mat::from_fn(m, 1, |i, _| {
                let o = &t.ws[i];
                let mut x = f64::from(t.meshes[i][v][axis]) - t.generic.neutral()[v][axis];
                for (wj, tj) in o.iter().zip(t.generic.deltas()) {
                    x -= wj * tj[v][axis];
                }
                t.importance[i].sqrt() * x
            });
            let (log_det, solved) = log_det_and_solve(&k_mat, &y);
            vertex_energy += (y.transpose() * &solved)[(0, 0)];
            *terms.log_det.as_mut().unwrap() += log_det;
            let fitted = &y - &hat * &y;
            terms.residual += fitted.squared_norm_l2();
            terms.residual_dof += (0..m).map(|i| 1.0 - hat[(i, i)]).sum::<f64>();
        }
        terms.energy += vertex_energy;
    }
    terms
}

#[test]
fn the_criteria_from_the_tridiagonal_form_equal_the_brute_force_ones() {
    let t = tiny();
    let observations: Vec<Observation> =
        t.ws.iter()
            .zip(&t.meshes)
            .zip(&t.importance)
            .map(|((w, m), c)| Observation {
                weights: *w,
                vertices: m,
                importance: *c,
            })
            .collect();
    let fit = BlendshapeFit::new(&t.generic, &t.weights, &t.captured, &observations);
    let all = RidgeCriteria::on_vertices(&fit, (0..6).collect());
    assert_eq!(all.vertices(), RidgeCriteria::new(&fit).vertices());
    for lambda in [1e-8, 1e-6, 1e-3, 0.1, 1.0, 30.0] {
        #[cfg(feature = "study")]
        let fast = all.terms_with_log_det(lambda).unwrap();
        #[cfg(not(feature = "study"))]
        let fast = all.terms(lambda).unwrap();
        let slow = brute_force(&t, lambda);
        // The brute force's K has entries up to 1/λ: at λ = 1e-8 it is
        // itself good to only about eight digits.
        let tol = if lambda < 1e-6 { 1e-7 } else { 1e-9 };
        let close = |a: f64, b: f64| (a - b).abs() <= tol * a.abs().max(b.abs()).max(1e-12);
        assert!(close(fast.energy, slow.energy), "{fast:?} vs {slow:?}");
        assert!(close(fast.residual, slow.residual), "{fast:?} vs {slow:?}");
        #[cfg(feature = "study")]
        {
            let (fl, sl) = (fast.log_det.unwrap(), slow.log_det.unwrap());
            assert!(
                (fl - sl).abs() < tol * sl.abs().max(1.0),
                "{fast:?} vs {slow:?}"
            );
            assert!((fast.evidence().unwrap() - slow.evidence().unwrap()).abs() < tol);
        }
        assert!(
            close(fast.residual_dof, slow.residual_dof),
            "{fast:?} vs {slow:?}"
        );
        assert!(close(fast.gcv(), slow.gcv()));
        assert_eq!((fast.coordinates, fast.observations), (18, 7));
        // The energy is the fit's own minimum: E_fit + λ E_reg at the
        // solution, with the generic deviation of the fixed shapes.
        let shapes = fit.solve(lambda).unwrap();
        let mut energy = 0.0;
        for (i, w) in t.ws.iter().enumerate() {
            let mut e = 0.0;
            for v in 0..6 {
                let mut p = t.generic.neutral()[v];
                for (wj, bj) in w.iter().zip(shapes.deltas()) {
                    p += *wj * bj[v];
                }
                e += (p - t.meshes[i][v].as_dvec3()).length_squared();
            }
            energy += t.importance[i] * e;
        }
        for (j, shape) in shapes.deltas().iter().enumerate() {
            for (v, b) in shape.iter().enumerate() {
                let dev = *b - t.generic.deltas()[j][v];
                energy += lambda * t.weights[j][v].powi(2) * dev.length_squared();
            }
        }
        assert!(close(fast.energy, energy), "{} vs {energy}", fast.energy);
    }
    // Without `ln det K` there is no evidence, and a subset is a subset.
    let two = RidgeCriteria::on_vertices(&fit, vec![1, 4, 99]);
    assert_eq!(two.vertices(), &[1, 4]);
    let terms = two.terms(0.1).unwrap();
    assert_eq!(terms.log_det, None);
    #[cfg(feature = "study")]
    assert_eq!(terms.evidence(), None);
    assert_eq!(terms.coordinates, 6);
}

#[test]
fn the_sample_is_stratified_and_deterministic() {
    let t = tiny();
    let unknowns = [2, 5, 11, 30];
    // Six vertices: fewer than MIN_SAMPLE, so every one is used.
    assert_eq!(
        criteria_sample(&t.generic, &unknowns),
        (0..6).collect::<Vec<_>>()
    );
    let n = 1000;
    let neutral = vec![DVec3::ZERO; n];
    let deltas: Vec<Vec<DVec3>> = (0..BLENDSHAPE_COUNT)
        .map(|_| (0..n).map(|v| DVec3::X * ((v * 7919) % n) as f64).collect())
        .collect();
    let big = Blendshapes::new(neutral, deltas).unwrap();
    let sample = criteria_sample(&big, &unknowns);
    assert_eq!(sample, criteria_sample(&big, &unknowns));
    assert!(sample.windows(2).all(|w| w[0] < w[1]));
    // Motions (v · 7919) mod n are a permutation of 0..n: the sample
    // takes the middle one of every run of SAMPLE_STRIDE, by motion.
    let mut motions: Vec<usize> = sample.iter().map(|v| (v * 7919) % n).collect();
    motions.sort_unstable();
    let expected: Vec<usize> = (SAMPLE_STRIDE / 2..n).step_by(SAMPLE_STRIDE).collect();
    assert_eq!(motions, expected);
    assert_eq!(sample.len(), n.div_ceil(SAMPLE_STRIDE));
}
