//! Per-triangle differential quantities for gradient-domain mesh editing.
//!
//! A triangle `(x₀, x₁, x₂)` carries three piecewise-linear *hat functions*
//! `φ₀, φ₁, φ₂` (`φᵢ(xⱼ) = δᵢⱼ`). Their gradients are constant on the triangle
//! and lie in its plane. Deformation transfer (Sumner & Popović 2004; Botsch,
//! Sumner, Pauly & Gross 2006) compares a triangle before and after a
//! deformation through its *deformation gradient* `Q`, the 3×3 matrix that
//! maps the rest triangle onto the deformed one.
//!
//! Notation used throughout:
//!
//! * edges from corner 0: `e₁ = x₁ − x₀`, `e₂ = x₂ − x₀`;
//! * twice the area vector: `c = e₁ × e₂`, area `A = ½‖c‖`, unit normal
//!   `n̂ = c / ‖c‖`;
//! * Sumner's scaled normal `ñ = c / √‖c‖`, which has the length of an edge
//!   (`‖ñ‖ = √(2A)`), so it scales like `e₁` and `e₂` under a uniform scaling
//!   and `Q` of a similarity is that similarity.
//!
//! All arithmetic is in f64 ([`DVec3`], [`DMat3`]); callers convert single
//! precision positions with `as_dvec3`.

use glam::{DMat3, DVec3};

/// Relative size below which a triangle counts as collapsed: a triangle is
/// degenerate when `‖e₁ × e₂‖ ≤ DEGENERACY_RATIO · (‖e₁‖² + ‖e₂‖²)`, i.e. when
/// the sine of its angle at corner 0 is below about `2·10⁻¹²`.
///
/// The test is scale-free, so it means the same in metres and millimetres.
/// Below it the direction of `c` is dominated by rounding, while its size,
/// `‖ñ‖ = √‖c‖ ≤ 10⁻⁶ · √(‖e₁‖² + ‖e₂‖²)`, is a millionth of an edge length:
/// setting `ñ` to zero there (see [`scaled_normal`]) moves it by less than that.
pub const DEGENERACY_RATIO: f64 = 1e-12;

/// Twice the area vector `c = (x₁ − x₀) × (x₂ − x₀)`.
fn area_vector(x: [DVec3; 3]) -> DVec3 {
    (x[1] - x[0]).cross(x[2] - x[0])
}

/// Whether the edges `e₁`, `e₂` span a collapsed triangle:
/// `‖e₁ × e₂‖ ≤ DEGENERACY_RATIO · (‖e₁‖² + ‖e₂‖²)`. A triangle whose corners
/// coincide (`e₁ = e₂ = 0`) is degenerate; a non-finite one is too.
pub fn is_collapsed(e1: DVec3, e2: DVec3) -> bool {
    let c = e1.cross(e2).length();
    let scale = e1.length_squared() + e2.length_squared();
    // NaN counts as collapsed.
    c.partial_cmp(&(DEGENERACY_RATIO * scale)) != Some(std::cmp::Ordering::Greater)
}

/// Whether the triangle `x` is degenerate in the sense of [`is_collapsed`].
pub fn is_degenerate(x: [DVec3; 3]) -> bool {
    is_collapsed(x[1] - x[0], x[2] - x[0])
}

/// Area of the triangle `x`: `A = ½ ‖(x₁ − x₀) × (x₂ − x₀)‖`.
pub fn triangle_area(x: [DVec3; 3]) -> f64 {
    0.5 * area_vector(x).length()
}

/// Gradients of the three hat functions of the triangle `x`, or `None` if the
/// triangle is degenerate ([`is_degenerate`]).
///
/// With `eᵢ` the edge opposite corner `i`, taken counter-clockwise
/// (`e₀ = x₂ − x₁`, `e₁ = x₀ − x₂`, `e₂ = x₁ − x₀`),
///
/// ```text
/// ∇φᵢ = n̂ × eᵢ / (2A).
/// ```
///
/// `∇φᵢ` lies in the triangle's plane, points from the opposite edge towards
/// corner `i` and has length `1/hᵢ` (`hᵢ` the height over that edge). The
/// three sum to zero (constants have zero gradient), and for any affine
/// function `f`, `∇f = Σᵢ f(xᵢ) ∇φᵢ`. The result does not depend on the
/// orientation of the triangle: reversing it flips both `n̂` and every `eᵢ`.
pub fn hat_gradients(x: [DVec3; 3]) -> Option<[DVec3; 3]> {
    if is_degenerate(x) {
        return None;
    }
    let c = area_vector(x);
    let double_area = c.length();
    let n = c / double_area;
    let edges = [x[2] - x[1], x[0] - x[2], x[1] - x[0]];
    Some(edges.map(|e| n.cross(e) / double_area))
}

/// Sumner's scaled normal of the triangle with edges `e₁`, `e₂`:
///
/// ```text
/// ñ = c / √‖c‖,   c = e₁ × e₂,   ‖ñ‖ = √‖c‖ = √(2A).
/// ```
///
/// As the triangle collapses (`‖c‖ → 0`), `ñ` tends continuously to zero, so
/// it is defined as exactly zero once the triangle is collapsed in the sense of
/// [`is_collapsed`]; it is never NaN. This matters for the virtual eye
/// triangles, which collapse when the eye closes.
pub fn scaled_normal(e1: DVec3, e2: DVec3) -> DVec3 {
    if is_collapsed(e1, e2) {
        return DVec3::ZERO;
    }
    let c = e1.cross(e2);
    c / c.length().sqrt()
}

/// The edge matrix `V = [e₁ e₂ ñ]` of the triangle `x` (columns), Sumner's
/// "fourth vertex" construction: `x₀ + ñ` plays the role of a fourth vertex
/// off the plane, so that `V` is invertible for any non-degenerate triangle
/// (`det V = ‖c‖^{3/2} > 0`).
pub fn edge_matrix(x: [DVec3; 3]) -> DMat3 {
    let e1 = x[1] - x[0];
    let e2 = x[2] - x[0];
    DMat3::from_cols(e1, e2, scaled_normal(e1, e2))
}

/// Deformation gradient `Q = [e₁' e₂' ñ'] [e₁ e₂ ñ]⁻¹` that maps the rest
/// triangle onto the deformed one (Sumner & Popović 2004, §3), or `None` if
/// the rest triangle is degenerate. The deformed triangle may be collapsed
/// (then `ñ' = 0`). See [`RestTriangle`] to reuse the inverse for many deformed
/// triangles.
pub fn deformation_gradient(rest: [DVec3; 3], deformed: [DVec3; 3]) -> Option<DMat3> {
    RestTriangle::new(rest).map(|f| f.deformation_gradient(deformed))
}

/// A rest triangle prepared for computing deformation gradients: its edge matrix
/// `V = [e₁ e₂ ñ]` ([`edge_matrix`]) and `V⁻¹`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct RestTriangle {
    edge_matrix: DMat3,
    inverse: DMat3,
}

impl RestTriangle {
    /// Prepares the rest triangle `x`, or returns `None` if it is degenerate
    /// ([`is_degenerate`]) and has no deformation gradient.
    pub fn new(x: [DVec3; 3]) -> Option<RestTriangle> {
        if is_degenerate(x) {
            return None;
        }
        let edge_matrix = edge_matrix(x);
        Some(RestTriangle {
            edge_matrix,
            inverse: edge_matrix.inverse(),
        })
    }

    /// The rest edge matrix `V = [e₁ e₂ ñ]`.
    pub fn edge_matrix(&self) -> DMat3 {
        self.edge_matrix
    }

    /// Deformation gradient `Q = V' V⁻¹` onto the triangle `deformed`, where
    /// `V' = [e₁' e₂' ñ']` is the deformed edge matrix ([`edge_matrix`]). `Q` maps `e₁ ↦ e₁'`,
    /// `e₂ ↦ e₂'` and `ñ ↦ ñ'`; for a similarity `x ↦ sRx + t` it is `sR`.
    /// Finite for every finite `deformed`, collapsed or not.
    pub fn deformation_gradient(&self, deformed: [DVec3; 3]) -> DMat3 {
        edge_matrix(deformed) * self.inverse
    }

    /// Displacement gradient `Q − I = (V' − V) V⁻¹`, computed from the edge-matrix
    /// difference so that it is exactly zero when `deformed` is the rest
    /// triangle (no `V V⁻¹ ≠ I` rounding).
    pub fn displacement_gradient(&self, deformed: [DVec3; 3]) -> DMat3 {
        (edge_matrix(deformed) - self.edge_matrix) * self.inverse
    }
}

/// How much of the triangle `x` still faces its own way under the
/// displacement gradient `g` (the triangle moved to `xᵢ + g xᵢ`): the
/// deformed triangle's area vector projected on the rest normal, over the
/// rest area,
///
/// ```text
/// a(g) = n̂ · ((I + g) e₁ × (I + g) e₂) / ‖e₁ × e₂‖.
/// ```
///
/// 1 for a rigid motion within the plane, between 0 and 1 for a
/// compression or a turn, negative once the triangle has turned past 90°
/// or been folded over; 0 for a degenerate rest triangle.
pub fn facing_area_ratio(x: [DVec3; 3], g: DMat3) -> f64 {
    let c = area_vector(x);
    let double_area = c.length();
    if is_degenerate(x) {
        return 0.0;
    }
    let q = DMat3::IDENTITY + g;
    let moved = (q * (x[1] - x[0])).cross(q * (x[2] - x[0]));
    moved.dot(c) / (double_area * double_area)
}

#[cfg(test)]
mod tests {
    use super::*;

    const TRI: [DVec3; 3] = [
        DVec3::new(0.01, -0.02, 0.03),
        DVec3::new(0.04, -0.01, 0.025),
        DVec3::new(0.015, 0.02, 0.035),
    ];

    fn close(a: DMat3, b: DMat3, tol: f64) -> bool {
        (a - b).to_cols_array().iter().all(|d| d.abs() <= tol)
    }

    #[test]
    fn area_and_hat_gradients_of_a_right_triangle() {
        let x = [DVec3::ZERO, DVec3::X, DVec3::Y];
        assert_eq!(triangle_area(x), 0.5);
        let g = hat_gradients(x).unwrap();
        assert_eq!(g, [DVec3::new(-1.0, -1.0, 0.0), DVec3::X, DVec3::Y]);
    }

    #[test]
    fn hat_gradients_reproduce_affine_functions() {
        let g = hat_gradients(TRI).unwrap();
        assert!((g[0] + g[1] + g[2]).length() < 1e-9);
        // φᵢ(xⱼ) − φᵢ(x₀) = δᵢⱼ − δᵢ₀ and ∇φᵢ ⟂ n̂.
        let n = area_vector(TRI).normalize();
        for (i, gi) in g.iter().enumerate() {
            assert!(gi.dot(n).abs() < 1e-9);
            for (j, xj) in TRI.iter().enumerate().skip(1) {
                let expected = f64::from(u8::from(i == j)) - f64::from(u8::from(i == 0));
                assert!((gi.dot(*xj - TRI[0]) - expected).abs() < 1e-12);
            }
        }
        // Orientation does not matter.
        let flipped = hat_gradients([TRI[0], TRI[2], TRI[1]]).unwrap();
        assert!((flipped[1] - g[2]).length() < 1e-9);
        assert!((flipped[0] - g[0]).length() < 1e-9);
    }

    #[test]
    fn gradient_of_a_similarity_is_the_similarity() {
        let r = DMat3::from_axis_angle(DVec3::new(1.0, 2.0, -0.5).normalize(), 0.7);
        let s = 1.7;
        let t = DVec3::new(0.3, -0.1, 0.2);
        let deformed = TRI.map(|p| s * (r * p) + t);
        let q = deformation_gradient(TRI, deformed).unwrap();
        assert!(close(q, s * r, 1e-12), "{q:?}");
    }

    #[test]
    fn gradient_maps_edges_and_normal() {
        let deformed = [
            DVec3::new(0.0, 0.0, 0.0),
            DVec3::new(0.05, 0.01, 0.0),
            DVec3::new(0.0, 0.03, 0.01),
        ];
        let q = deformation_gradient(TRI, deformed).unwrap();
        let e = |x: [DVec3; 3], k: usize| x[k] - x[0];
        for k in 1..3 {
            assert!((q * e(TRI, k) - e(deformed, k)).length() < 1e-14);
        }
        let n = scaled_normal(e(TRI, 1), e(TRI, 2));
        let n2 = scaled_normal(e(deformed, 1), e(deformed, 2));
        assert!((q * n - n2).length() < 1e-14);
        assert!((n.length() - (2.0 * triangle_area(TRI)).sqrt()).abs() < 1e-15);
    }

    #[test]
    fn collapsing_triangles_have_finite_gradients_that_converge() {
        let rest = RestTriangle::new(TRI).unwrap();
        // Squash corner 2 onto the line through corners 0 and 1.
        let mid = 0.5 * (TRI[0] + TRI[1]);
        let squash = |h: f64| [TRI[0], TRI[1], mid + h * (TRI[2] - mid)];
        let limit = rest.deformation_gradient(squash(0.0));
        assert!(limit.is_finite());
        assert_eq!(edge_matrix(squash(0.0)).z_axis, DVec3::ZERO);
        let mut previous = f64::INFINITY;
        for h in [1e-2, 1e-4, 1e-6, 1e-8, 1e-12, 1e-200] {
            let q = rest.deformation_gradient(squash(h));
            assert!(q.is_finite());
            let gap = (q - limit)
                .to_cols_array()
                .iter()
                .map(|d| d.abs())
                .sum::<f64>();
            assert!(gap <= previous, "h = {h}: {gap} > {previous}");
            previous = gap;
        }
        assert!(previous < 1e-5);
        // All three corners on one point.
        let point = rest.deformation_gradient([TRI[0]; 3]);
        assert_eq!(point, DMat3::ZERO);
    }

    #[test]
    fn degenerate_rest_triangles_are_rejected() {
        assert!(RestTriangle::new([TRI[0], TRI[1], TRI[1]]).is_none());
        assert!(RestTriangle::new([TRI[0], TRI[1], 2.0 * TRI[1] - TRI[0]]).is_none());
        assert!(hat_gradients([TRI[0]; 3]).is_none());
        let nan = DVec3::new(f64::NAN, 0.0, 0.0);
        assert!(RestTriangle::new([TRI[0], TRI[1], nan]).is_none());
        assert!(is_degenerate([TRI[0], TRI[1], nan]));
    }

    #[test]
    fn displacement_gradient_of_the_rest_triangle_is_exactly_zero() {
        let rest = RestTriangle::new(TRI).unwrap();
        assert_eq!(rest.displacement_gradient(TRI), DMat3::ZERO);
        let deformed = TRI.map(|p| p * 1.1);
        let q = rest.deformation_gradient(deformed);
        assert!(close(
            rest.displacement_gradient(deformed),
            q - DMat3::IDENTITY,
            1e-14
        ));
    }

    #[test]
    fn the_facing_area_ratio_says_compressed_turned_and_folded() {
        let g = |m: DMat3| m - DMat3::IDENTITY;
        assert!((facing_area_ratio(TRI, DMat3::ZERO) - 1.0).abs() < 1e-12);
        // A rotation about the normal keeps the triangle facing its way.
        let c = (TRI[1] - TRI[0]).cross(TRI[2] - TRI[0]).normalize();
        let spin = DMat3::from_axis_angle(c, 1.0);
        assert!((facing_area_ratio(TRI, g(spin)) - 1.0).abs() < 1e-12);
        // Halved in one in-plane direction: half the area.
        let e = (TRI[1] - TRI[0]).normalize();
        let squash = DMat3::IDENTITY - 0.5 * DMat3::from_cols(e * e.x, e * e.y, e * e.z);
        assert!((facing_area_ratio(TRI, g(squash)) - 0.5).abs() < 1e-12);
        // Turned past 90° about an in-plane axis, or mirrored in the plane:
        // negative.
        let turn = DMat3::from_axis_angle(e, 2.0);
        assert!(facing_area_ratio(TRI, g(turn)) < 0.0);
        let mirror = DMat3::IDENTITY - 2.0 * DMat3::from_cols(e * e.x, e * e.y, e * e.z);
        assert!((facing_area_ratio(TRI, g(mirror)) + 1.0).abs() < 1e-12);
        assert_eq!(facing_area_ratio([TRI[0]; 3], DMat3::ZERO), 0.0);
    }
}
