//! The sphere closest to a point set, by the algebraic least-squares fit
//! (Kåsa 1976): with `k = r² − ‖c‖²`, every point should satisfy
//! `‖p‖² = 2 c·p + k`, linear in `(c, k)`; the 4 × 4 normal equations give
//! the centre and radius. Its RMS geometric residual `‖p − c‖ − r` says how
//! spherical the set is. Used to tell eyeballs from other closed parts.

use faer::Mat;
use faer::linalg::solvers::Solve;
use glam::DVec3;

/// A fitted sphere and how far the points lie from it.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Sphere {
    /// Centre.
    pub centre: DVec3,
    /// Radius.
    pub radius: f64,
    /// RMS of `‖p − c‖ − r` over the points.
    pub rms_residual: f64,
}

/// The algebraic least-squares sphere through `points` (module docs);
/// `None` for fewer than four points or a degenerate (flat) set.
pub fn fit_sphere(points: &[DVec3]) -> Option<Sphere> {
    if points.len() < 4 {
        return None;
    }
    // Centred first, for conditioning.
    let mean = points.iter().sum::<DVec3>() / points.len() as f64;
    let mut a = Mat::<f64>::zeros(4, 4);
    let mut b = Mat::<f64>::zeros(4, 1);
    for p in points {
        let q = *p - mean;
        let row = [2.0 * q.x, 2.0 * q.y, 2.0 * q.z, 1.0];
        let rhs = q.length_squared();
        for i in 0..4 {
            b[(i, 0)] += row[i] * rhs;
            for j in 0..4 {
                a[(i, j)] += row[i] * row[j];
            }
        }
    }
    let x = a.partial_piv_lu().solve(&b);
    let centre = DVec3::new(x[(0, 0)], x[(1, 0)], x[(2, 0)]);
    let r2 = x[(3, 0)] + centre.length_squared();
    if !(r2 > 0.0 && r2.is_finite()) {
        return None;
    }
    let radius = r2.sqrt();
    let rms_residual = (points
        .iter()
        .map(|p| ((*p - mean - centre).length() - radius).powi(2))
        .sum::<f64>()
        / points.len() as f64)
        .sqrt();
    Some(Sphere {
        centre: centre + mean,
        radius,
        rms_residual,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn points_on_a_sphere_give_it_back() {
        let c = DVec3::new(1.0, -2.0, 0.5);
        let points: Vec<DVec3> = (0..200)
            .map(|i| {
                let t = i as f64 * 0.37;
                let z = (i as f64 / 100.0) - 1.0;
                let s = (1.0 - z * z).sqrt();
                c + DVec3::new(s * t.cos(), s * t.sin(), z) * 0.012
            })
            .collect();
        let sphere = fit_sphere(&points).expect("fits");
        assert!((sphere.centre - c).length() < 1e-9);
        assert!((sphere.radius - 0.012).abs() < 1e-9);
        assert!(sphere.rms_residual < 1e-9);
        // A flat set is no sphere.
        let flat: Vec<DVec3> = (0..20)
            .map(|i| DVec3::new(i as f64, (i * i % 7) as f64, 0.0))
            .collect();
        assert!(fit_sphere(&flat).is_none_or(|s| s.radius > 1e6 || s.rms_residual > 0.1));
    }
}
