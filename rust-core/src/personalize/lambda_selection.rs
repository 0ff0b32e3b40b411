//! Choosing the weight λ of `E_reg` for each session.
//!
//! Eq. (3) makes every weight `D_j ≥ 1`, so with `E_fit + E_reg` the
//! regularizer weighs at least as much as the data even at a shape's most
//! moving vertex: read literally, the fit recovers at most about half of a
//! person's deviation from the template. The paper states no weight on
//! `E_reg`; `paper-cv` and `multi` pick one per session from the captures
//! themselves.
//!
//! # The rule
//!
//! [`LambdaRule::Gcv`]: the λ of least generalized cross-validation score
//! of the fitted captures (Golub, Heath & Wahba 1979), an estimate of the
//! error of predicting new observations that needs no held-out frames and
//! no model of how a person deviates from the template
//! ([`super::lambda_criteria`], where the formulas are derived). It works
//! the same on a session without stream meshes (an imported OBJ + CSV
//! folder) as on one with them. `multi` uses the λ chosen on the captures:
//! frames next to a peak repeat its tracker noise (ARKit filters over
//! ~0.3 s), which cross-validation takes for independent evidence.
//! Leave-one-capture-out would be biased: without capture `i` the shape `i`
//! is identified almost only by the regularizer, which favours a large λ.
//! The rules measured against GCV, and what was found, are in
//! `docs/notes/2026-12-lambda-rules.md`; the two that need code of their own
//! (the marginal likelihood and held-out stream frames) are built with the
//! `study` feature only.
//!
//! # The search
//!
//! The criterion is minimized over `log₁₀ λ` in [`LOG10_RANGE`]
//! (10⁻⁸ … 10²): first every [`SCAN_STEP`] decades, then by golden-section
//! search between the neighbours of the best scanned point, until the
//! bracket is narrower than [`SEARCH_TOLERANCE`] decades (21 evaluations
//! in all). The best λ visited is chosen; if it lies within the tolerance
//! of an end of the range the choice is reported [`LambdaChoice::at_bound`].
//! Once the sampled vertices are reduced
//! ([`super::lambda_criteria::RidgeCriteria`]), an evaluation costs O(k)
//! per sampled vertex, so the whole choice costs less than one more fit.

use super::blendshape_fit::BlendshapeFit;
use super::error::PersonalizeError;
#[cfg(feature = "study")]
use super::frame_selection::validation_frames;
use super::lambda_criteria::RidgeCriteria;
use crate::session::Session;
#[cfg(feature = "study")]
use glam::DVec3;
use std::fmt;

/// The range searched, in decades: λ from 10⁻⁸ (the data alone, nearly)
/// to 10² (the generic shapes, nearly).
pub const LOG10_RANGE: [f64; 2] = [-8.0, 2.0];

/// The first pass evaluates the criterion every this many decades.
pub const SCAN_STEP: f64 = 1.0;

/// The golden-section search stops when its bracket is narrower than this
/// many decades (a factor 1.12 in λ; near its optimum the accuracy of the
/// fit changes by well under 1% over a factor 2).
pub const SEARCH_TOLERANCE: f64 = 0.05;

/// How λ was chosen.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum LambdaRule {
    /// The paper's λ = 1, not chosen.
    Fixed,
    /// Largest marginal likelihood (evidence) of the fitted data
    /// ([`super::lambda_criteria`]); the study's only.
    #[cfg(feature = "study")]
    Evidence,
    /// Smallest generalized cross-validation score (Golub, Heath & Wahba
    /// 1979): the rule of `paper-cv` and `multi`.
    Gcv,
    /// Smallest error on held-out stream frames near the captures
    /// (`frame_selection::validation_frames`); needs stream meshes; the
    /// study's only.
    #[cfg(feature = "study")]
    Holdout,
}

impl LambdaRule {
    /// Whether the rule scores λ by the fit's own data (GCV, the evidence),
    /// rather than by nothing (`Fixed`) or by frames held out of it.
    pub fn scores_the_fit(self) -> bool {
        match self {
            LambdaRule::Gcv => true,
            #[cfg(feature = "study")]
            LambdaRule::Evidence => true,
            _ => false,
        }
    }

    /// The rule's name in reports.
    pub const fn name(self) -> &'static str {
        match self {
            LambdaRule::Fixed => "fixed",
            #[cfg(feature = "study")]
            LambdaRule::Evidence => "evidence",
            LambdaRule::Gcv => "gcv",
            #[cfg(feature = "study")]
            LambdaRule::Holdout => "holdout",
        }
    }
}

impl fmt::Display for LambdaRule {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.name())
    }
}

/// An end of [`LOG10_RANGE`].
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Bound {
    /// The smallest λ searched: the data want less regularization still.
    Lower,
    /// The largest λ searched: the data want the generic shapes.
    Upper,
}

impl Bound {
    /// `lower` or `upper`.
    pub const fn name(self) -> &'static str {
        match self {
            Bound::Lower => "lower",
            Bound::Upper => "upper",
        }
    }
}

/// One λ visited by the search and its criterion value.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct LambdaScore {
    /// The candidate.
    pub lambda: f64,
    /// The rule's criterion (smaller is better): for [`LambdaRule::Gcv`]
    /// the GCV score (m²); for the study's rules the profiled negative log
    /// evidence per datum, or the held-out mean squared error (m²).
    pub criterion: f64,
}

/// How λ was chosen, and what was chosen.
#[derive(Clone, Debug, PartialEq)]
pub struct LambdaChoice {
    /// The rule.
    pub rule: LambdaRule,
    /// The λ chosen.
    pub lambda: f64,
    /// The range searched (λ, not decades); `[1, 1]` for
    /// [`LambdaRule::Fixed`].
    pub range: [f64; 2],
    /// `Some` if the choice lies at an end of the range (within
    /// [`SEARCH_TOLERANCE`]): the rule would have gone further.
    pub at_bound: Option<Bound>,
    /// Every λ the search evaluated, in order.
    pub visited: Vec<LambdaScore>,
}

impl LambdaChoice {
    /// The paper's λ = 1, not chosen.
    pub fn fixed(lambda: f64) -> LambdaChoice {
        LambdaChoice {
            rule: LambdaRule::Fixed,
            lambda,
            range: [lambda, lambda],
            at_bound: None,
            visited: Vec::new(),
        }
    }
}

/// Minimizes `criterion(λ)` over `log₁₀ λ ∈ LOG10_RANGE`: every
/// [`SCAN_STEP`], then golden-section search around the best scanned point
/// (module docs). A NaN value counts as the worst.
pub fn search_lambda(
    rule: LambdaRule,
    mut criterion: impl FnMut(f64) -> Result<f64, PersonalizeError>,
) -> Result<LambdaChoice, PersonalizeError> {
    let [lo, hi] = LOG10_RANGE;
    let mut visited: Vec<LambdaScore> = Vec::new();
    let mut at = |x: f64| -> Result<f64, PersonalizeError> {
        let lambda = 10f64.powf(x);
        let value = criterion(lambda)?;
        visited.push(LambdaScore {
            lambda,
            criterion: value,
        });
        Ok(if value.is_nan() { f64::INFINITY } else { value })
    };
    let steps = ((hi - lo) / SCAN_STEP).round() as usize;
    let mut best = (lo, f64::INFINITY);
    for i in 0..=steps {
        let x = lo + i as f64 * SCAN_STEP;
        let value = at(x)?;
        if value < best.1 {
            best = (x, value);
        }
    }
    let inverse_phi = (5f64.sqrt() - 1.0) / 2.0;
    let (mut a, mut b) = ((best.0 - SCAN_STEP).max(lo), (best.0 + SCAN_STEP).min(hi));
    let mut x1 = b - inverse_phi * (b - a);
    let mut x2 = a + inverse_phi * (b - a);
    let (mut f1, mut f2) = (at(x1)?, at(x2)?);
    while b - a > SEARCH_TOLERANCE {
        if f1 < f2 {
            b = x2;
            (x2, f2) = (x1, f1);
            x1 = b - inverse_phi * (b - a);
            f1 = at(x1)?;
        } else {
            a = x1;
            (x1, f1) = (x2, f2);
            x2 = a + inverse_phi * (b - a);
            f2 = at(x2)?;
        }
    }
    let chosen = visited
        .iter()
        .min_by(|p, q| {
            let key = |s: &LambdaScore| {
                if s.criterion.is_nan() {
                    f64::INFINITY
                } else {
                    s.criterion
                }
            };
            key(p).total_cmp(&key(q))
        })
        .map_or(1.0, |s| s.lambda);
    let x = chosen.log10();
    let at_bound = if x <= lo + SEARCH_TOLERANCE {
        Some(Bound::Lower)
    } else if x >= hi - SEARCH_TOLERANCE {
        Some(Bound::Upper)
    } else {
        None
    };
    Ok(LambdaChoice {
        rule,
        lambda: chosen,
        range: [10f64.powf(lo), 10f64.powf(hi)],
        at_bound,
        visited,
    })
}

/// Chooses λ for `fit` by `rule`. The study's `Holdout` scores on the
/// stream frames of `session` (the session `fit` was assembled from); a
/// session without usable stream frames keeps λ = 1 under that rule, as
/// does [`LambdaRule::Fixed`].
#[cfg_attr(not(feature = "study"), allow(unused_variables))]
pub fn choose_lambda(
    session: &Session,
    fit: &BlendshapeFit<'_>,
    rule: LambdaRule,
) -> Result<LambdaChoice, PersonalizeError> {
    match rule {
        LambdaRule::Fixed => Ok(LambdaChoice::fixed(1.0)),
        LambdaRule::Gcv => {
            let criteria = RidgeCriteria::new(fit);
            search_lambda(rule, |lambda| Ok(criteria.terms(lambda)?.gcv()))
        }
        #[cfg(feature = "study")]
        LambdaRule::Evidence => {
            let criteria = RidgeCriteria::new(fit);
            search_lambda(rule, |lambda| {
                Ok(criteria
                    .terms_with_log_det(lambda)?
                    .evidence()
                    .unwrap_or(f64::NAN))
            })
        }
        #[cfg(feature = "study")]
        LambdaRule::Holdout => {
            let frames = validation_frames(session);
            if frames.is_empty() {
                return Ok(LambdaChoice::fixed(1.0));
            }
            let neutral: Vec<DVec3> = session.neutral.iter().map(|p| p.as_dvec3()).collect();
            let error = super::holdout::ValidationError::new(session, &neutral, &frames);
            search_lambda(rule, |lambda| error.mean_squared(&fit.solve(lambda)?))
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_search_finds_an_inner_minimum_and_reports_a_bound() {
        // A smooth criterion in log λ with its minimum at 10^-3.7.
        let inner = search_lambda(LambdaRule::Gcv, |l| Ok((l.log10() + 3.7).powi(2))).unwrap();
        assert!(
            (inner.lambda.log10() + 3.7).abs() < SEARCH_TOLERANCE,
            "{inner:?}"
        );
        assert_eq!(inner.at_bound, None);
        assert_eq!(inner.rule, LambdaRule::Gcv);
        assert_eq!(inner.visited.len(), 21);
        assert_eq!(inner.range, [1e-8, 1e2]);
        // Monotone criteria stop at the ends, and say so.
        let lower = search_lambda(LambdaRule::Gcv, Ok).unwrap();
        assert_eq!((lower.lambda, lower.at_bound), (1e-8, Some(Bound::Lower)));
        let upper = search_lambda(LambdaRule::Gcv, |l| Ok(-l)).unwrap();
        assert_eq!((upper.lambda, upper.at_bound), (1e2, Some(Bound::Upper)));
        // NaN counts as the worst; an error is passed on.
        let nan = search_lambda(LambdaRule::Gcv, |l| {
            Ok(if l > 1e-3 { f64::NAN } else { -l })
        })
        .unwrap();
        assert!(nan.lambda <= 1e-3 * 1.0001, "{nan:?}");
        let failed = search_lambda(LambdaRule::Gcv, |_| Err(PersonalizeError::NoCaptures));
        assert_eq!(failed, Err(PersonalizeError::NoCaptures));
    }
}
