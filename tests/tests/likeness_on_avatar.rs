//! Does the avatar look like the person? (§4.2, Fig. 7 and 8.) On the
//! committed simulated subjects, each test expression is animated on the
//! default avatar three ways from the tracked weights `w` — manual
//! retargeting (the avatar's own shape `j` driven by weight `j`, what Unity
//! Live Capture and Live Link do), automatic retargeting (`Σ w_j A_j`,
//! Eq. 4) and the personalized avatar (`Σ w_j` of the implanted shapes) —
//! and compared on the avatar's face region with the subject's true
//! expression carried onto the avatar by `M`. Errors in millimetres at the
//! mask's scale; also on the mouth corners (face vertices within 12 mm of
//! a corner) and the lip contour (within 4 mm of a lip row), where the
//! paper says the differences are.

use glam::DVec3;
use likeness::Blendshape;
use likeness::avatar::partial_transfer::implant;
use likeness::avatar::registration::find_face;
use likeness::avatar::retargeting::retarget;
use likeness::personalize::{Method, personalize};
use likeness_sim::default_avatar::default_avatar;
use likeness_sim::face_mask::face_mask;

/// RMSE and max (mm) of `got` against `truth` over `vertices` (indices
/// into both), `scale` avatar units per metre.
fn errors(got: &[DVec3], truth: &[DVec3], vertices: &[usize], scale: f64) -> (f64, f64) {
    let (mut sum, mut max) = (0.0, 0.0f64);
    for &i in vertices {
        let e = (got[i] - truth[i]).length() / scale * 1000.0;
        sum += e * e;
        max = max.max(e);
    }
    ((sum / vertices.len().max(1) as f64).sqrt(), max)
}

#[test]
fn personalized_beats_automatic_beats_manual_retargeting() {
    let built = default_avatar();
    let avatar = &built.avatar;
    let landmarks = &face_mask().landmarks;
    let mut totals = [[0.0f64; 6]; 3]; // method × (face rmse, max, corners rmse, max, lips rmse, max)
    let mut count = 0.0;
    for subject in 1..=4 {
        let session =
            likeness::session::file::read(likeness_tests::committed::path(subject)).expect("reads");
        let truth = session.truth.as_ref().expect("simulated");
        let person = personalize(&session, Method::DEFAULT)
            .expect("personalizes")
            .shapes;
        let rig = session.template.blendshapes().expect("a template");
        let found = find_face(avatar, &session.topology, &rig).expect("a face");
        let retargeting = retarget(avatar, &found, &person).expect("solves");
        let implanted = implant(
            avatar,
            &found,
            &retargeting,
            &person,
            session.topology.triangles(),
        )
        .expect("implants");
        let automatic = retargeting.displacements(avatar);
        let own: Vec<Vec<glam::Vec3>> = Blendshape::ALL
            .iter()
            .map(|b| avatar.named_displacement(b.name()))
            .collect();
        let s = found.similarity;
        // The face vertices and the two subsets, as indices into map.face.
        let on_mask = found.map.apply(
            &session
                .template
                .neutral
                .iter()
                .map(|p| p.as_dvec3())
                .collect::<Vec<_>>(),
        );
        let template = |i: u32| session.template.neutral[i as usize].as_dvec3();
        let corners: Vec<DVec3> = landmarks.lip_corners.iter().map(|&i| template(i)).collect();
        let lips: Vec<DVec3> = landmarks
            .upper_lip
            .iter()
            .chain(&landmarks.lower_lip)
            .map(|&i| template(i))
            .collect();
        let all: Vec<usize> = (0..found.map.face.len()).collect();
        let near = |points: &[DVec3], within: f64| -> Vec<usize> {
            (0..on_mask.len())
                .filter(|&f| points.iter().any(|c| (on_mask[f] - *c).length() < within))
                .collect()
        };
        let (corner_set, lip_set) = (near(&corners, 0.012), near(&lips, 0.004));
        for (k, test) in session.tests.iter().enumerate() {
            let true_delta: Vec<DVec3> = truth.tests[k]
                .iter()
                .zip(&truth.neutral)
                .map(|(p, n)| s.apply_vector((*p - *n).as_dvec3()))
                .collect();
            let reference = found.map.apply(&true_delta);
            let animate = |shapes: &[Vec<glam::Vec3>]| -> Vec<DVec3> {
                found
                    .map
                    .face
                    .iter()
                    .map(|f| {
                        Blendshape::ALL
                            .iter()
                            .map(|b| {
                                shapes[b.index()][f.vertex as usize].as_dvec3()
                                    * f64::from(test.weights.get(*b))
                            })
                            .sum()
                    })
                    .collect()
            };
            for (m, shapes) in [&own, &automatic, &implanted.shapes]
                .into_iter()
                .enumerate()
            {
                let got = animate(shapes);
                for (q, set) in [&all, &corner_set, &lip_set].into_iter().enumerate() {
                    let (rmse, max) = errors(&got, &reference, set, s.scale);
                    totals[m][2 * q] += rmse;
                    totals[m][2 * q + 1] += max;
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
