//! Does the avatar look like the person? (§4.2, Fig. 7 and 8.) On the
//! committed simulated subjects, each test expression is animated on the
//! default avatar three ways from the tracked weights `w` — manual
//! retargeting (the avatar's own shape `j` driven by weight `j`, what Unity
//! Live Capture and Live Link do), automatic retargeting (`Σ w_j A_j`,
//! Eq. 4) and the personalized avatar (`Σ w_j` of the implanted shapes) —
//! and compared on the avatar's face region with the subject's true
//! expression carried onto the avatar by `M`
//! (`likeness::avatar::likeness_check`). Errors in millimetres at the
//! mask's scale; also on the mouth corners (face vertices within 12 mm of
//! a corner) and the lip contour (within 4 mm of a lip row), where the
//! paper says the differences are.

mod implanted_subject;

use glam::DVec3;
use likeness::avatar::likeness_check::{
    AnimationShapes, face_vertices_near, likeness_on_avatar, summarize,
};
use likeness_sim::default_avatar::default_avatar;
use likeness_sim::face_mask::face_mask;

#[test]
fn personalized_beats_automatic_beats_manual_retargeting() {
    let built = default_avatar();
    let avatar = &built.avatar;
    let landmarks = &face_mask().landmarks;
    let mut totals = [[0.0f64; 6]; 3]; // method × (face rmse, max, corners rmse, max, lips rmse, max)
    let mut count = 0.0;
    for subject in 1..=4 {
        let implanted_subject::Subject {
            session,
            found,
            retargeting,
            implanted,
            ..
        } = implanted_subject::implanted_subject(subject);
        assert!(session.truth.is_some(), "simulated");
        let shapes = AnimationShapes::new(avatar, &retargeting, implanted.shapes);
        // The mouth corners and the lip contour, as face vertices.
        let template: Vec<DVec3> = session
            .template
            .neutral
            .iter()
            .map(|p| p.as_dvec3())
            .collect();
        let at = |i: &u32| template[*i as usize];
        let corners: Vec<DVec3> = landmarks.lip_corners.iter().map(at).collect();
        let lips: Vec<DVec3> = landmarks
            .upper_lip
            .iter()
            .chain(&landmarks.lower_lip)
            .map(at)
            .collect();
        let corner_set = face_vertices_near(&found, &template, &corners, 0.012);
        let lip_set = face_vertices_near(&found, &template, &lips, 0.004);
        for test in likeness_on_avatar(&session, &found, &shapes) {
            for (m, errors) in test.errors_mm.iter().enumerate() {
                for (q, set) in [None, Some(&corner_set[..]), Some(&lip_set[..])]
                    .into_iter()
                    .enumerate()
                {
                    let e = summarize(errors, set);
                    totals[m][2 * q] += e.rmse_mm;
                    totals[m][2 * q + 1] += e.max_mm;
                }
            }
            count += 1.0;
        }
    }
    let names = ["manual", "automatic", "personalized"];
    for (m, t) in totals.iter().enumerate() {
        eprintln!(
            "{:>12}: face RMSE {:.3} max {:.3} mm; mouth corners RMSE {:.3} max {:.3}; lip contour RMSE {:.3} max {:.3}",
            names[m],
            t[0] / count,
            t[1] / count,
            t[2] / count,
            t[3] / count,
            t[4] / count,
            t[5] / count
        );
    }
    let rmse = |m: usize, q: usize| totals[m][2 * q] / count;
    eprintln!(
        "ratios: personalized/automatic {:.3}, automatic/manual {:.3} (face); personalized/manual {:.3} (corners), {:.3} (lips)",
        rmse(2, 0) / rmse(1, 0),
        rmse(1, 0) / rmse(0, 0),
        rmse(2, 1) / rmse(0, 1),
        rmse(2, 2) / rmse(0, 2)
    );
    for q in 0..3 {
        assert!(
            rmse(2, q) < rmse(1, q),
            "personalized not better than automatic ({q})"
        );
        assert!(
            rmse(1, q) < rmse(0, q),
            "automatic not better than manual ({q})"
        );
    }
}
