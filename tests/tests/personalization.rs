//! Personalization (§3.2) end to end on a committed simulated session: every
//! method produces 52 shapes, bad input is a typed error naming the
//! expression, uncaptured prompts fall back to the generic shape, and the
//! fitted shapes are more faithful than the generic ones.

use likeness::evaluation::{evaluate, mean_errors};
use likeness::personalization::{Method, PersonalizeError, generic_blendshapes, personalize};
use likeness::{Blendshape, Session, SessionError, session_file};
use std::sync::OnceLock;

fn sample() -> &'static Session {
    static S: OnceLock<Session> = OnceLock::new();
    S.get_or_init(|| {
        let path = concat!(
            env!("CARGO_MANIFEST_DIR"),
            "/../sim-data/sessions/subject-3.likeness"
        );
        session_file::read(path).expect("committed session")
    })
}

#[test]
fn every_method_gives_52_finite_shapes() {
    for method in Method::ALL {
        let r = personalize(sample(), method).expect("personalizes");
        assert_eq!(r.deltas.len(), 52, "{method}");
        assert!(r.deltas.iter().flatten().all(|d| d.is_finite()), "{method}");
        assert!(r.generic_fallback.is_empty());
    }
}

#[test]
fn fitted_shapes_beat_the_generic_ones_on_held_out_tests() {
    let s = sample();
    let score = |m| {
        let r = personalize(s, m).unwrap();
        mean_errors(&evaluate(&r.neutral, &r.deltas, s))
            .truth_rmse_mm
            .unwrap()
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
    let mut s = sample().clone();
    s.captures.truncate(40);
    let missing: Vec<Blendshape> = sample().captures[40..].iter().map(|c| c.prompt).collect();
    if let Some(t) = s.truth.as_mut() {
        t.captures.truncate(40);
    }
    let generic = generic_blendshapes(&s).unwrap();
    for method in [Method::Paper, Method::PaperCv, Method::Ebfr, Method::Multi] {
        let r = personalize(&s, method).unwrap();
        assert_eq!(r.deltas.len(), 52);
        let mut fallback = r.generic_fallback.clone();
        fallback.sort();
        let mut expected = missing.clone();
        expected.sort();
        assert_eq!(fallback, expected, "{method}");
        for shape in &missing {
            let same = r.deltas[shape.index()] == generic.deltas[shape.index()];
            assert!(
                same,
                "{method}: uncaptured {shape} is not the generic shape"
            );
        }
    }
}

#[test]
fn nan_weights_and_positions_name_the_expression() {
    let mut s = sample().clone();
    let prompt = s.captures[7].prompt;
    s.captures[7].weights.0[3] = f32::NAN;
    match personalize(&s, Method::Paper) {
        Err(PersonalizeError::Session(SessionError::BadWeight { what, .. })) => {
            assert_eq!(what, format!("capture {prompt}"))
        }
        other => panic!("expected a bad-weight error, got {other:?}"),
    }
    let mut s = sample().clone();
    s.tests[2].vertices[100].y = f32::INFINITY;
    let err = personalize(&s, Method::PaperCv).unwrap_err().to_string();
    assert!(
        err.contains(&s.tests[2].id) && err.contains("vertex 100"),
        "{err}"
    );
}

#[test]
fn a_mesh_of_another_topology_is_a_typed_error() {
    let mut s = sample().clone();
    let prompt = s.captures[0].prompt;
    s.captures[0].vertices.pop();
    let err = personalize(&s, Method::Ebfr).unwrap_err();
    assert!(matches!(err, PersonalizeError::Session(_)), "{err:?}");
    assert!(
        err.to_string().contains(&format!("capture {prompt}")),
        "{err}"
    );
}

#[test]
fn no_captures_is_an_error_for_fits_but_not_for_dt() {
    let mut s = sample().clone();
    s.captures.clear();
    if let Some(t) = s.truth.as_mut() {
        t.captures.clear();
    }
    assert!(matches!(
        personalize(&s, Method::Paper),
        Err(PersonalizeError::NoCaptures)
    ));
    let dt = personalize(&s, Method::Dt).unwrap();
    assert_eq!(dt.generic_fallback.len(), 52);
}

#[test]
fn paper_cv_reports_its_choice_of_lambda() {
    let r = personalize(sample(), Method::PaperCv).unwrap();
    let lambda = r.lambda.unwrap();
    assert_eq!(
        r.lambda_scores.len(),
        likeness::lambda_selection::LAMBDA_GRID.len()
    );
    let best = r
        .lambda_scores
        .iter()
        .min_by(|a, b| a.1.total_cmp(&b.1))
        .unwrap();
    assert_eq!(best.0, lambda);
}
