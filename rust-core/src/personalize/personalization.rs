//! §3.2: from a capture session to the person's own 52 blendshapes.
//!
//! Every method starts the same way: the generic template is carried onto
//! the person's neutral scan `B₀` by deformation transfer (virtual triangles
//! close the eye holes), giving the generic blendshapes `T_j`. Then:
//!
//! | method | blendshapes |
//! |---|---|
//! | `dt` | `B_j = T_j` (Sumner & Popović 2004; the paper's DT baseline) |
//! | `ebfr` | Li, Weise & Pauly 2010, blendshape step with known weights ([`crate::personalize::ebfr`]) |
//! | `paper` | Eq. (1)–(3) literally: `E_fit + E_reg` ([`crate::personalize::blendshape_fit`]) |
//! | `paper-cv` | `E_fit + λ·E_reg`, λ by generalized cross-validation on the captures ([`crate::personalize::lambda_selection`]) |
//! | `multi` | as `paper-cv` (λ chosen on the captures), fitted to frames around each peak as well ([`crate::personalize::frame_selection`]) |
//!
//! The names and the product's default are in [`super::method`].
//!
//! Every method's blinks close the eye: the lid pairs that the template's
//! eyeBlink closes (even short of touching, as Apple's does) are exactly
//! closed in `T_j` by DT, and closed again in each fitted result
//! ([`crate::personalize::blendshape_fit`], "Closed eyes"; EBFR in its
//! Poisson step).
//!
//! Shapes whose prompt was not captured keep their generic shape `T_j`, and
//! the result lists them.

use super::blendshape_fit::{BlendshapeFit, Observation};
use super::ebfr::ebfr_blendshapes;
use super::error::PersonalizeError;
use super::frame_selection::fit_frames;
use super::generic_blendshapes::{GenericBlendshapes, generic_blendshapes};
use super::lambda_selection::{LambdaChoice, LambdaRule, choose_lambda};
use super::method::{FitFrames, Method, PersonalizeStage};
use super::regularization_weights::regularization_weights_per_shape;
use crate::arkit::{BLENDSHAPE_COUNT, Blendshape, Blendshapes, Weights};
use crate::session::Session;

/// The person's blendshapes.
#[derive(Clone, Debug)]
pub struct Personalized {
    /// How they were computed.
    pub method: Method,
    /// The neutral face `B₀` (the neutral scan) and the 52 delta blendshapes
    /// `B_j`.
    pub shapes: Blendshapes,
    /// Shapes that were not captured and are the generic `T_j`.
    pub generic_fallback: Vec<Blendshape>,
    /// The regularization strength used (fits only).
    pub lambda: Option<f64>,
    /// How it was chosen (fits only): the rule, whether the choice stopped
    /// at a bound of the range searched, and the λ visited.
    pub lambda_choice: Option<LambdaChoice>,
}

fn weights_f64(w: &Weights) -> [f64; BLENDSHAPE_COUNT] {
    w.0.map(f64::from)
}

/// Personalizes the session's blendshapes with `method`.
pub fn personalize(session: &Session, method: Method) -> Result<Personalized, PersonalizeError> {
    personalize_with_progress(session, method, &mut |_| true)
}

/// [`personalize`], telling `progress` which stage starts; it returns
/// `false` to stop there ([`PersonalizeError::Cancelled`]).
pub fn personalize_with_progress(
    session: &Session,
    method: Method,
    progress: &mut dyn FnMut(PersonalizeStage) -> bool,
) -> Result<Personalized, PersonalizeError> {
    let mut go = |stage| {
        if progress(stage) {
            Ok(())
        } else {
            Err(PersonalizeError::Cancelled(stage))
        }
    };
    go(PersonalizeStage::Transferring)?;
    let generic = generic_blendshapes(session)?;
    let captured = captured_prompts(session);
    let finish = |shapes, lambda_choice: Option<LambdaChoice>| Personalized {
        method,
        shapes,
        generic_fallback: Blendshape::ALL
            .into_iter()
            .filter(|s| !captured[s.index()])
            .collect(),
        lambda: lambda_choice.as_ref().map(|c| c.lambda),
        lambda_choice,
    };
    if method != Method::Dt && session.captures.is_empty() {
        return Err(PersonalizeError::NoCaptures);
    }
    let (frames, rule) = match method {
        Method::Dt => return Ok(finish(generic.shapes.clone(), None)),
        Method::Ebfr => {
            go(PersonalizeStage::Fitting)?;
            let shapes = ebfr_blendshapes(session, &generic, &captured)?;
            return Ok(finish(shapes, None));
        }
        Method::Paper => (FitFrames::Captures, LambdaRule::Fixed),
        Method::PaperCv => (FitFrames::Captures, LambdaRule::Gcv),
        Method::Multi => (FitFrames::AroundPeaks, LambdaRule::Gcv),
    };
    let (choice, shapes) = fit_with_rule(session, &generic, frames, rule, &mut go)?;
    Ok(finish(shapes, Some(choice)))
}

/// The observations of `E_fit`: the captures, and with
/// [`FitFrames::AroundPeaks`] the frames around them, each prompt weighing
/// as one capture in total.
fn observations(session: &Session, frames: FitFrames) -> Vec<Observation<'_>> {
    let mut observations: Vec<Observation> = session
        .captures
        .iter()
        .map(|c| Observation {
            weights: weights_f64(&c.weights),
            vertices: &c.vertices,
            importance: 1.0,
        })
        .collect();
    if frames == FitFrames::AroundPeaks {
        // Indexing: `fit_frames` gives capture and frame indices of `session`.
        let extra = fit_frames(session);
        let mut per_capture = vec![1usize; session.captures.len()];
        for e in &extra {
            per_capture[e.capture] += 1;
        }
        for (o, k) in observations.iter_mut().zip(&per_capture) {
            o.importance = 1.0 / *k as f64;
        }
        for e in extra {
            let frame = &session.frames[e.frame];
            if let Some(vertices) = &frame.vertices {
                observations.push(Observation {
                    weights: weights_f64(&frame.weights),
                    vertices,
                    importance: 1.0 / per_capture[e.capture] as f64,
                });
            }
        }
    }
    observations
}

/// The paper's fit solved for one λ of a sweep.
#[derive(Clone, Debug)]
pub struct LambdaFit {
    /// The regularization strength.
    pub lambda: f64,
    /// The blendshapes fitted with it.
    pub shapes: Blendshapes,
}

/// The λ study: the fit with `frames`, solved for each λ of `grid`.
pub fn lambda_sweep(
    session: &Session,
    frames: FitFrames,
    grid: &[f64],
) -> Result<Vec<LambdaFit>, PersonalizeError> {
    let generic = generic_blendshapes(session)?;
    let fit = assemble_fit(session, &generic, frames);
    grid.iter()
        .map(|&lambda| {
            Ok(LambdaFit {
                lambda,
                shapes: fit.solve(lambda)?,
            })
        })
        .collect()
}

/// The paper's fit with `frames`, λ chosen by `rule`: the choice and the
/// blendshapes fitted with it. `personalize` with `paper`, `paper-cv` or
/// `multi` is this with [`LambdaRule::Fixed`] or [`LambdaRule::Gcv`] and
/// the captures, or GCV and the frames around the peaks; the other rules
/// are there to compare.
pub fn lambda_fit(
    session: &Session,
    frames: FitFrames,
    rule: LambdaRule,
) -> Result<(LambdaChoice, Blendshapes), PersonalizeError> {
    if session.captures.is_empty() {
        return Err(PersonalizeError::NoCaptures);
    }
    let generic = generic_blendshapes(session)?;
    fit_with_rule(session, &generic, frames, rule, &mut |_| Ok(()))
}

/// The fit with `frames`, λ by `rule`; `go` hears the stages
/// [`PersonalizeStage::ChoosingLambda`] (rules that search) and
/// [`PersonalizeStage::Fitting`], and may stop before either.
fn fit_with_rule(
    session: &Session,
    generic: &GenericBlendshapes,
    frames: FitFrames,
    rule: LambdaRule,
    go: &mut dyn FnMut(PersonalizeStage) -> Result<(), PersonalizeError>,
) -> Result<(LambdaChoice, Blendshapes), PersonalizeError> {
    if rule != LambdaRule::Fixed {
        go(PersonalizeStage::ChoosingLambda)?;
    }
    let fit = assemble_fit(session, generic, frames);
    let choice = match (frames, rule) {
        // Frames next to a peak repeat its noise (the tracker filters over
        // ~0.3 s), which cross-validation takes for independent evidence:
        // λ is chosen on the captures alone, whose energy gives each prompt
        // the same total weight as the `multi` energy does.
        (FitFrames::AroundPeaks, rule) if rule.scores_the_fit() => {
            let captures = assemble_fit(session, generic, FitFrames::Captures);
            choose_lambda(session, &captures, rule)?
        }
        _ => choose_lambda(session, &fit, rule)?,
    };
    go(PersonalizeStage::Fitting)?;
    let shapes = fit.solve(choice.lambda)?;
    Ok((choice, shapes))
}

/// Which prompts were captured: the unknowns of the fits. (Indexed by
/// `Blendshape::index()`, always below 52.)
fn captured_prompts(session: &Session) -> [bool; BLENDSHAPE_COUNT] {
    let mut captured = [false; BLENDSHAPE_COUNT];
    for c in &session.captures {
        captured[c.prompt.index()] = true;
    }
    captured
}

/// Eq. (1)–(3) assembled for the session: the Eq. (3) weights of the generic
/// blendshapes, the observations of `frames`, the captured shapes unknown.
fn assemble_fit<'g>(
    session: &Session,
    generic: &'g GenericBlendshapes,
    frames: FitFrames,
) -> BlendshapeFit<'g> {
    BlendshapeFit::new(
        &generic.shapes,
        &regularization_weights_per_shape(&generic.shapes),
        &captured_prompts(session),
        &observations(session, frames),
    )
    .closing_lids(&generic.contacts)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geometry::mesh_boundary::EyeHoleError;
    use crate::geometry::topology::Topology;
    use crate::test_support::{face_grid, stretch_session};
    use glam::Vec3;

    #[test]
    fn sessions_without_usable_eye_holes_are_errors_not_panics() {
        // A single triangle, and the face's topology with every template
        // vertex at one point (no eye has two corners).
        let triangle = vec![Vec3::ZERO, Vec3::X * 0.01, Vec3::Y * 0.01];
        let tiny = stretch_session(Topology::new(3, vec![[0, 1, 2]]).unwrap(), triangle);
        let (topology, neutral, _) = face_grid();
        let flat = stretch_session(topology, vec![Vec3::ZERO; neutral.len()]);
        for method in Method::ALL {
            assert!(matches!(
                personalize(&tiny, method),
                Err(PersonalizeError::EyeHoles(EyeHoleError::LoopCount {
                    found: 1,
                    ..
                }))
            ));
            assert!(matches!(
                personalize(&flat, method),
                Err(PersonalizeError::EyeHoles(EyeHoleError::EyeTooSmall { .. }))
            ));
        }
    }

    #[test]
    fn stages_are_reported_in_order_and_cancelling_stops_there() {
        let (topology, neutral, _) = face_grid();
        let face = stretch_session(topology, neutral);
        let expected: [(Method, &[PersonalizeStage]); 3] = [
            (Method::Dt, &[PersonalizeStage::Transferring]),
            (
                Method::Ebfr,
                &[PersonalizeStage::Transferring, PersonalizeStage::Fitting],
            ),
            (
                Method::Multi,
                &[
                    PersonalizeStage::Transferring,
                    PersonalizeStage::ChoosingLambda,
                    PersonalizeStage::Fitting,
                ],
            ),
        ];
        for (method, stages) in expected {
            let mut seen = Vec::new();
            let p = personalize_with_progress(&face, method, &mut |s| {
                seen.push(s);
                true
            })
            .unwrap();
            assert_eq!(seen, stages, "{method}");
            assert_eq!(p.shapes, personalize(&face, method).unwrap().shapes);
        }
        for stage in [PersonalizeStage::ChoosingLambda, PersonalizeStage::Fitting] {
            let r = personalize_with_progress(&face, Method::Multi, &mut |s| s != stage);
            assert_eq!(r.unwrap_err(), PersonalizeError::Cancelled(stage));
        }
    }

    #[test]
    fn every_method_personalizes_a_small_face() {
        let (topology, neutral, _) = face_grid();
        let face = stretch_session(topology, neutral);
        for method in Method::ALL {
            let p = personalize(&face, method).unwrap();
            assert_eq!(p.generic_fallback.len(), BLENDSHAPE_COUNT - 1);
        }
    }
}
