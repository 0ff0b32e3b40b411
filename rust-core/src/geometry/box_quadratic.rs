//! The least of a convex quadratic over a box,
//!
//! ```text
//! min ½ wᵀ H w − cᵀ w   subject to   lo ≤ w ≤ hi,
//! ```
//!
//! `H` symmetric positive definite (`k × k`, small: one row per blendshape).
//! Bounded weights are the usual constraint of blendshape retargeting
//! (Lewis et al. 2014, *Practice and Theory of Blendshape Facial Models*,
//! §5.2: a rig is made for weights in `[0, 1]`, and outside it its shapes
//! are extrapolated past anything the artist looked at).
//!
//! **Method.** The primal–dual active set method (Hintermüller, Ito &
//! Kunisch 2002), a semismooth Newton step on the optimality conditions:
//! with the gradient `g = H w − c`, the minimum has `w_i = lo_i` where
//! `g_i ≥ 0`, `w_i = hi_i` where `g_i ≤ 0`, and `g_i = 0` in between. Each
//! round guesses the bound of every `i` from `w_i − g_i / H_ii`, fixes the
//! bound ones and solves `H_FF w_F = c_F − H_FB w_B` for the free ones
//! (one Cholesky factorization of the free block). When a round guesses
//! the same sets as the one before, its `w` satisfies the optimality
//! conditions. The method converges in a few rounds on such problems but
//! can, rarely, cycle; after [`MAX_ACTIVE_SET_ROUNDS`] without a fixed
//! point, projected coordinate descent (Gauss–Seidel with each coordinate
//! clamped to its bounds; it lowers the objective at every step and
//! converges for any positive definite `H`) finishes from the best point
//! seen.

use faer::Mat;
use faer::linalg::solvers::Solve;

/// Rounds of the active set method before it hands over to coordinate
/// descent (module docs). Each round changes the guessed sets, and on the
/// retargeting's problems it settles in under ten.
pub const MAX_ACTIVE_SET_ROUNDS: usize = 50;

/// Sweeps of the coordinate descent fallback.
pub const MAX_DESCENT_SWEEPS: usize = 20_000;

/// Optimality is met when the projected gradient, `w − clamp(w − g)`, is at
/// most this share of the largest `|c_i|` (or of 1 where `c` vanishes).
pub const OPTIMALITY_TOLERANCE: f64 = 1e-10;

/// Why the problem has no answer.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
pub enum BoxQuadraticError {
    /// `H` is not square, or `c` or a bound has another length.
    #[error("a {rows} × {cols} matrix with {c} linear terms and bounds of {lo} and {hi}")]
    Sizes {
        /// Rows of `H`.
        rows: usize,
        /// Columns of `H`.
        cols: usize,
        /// Length of `c`.
        c: usize,
        /// Length of `lo`.
        lo: usize,
        /// Length of `hi`.
        hi: usize,
    },
    /// A lower bound above its upper bound, or a bound not a number.
    #[error("variable {index}: the bounds {lo}..{hi} hold no value")]
    EmptyBox {
        /// The variable.
        index: usize,
        /// Its lower bound.
        lo: f64,
        /// Its upper bound.
        hi: f64,
    },
    /// `H` is not positive definite (a free block could not be factored,
    /// or a diagonal entry is not positive).
    #[error("the quadratic is not positive definite")]
    NotPositiveDefinite,
}

/// A box `lo ≤ w ≤ hi`, checked to hold a value in every coordinate.
#[derive(Clone, Debug, PartialEq)]
pub struct Bounds {
    lo: Vec<f64>,
    hi: Vec<f64>,
}

impl Bounds {
    /// The box between `lo` and `hi`.
    pub fn new(lo: Vec<f64>, hi: Vec<f64>) -> Result<Bounds, BoxQuadraticError> {
        if lo.len() != hi.len() {
            return Err(BoxQuadraticError::Sizes {
                rows: lo.len(),
                cols: lo.len(),
                c: lo.len(),
                lo: lo.len(),
                hi: hi.len(),
            });
        }
        for (index, (&l, &h)) in lo.iter().zip(&hi).enumerate() {
            if l.is_nan() || h.is_nan() || l > h {
                return Err(BoxQuadraticError::EmptyBox {
                    index,
                    lo: l,
                    hi: h,
                });
            }
        }
        Ok(Bounds { lo, hi })
    }

    /// The same interval `[lo, hi]` for `k` variables.
    pub fn uniform(k: usize, lo: f64, hi: f64) -> Result<Bounds, BoxQuadraticError> {
        Bounds::new(vec![lo; k], vec![hi; k])
    }

    /// How many variables the box bounds.
    pub fn len(&self) -> usize {
        self.lo.len()
    }

    /// Whether it bounds none.
    pub fn is_empty(&self) -> bool {
        self.lo.is_empty()
    }

    fn clamp(&self, i: usize, x: f64) -> f64 {
        x.clamp(self.lo[i], self.hi[i])
    }
}

/// Where a variable sits at the minimum.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Side {
    Lower,
    Free,
    Upper,
}

/// The minimum found.
#[derive(Clone, Debug, PartialEq)]
pub struct BoxMinimum {
    /// The minimizer, inside the box.
    pub w: Vec<f64>,
    /// Active set rounds taken.
    pub rounds: usize,
    /// Whether coordinate descent had to finish (the active set method
    /// cycled).
    pub by_descent: bool,
}

/// `min ½ wᵀ H w − cᵀ w` over `bounds` (module docs), `H` symmetric
/// positive definite.
pub fn minimize(h: &Mat<f64>, c: &[f64], bounds: &Bounds) -> Result<BoxMinimum, BoxQuadraticError> {
    let k = c.len();
    if h.nrows() != k || h.ncols() != k || bounds.len() != k {
        return Err(BoxQuadraticError::Sizes {
            rows: h.nrows(),
            cols: h.ncols(),
            c: k,
            lo: bounds.lo.len(),
            hi: bounds.hi.len(),
        });
    }
    if (0..k).any(|i| h[(i, i)].is_nan() || h[(i, i)] <= 0.0) {
        return Err(BoxQuadraticError::NotPositiveDefinite);
    }
    active_set(h, c, bounds, MAX_ACTIVE_SET_ROUNDS)
}

/// The primal–dual active set rounds, at most `rounds` of them, then
/// coordinate descent if they did not settle.
fn active_set(
    h: &Mat<f64>,
    c: &[f64],
    bounds: &Bounds,
    rounds: usize,
) -> Result<BoxMinimum, BoxQuadraticError> {
    let k = c.len();
    let mut w: Vec<f64> = (0..k).map(|i| bounds.clamp(i, 0.0)).collect();
    let mut sides: Option<Vec<Side>> = None;
    let mut best = (objective(h, c, &w), w.clone());
    for round in 1..=rounds {
        let g = gradient(h, c, &w);
        let guess: Vec<Side> = (0..k)
            .map(|i| {
                let t = w[i] - g[i] / h[(i, i)];
                if t <= bounds.lo[i] {
                    Side::Lower
                } else if t >= bounds.hi[i] {
                    Side::Upper
                } else {
                    Side::Free
                }
            })
            .collect();
        if sides.as_ref() == Some(&guess) {
            let w = (0..k).map(|i| bounds.clamp(i, w[i])).collect();
            return Ok(BoxMinimum {
                w,
                rounds: round - 1,
                by_descent: false,
            });
        }
        w = solve_free(h, c, bounds, &guess)?;
        let clamped: Vec<f64> = (0..k).map(|i| bounds.clamp(i, w[i])).collect();
        let value = objective(h, c, &clamped);
        if value < best.0 {
            best = (value, clamped);
        }
        sides = Some(guess);
    }
    Ok(BoxMinimum {
        w: coordinate_descent(h, c, bounds, best.1),
        rounds,
        by_descent: true,
    })
}

/// `w` with the bound variables of `sides` at their bounds and the free
/// ones solving `H_FF w_F = c_F − H_FB w_B`.
fn solve_free(
    h: &Mat<f64>,
    c: &[f64],
    bounds: &Bounds,
    sides: &[Side],
) -> Result<Vec<f64>, BoxQuadraticError> {
    let k = c.len();
    let mut w: Vec<f64> = (0..k)
        .map(|i| match sides[i] {
            Side::Lower => bounds.lo[i],
            Side::Upper => bounds.hi[i],
            Side::Free => 0.0,
        })
        .collect();
    let free: Vec<usize> = (0..k).filter(|&i| sides[i] == Side::Free).collect();
    if free.is_empty() {
        return Ok(w);
    }
    let block = Mat::<f64>::from_fn(free.len(), free.len(), |a, b| h[(free[a], free[b])]);
    let rhs = Mat::<f64>::from_fn(free.len(), 1, |a, _| {
        let i = free[a];
        c[i] - (0..k)
            .filter(|&j| sides[j] != Side::Free)
            .map(|j| h[(i, j)] * w[j])
            .sum::<f64>()
    });
    let llt = block
        .llt(faer::Side::Lower)
        .map_err(|_| BoxQuadraticError::NotPositiveDefinite)?;
    let x = llt.solve(&rhs);
    for (a, &i) in free.iter().enumerate() {
        w[i] = x[(a, 0)];
    }
    Ok(w)
}

/// Projected Gauss–Seidel from `w` (module docs): each coordinate in turn
/// set to its exact minimizer with the others fixed, clamped to its
/// bounds, until the projected gradient meets [`OPTIMALITY_TOLERANCE`] or
/// [`MAX_DESCENT_SWEEPS`] have passed.
fn coordinate_descent(h: &Mat<f64>, c: &[f64], bounds: &Bounds, mut w: Vec<f64>) -> Vec<f64> {
    let k = c.len();
    let scale = c.iter().fold(0.0_f64, |m, x| m.max(x.abs())).max(1.0);
    let mut g = gradient(h, c, &w);
    for _ in 0..MAX_DESCENT_SWEEPS {
        for i in 0..k {
            let new = bounds.clamp(i, w[i] - g[i] / h[(i, i)]);
            let step = new - w[i];
            if step != 0.0 {
                for (j, gj) in g.iter_mut().enumerate() {
                    *gj += h[(j, i)] * step;
                }
                w[i] = new;
            }
        }
        if projected_gradient(&w, &g, bounds) <= OPTIMALITY_TOLERANCE * scale {
            break;
        }
    }
    w
}

/// `H w − c`.
fn gradient(h: &Mat<f64>, c: &[f64], w: &[f64]) -> Vec<f64> {
    (0..c.len())
        .map(|i| (0..c.len()).map(|j| h[(i, j)] * w[j]).sum::<f64>() - c[i])
        .collect()
}

/// `½ wᵀ H w − cᵀ w`.
fn objective(h: &Mat<f64>, c: &[f64], w: &[f64]) -> f64 {
    let g = gradient(h, c, w);
    // ½ wᵀHw − cᵀw = ½ wᵀ(Hw − c) − ½ cᵀw.
    (0..c.len())
        .map(|i| 0.5 * w[i] * g[i] - 0.5 * c[i] * w[i])
        .sum()
}

/// The largest `|w_i − clamp(w_i − g_i)|`: zero exactly at the minimum.
fn projected_gradient(w: &[f64], g: &[f64], bounds: &Bounds) -> f64 {
    (0..w.len())
        .map(|i| (w[i] - bounds.clamp(i, w[i] - g[i])).abs())
        .fold(0.0, f64::max)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A symmetric positive definite matrix `AᵀA + εI` from a small
    /// deterministic generator, with condition number up to ~`1/ε`.
    fn spd(k: usize, seed: u64, eps: f64) -> Mat<f64> {
        let mut s = seed
            .wrapping_mul(6364136223846793005)
            .wrapping_add(1442695040888963407);
        let mut next = move || {
            s = s
                .wrapping_mul(6364136223846793005)
                .wrapping_add(1442695040888963407);
            ((s >> 11) as f64 / (1u64 << 53) as f64) * 2.0 - 1.0
        };
        let a = Mat::<f64>::from_fn(k + 3, k, |_, _| next());
        let mut h = a.transpose() * &a;
        for i in 0..k {
            h[(i, i)] += eps;
        }
        h
    }

    fn linear(k: usize, seed: u64) -> Vec<f64> {
        (0..k)
            .map(|i| ((seed as f64 + 1.0) * (i as f64 + 0.7)).sin() * 3.0)
            .collect()
    }

    /// The exact minimum by trying every assignment of lower, free and
    /// upper (3^k), keeping the feasible one with the least objective.
    fn brute_force(h: &Mat<f64>, c: &[f64], bounds: &Bounds) -> Vec<f64> {
        let k = c.len();
        let mut best = (f64::INFINITY, vec![]);
        for code in 0..3usize.pow(k as u32) {
            let sides: Vec<Side> = (0..k)
                .map(|i| match (code / 3usize.pow(i as u32)) % 3 {
                    0 => Side::Lower,
                    1 => Side::Free,
                    _ => Side::Upper,
                })
                .collect();
            let w = solve_free(h, c, bounds, &sides).expect("positive definite");
            let feasible =
                (0..k).all(|i| w[i] >= bounds.lo[i] - 1e-12 && w[i] <= bounds.hi[i] + 1e-12);
            let value = objective(h, c, &w);
            if feasible && value < best.0 {
                best = (value, w);
            }
        }
        best.1
    }

    fn largest_difference(a: &[f64], b: &[f64]) -> f64 {
        a.iter()
            .zip(b)
            .map(|(x, y)| (x - y).abs())
            .fold(0.0, f64::max)
    }

    #[test]
    fn the_minimum_is_the_one_every_active_set_would_give() {
        for seed in 0..40 {
            let k = 6;
            let h = spd(k, seed, 1e-3);
            let c = linear(k, seed);
            let bounds = Bounds::uniform(k, 0.0, 1.0).expect("a box");
            let got = minimize(&h, &c, &bounds).expect("solves");
            let exact = brute_force(&h, &c, &bounds);
            let worst = largest_difference(&got.w, &exact);
            assert!(
                worst < 1e-8,
                "seed {seed}: off by {worst}, {got:?} against {exact:?}"
            );
        }
    }

    #[test]
    fn an_inner_minimum_is_the_unconstrained_one() {
        let h = spd(5, 7, 1.0);
        let inside = [0.2, 0.5, 0.7, 0.3, 0.9];
        let c: Vec<f64> = (0..5)
            .map(|i| (0..5).map(|j| h[(i, j)] * inside[j]).sum())
            .collect();
        let got = minimize(&h, &c, &Bounds::uniform(5, 0.0, 1.0).expect("a box")).expect("solves");
        for (a, b) in got.w.iter().zip(inside) {
            assert!((a - b).abs() < 1e-10, "{a} against {b}");
        }
        assert!(!got.by_descent);
    }

    #[test]
    fn coordinate_descent_alone_reaches_the_same_minimum() {
        for seed in 0..10 {
            let k = 6;
            let h = spd(k, seed, 1e-2);
            let c = linear(k, seed);
            let bounds = Bounds::new(vec![-0.5; k], vec![0.8; k]).expect("a box");
            let forced = active_set(&h, &c, &bounds, 0).expect("solves");
            assert!(forced.by_descent);
            let exact = brute_force(&h, &c, &bounds);
            let worst = largest_difference(&forced.w, &exact);
            assert!(worst < 1e-6, "seed {seed}: off by {worst}");
        }
    }

    #[test]
    fn bad_problems_are_named() {
        let h = spd(3, 1, 1.0);
        assert!(matches!(
            Bounds::new(vec![0.0, 1.0], vec![1.0, 0.5]),
            Err(BoxQuadraticError::EmptyBox { index: 1, .. })
        ));
        let bounds = Bounds::uniform(2, 0.0, 1.0).expect("a box");
        assert!(matches!(
            minimize(&h, &[1.0, 2.0], &bounds),
            Err(BoxQuadraticError::Sizes { .. })
        ));
        let mut negative = Mat::<f64>::identity(2, 2);
        negative[(1, 1)] = -1.0;
        assert_eq!(
            minimize(&negative, &[1.0, 1.0], &bounds),
            Err(BoxQuadraticError::NotPositiveDefinite)
        );
    }
}
