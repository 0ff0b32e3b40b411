//! Personalization (§3.2) end to end on a committed simulated session: every
//! method produces 52 shapes, bad input is a typed error naming the
//! expression (where the session is made), uncaptured prompts fall back to
//! the generic shape, and the fitted shapes are more faithful than the
//! generic ones.

use likeness::personalize::evaluation::{evaluate, mean_errors};
use likeness::personalize::{Method, PersonalizeError, generic_blendshapes, personalize};
use likeness::{Blendshape, Session, SessionError, SessionParts};
use std::sync::OnceLock;

fn sample() -> &'static Session {
    static S: OnceLock<Session> = OnceLock::new();
    S.get_or_init(|| likeness_tests::committed::read(3).expect("committed session"))
}

#[test]
fn every_method_gives_52_finite_shapes() {
    for method in Method::ALL {
        let r = personalize(sample(), method).expect("personalizes");
        assert_eq!(r.shapes.deltas().len(), 52, "{method}");
        assert!(
            r.shapes.deltas().iter().flatten().all(|d| d.is_finite()),
            "{method}"
        );
        assert!(r.generic_fallback.is_empty());
    }
}

#[test]
fn fitted_shapes_beat_the_generic_ones_on_held_out_tests() {
    let s = sample();
    let score = |m| {
        let r = personalize(s, m).unwrap();
        mean_errors(&evaluate(&r.shapes, s)).truth_rmse_mm.unwrap()
    };
    let (dt, paper, cv) = (
        score(Method::Dt),
        score(Method::Paper),
        score(Method::PaperCv),
    );
    assert!(paper < dt, "paper {paper} mm vs DT {dt} mm");
    assert!(cv < paper, "paper-cv {cv} mm vs paper {paper} mm");
}

#[test]
fn uncaptured_prompts_fall_back_to_the_generic_shape() {
    let mut s = sample().clone().into_parts();
    s.captures.truncate(40);
    let missing: Vec<Blendshape> = sample().captures[40..].iter().map(|c| c.prompt).collect();
    if let Some(t) = s.truth.as_mut() {
        t.captures.truncate(40);
    }
    let s = Session::new(s).unwrap();
    let generic = generic_blendshapes(&s).unwrap();
    for method in [Method::Paper, Method::PaperCv, Method::Ebfr, Method::Multi] {
        let r = personalize(&s, method).unwrap();
        let mut fallback = r.generic_fallback.clone();
        fallback.sort();
        let mut expected = missing.clone();
        expected.sort();
        assert_eq!(fallback, expected, "{method}");
        for shape in &missing {
            let same = r.shapes.delta(*shape) == generic.shapes.delta(*shape);
            assert!(
                same,
                "{method}: uncaptured {shape} is not the generic shape"
            );
        }
    }
}

/// A copy of the sample's parts, changed by `change`, made a session again.
fn changed(change: impl FnOnce(&mut SessionParts)) -> Result<Session, SessionError> {
    let mut parts = sample().clone().into_parts();
    change(&mut parts);
    Session::new(parts)
}

#[test]
fn nan_weights_and_positions_name_the_expression() {
    let prompt = sample().captures[7].prompt;
    match changed(|s| s.captures[7].weights.0[3] = f32::NAN) {
        Err(SessionError::BadWeight { what, .. }) => {
            assert_eq!(what, format!("capture {prompt}"))
        }
        other => panic!("expected a bad-weight error, got {other:?}"),
    }
    let err = changed(|s| s.tests[2].vertices[100].y = f32::INFINITY)
        .unwrap_err()
        .to_string();
    assert!(
        err.contains(&sample().tests[2].id) && err.contains("vertex 100"),
        "{err}"
    );
}

#[test]
fn a_mesh_of_another_topology_is_a_typed_error() {
    let prompt = sample().captures[0].prompt;
    let err = changed(|s| {
        s.captures[0].vertices.pop();
    })
    .unwrap_err();
    assert!(matches!(err, SessionError::Geometry(_)), "{err:?}");
    assert!(
        err.to_string().contains(&format!("capture {prompt}")),
        "{err}"
    );
}

#[test]
fn no_captures_is_an_error_for_fits_but_not_for_dt() {
    let s = changed(|s| {
        s.captures.clear();
        if let Some(t) = s.truth.as_mut() {
            t.captures.clear();
        }
    })
    .unwrap();
    assert!(matches!(
        personalize(&s, Method::Paper),
        Err(PersonalizeError::NoCaptures)
    ));
    let dt = personalize(&s, Method::Dt).unwrap();
    assert_eq!(dt.generic_fallback.len(), 52);
}

#[test]
fn paper_cv_reports_its_choice_of_lambda_and_needs_no_stream() {
    use likeness::personalize::lambda_selection::{LOG10_RANGE, LambdaRule};
    let r = personalize(sample(), Method::PaperCv).unwrap();
    let choice = r.lambda_choice.clone().unwrap();
    assert_eq!(choice.rule, LambdaRule::Gcv);
    assert_eq!(r.lambda, Some(choice.lambda));
    assert_eq!(choice.range, LOG10_RANGE.map(|x| 10f64.powf(x)));
    // The best λ visited is the one chosen, inside the range.
    let best = choice
        .visited
        .iter()
        .min_by(|a, b| a.criterion.total_cmp(&b.criterion))
        .unwrap();
    assert_eq!(best.lambda, choice.lambda);
    assert_eq!(choice.at_bound, None, "{choice:?}");
    assert!(choice.visited.len() > 20);
    // The choice uses the captures alone: without stream meshes it is the
    // same.
    let without_stream = changed(|s| {
        for frame in &mut s.frames {
            frame.vertices = None;
        }
    })
    .unwrap();
    let again = personalize(&without_stream, Method::PaperCv).unwrap();
    assert_eq!(again.lambda_choice, Some(choice));
    assert_eq!(again.shapes, r.shapes);
    // `paper` reports its fixed λ = 1.
    let paper = personalize(sample(), Method::Paper).unwrap();
    let fixed = paper.lambda_choice.unwrap();
    assert_eq!(
        (fixed.rule, fixed.lambda, fixed.at_bound),
        (LambdaRule::Fixed, 1.0, None)
    );
    assert!(
        personalize(sample(), Method::Dt)
            .unwrap()
            .lambda_choice
            .is_none()
    );
}
