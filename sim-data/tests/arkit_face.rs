//! People simulated on ARKit's own mesh (`../shared/arkit-face/`, never
//! committed): the basis reads, its landmarks are ARKit's holes, and a
//! person on it is ARKit's face with a person's differences. Each test
//! skips, saying so, where `../shared/` is absent, and fails there under CI.

use glam::DVec3;
use likeness::Blendshape;
use likeness::geometry::mesh_boundary::boundary_loops;
use likeness_sim::arkit_face::{ArkitFace, shared_arkit_face, shared_arkit_face_dir};
use likeness_sim::face_basis::FaceBasis;
use likeness_sim::subject::Subject;
use likeness_sim::{SimulationOptions, simulate_session_with};

fn arkit() -> Option<&'static ArkitFace> {
    let face = shared_arkit_face();
    if face.is_none() {
        eprintln!(
            "skipped: {} is absent (it is never committed)",
            shared_arkit_face_dir().display()
        );
    }
    face
}

#[test]
fn the_landmarks_are_arkits_own_holes() {
    let Some(face) = arkit() else { return };
    let mask = &face.mask;
    assert_eq!(mask.topology.vertex_count(), 1220);
    assert_eq!(mask.topology.triangles().len(), 2304);
    let mut sizes: Vec<usize> = boundary_loops(&mask.topology)
        .expect("loops")
        .iter()
        .map(Vec::len)
        .collect();
    sizes.sort_unstable();
    assert_eq!(
        sizes,
        vec![24, 24, 36, 56],
        "ARKit's README: 56, 36, 24, 24"
    );
    let lm = &mask.landmarks;
    assert_eq!(lm.outline.len(), 56);
    assert_eq!(lm.upper_lip.len(), lm.lower_lip.len());
    for side in 0..2 {
        assert_eq!(lm.upper_lid[side].len(), lm.lower_lid[side].len());
        let p = |v: u32| mask.neutral[v as usize];
        // The left eye (side 0) is at +x; the inner corner is nearer the
        // midline; the upper lid lies above the lower.
        let sign = if side == 0 { 1.0 } else { -1.0 };
        assert!(sign * p(lm.eye_inner[side]).x > 0.0);
        assert!(p(lm.eye_inner[side]).x.abs() < p(lm.eye_outer[side]).x.abs());
        let mean_y = |row: &[u32]| row.iter().map(|v| p(*v).y).sum::<f32>() / row.len() as f32;
        assert!(mean_y(&lm.upper_lid[side]) > mean_y(&lm.lower_lid[side]));
    }
    // The carried parameter plane puts ARKit's eyes and mouth where the
    // simulator's are (eyes at (±32.5, 28) mm, mouth at (0, −47) mm), to
    // within the registration's slide: the midpoints of their corners.
    let centre = |row: &[u32]| {
        row.iter()
            .map(|v| mask.uv[*v as usize])
            .fold([0.0; 2], |a, b| [a[0] + b[0], a[1] + b[1]])
            .map(|x| x / row.len() as f64)
    };
    let left_eye = centre(&[lm.eye_inner[0], lm.eye_outer[0]]);
    assert!(
        (left_eye[0] - 0.0325).abs() < 0.006 && (left_eye[1] - 0.028).abs() < 0.006,
        "{left_eye:?}"
    );
    let mouth = centre(&lm.lip_corners);
    assert!(
        mouth[0].abs() < 0.004 && (mouth[1] + 0.047).abs() < 0.006,
        "{mouth:?}"
    );
}

/// Each lip of a person on ARKit's mesh moves as ARKit's own does in
/// `jawOpen`, the lips' curl behind the slit too: a vertex that ARKit's
/// template leaves with the skull never goes more than halfway with the
/// jaw, and one it moves with the jaw goes at least halfway. Carried by
/// its closest point alone, an upper-lip vertex of the curl once moved
/// 23 mm with the jaw where ARKit's moves it 2.5 mm.
#[test]
fn each_lip_of_a_person_on_arkits_mesh_moves_as_arkits_own() {
    use likeness::avatar::registration::lips_parting::{STILL, WITH_JAW};
    let Some(face) = arkit() else { return };
    let basis = FaceBasis::Arkit(face);
    let neutral: Vec<DVec3> = face.mask.neutral.iter().map(|p| p.as_dvec3()).collect();
    let [a, b] = face.mask.landmarks.lip_corners.map(|v| neutral[v as usize]);
    let (centre, radius) = ((a + b) / 2.0, a.distance(b) / 2.0);
    let near: Vec<usize> = (0..neutral.len())
        .filter(|&v| neutral[v].distance(centre) <= radius)
        .collect();
    let shares = |d: &[DVec3]| {
        let largest = near.iter().map(|&v| d[v].length()).fold(0.0, f64::max);
        near.iter()
            .map(|&v| d[v].length() / largest)
            .collect::<Vec<f64>>()
    };
    let template: Vec<DVec3> = face
        .template
        .delta(Blendshape::JawOpen)
        .iter()
        .map(|d| d.as_dvec3())
        .collect();
    let own = shares(&template);
    let middle = (STILL + WITH_JAW) / 2.0;
    for seed in 1..=5 {
        let person = Subject::on(basis, seed).model;
        let open: Vec<DVec3> = person
            .shape(Blendshape::JawOpen)
            .iter()
            .zip(&person.neutral)
            .map(|(s, n)| *s - *n)
            .collect();
        let theirs = shares(&open);
        for ((&v, o), t) in near.iter().zip(&own).zip(&theirs) {
            if *o <= STILL {
                assert!(
                    *t <= middle,
                    "seed {seed}: upper-lip vertex {v} moves {t:.2} with the jaw (ARKit's: {o:.2})"
                );
            } else if *o >= WITH_JAW {
                assert!(
                    *t >= middle,
                    "seed {seed}: lower-lip vertex {v} moves {t:.2} with the jaw (ARKit's: {o:.2})"
                );
            }
        }
    }
}

#[test]
fn a_person_on_arkits_mesh_is_arkits_face_with_a_persons_differences() {
    let Some(face) = arkit() else { return };
    let basis = FaceBasis::Arkit(face);
    for seed in 1..=5 {
        let person = Subject::on(basis, seed).model;
        let neutral_change: Vec<f64> = person
            .neutral
            .iter()
            .zip(&face.mask.neutral)
            .map(|(p, q)| (*p - q.as_dvec3()).length())
            .collect();
        let mean = neutral_change.iter().sum::<f64>() / neutral_change.len() as f64;
        // Proportions (σ 5–8%) and bumps (a few mm) on a face ~15 cm across.
        assert!(
            mean > 5e-4 && mean < 0.012,
            "seed {seed}: mean identity change {mean} m"
        );
        // Every person closes their eyes: each upper-lid vertex meets its
        // partner at eyeBlink = 1.
        for (side, blink) in [Blendshape::EyeBlinkLeft, Blendshape::EyeBlinkRight]
            .into_iter()
            .enumerate()
        {
            let closed = person.shape(blink);
            let lm = &face.mask.landmarks;
            let gap = lm.upper_lid[side]
                .iter()
                .zip(&lm.lower_lid[side])
                .map(|(u, l)| (closed[*u as usize] - closed[*l as usize]).length())
                .fold(0.0, f64::max);
            assert!(gap < 1e-4, "seed {seed}, {blink}: lids {gap} m apart");
        }
        // A shape is ARKit's plus a person's style: a smile still lifts
        // the corner it is named for, by centimetres as ARKit's does.
        let smile = person.shape(Blendshape::MouthSmileLeft);
        let corner = face.mask.landmarks.lip_corners[0] as usize;
        let lift: DVec3 = smile[corner] - person.neutral[corner];
        assert!(
            lift.y > 0.003 && lift.x > 0.0,
            "seed {seed}: the left corner moves {lift:?}"
        );
    }
}

#[test]
fn a_session_on_arkits_mesh_carries_arkits_topology_and_template() {
    let Some(face) = arkit() else { return };
    let options = SimulationOptions {
        face: FaceBasis::Arkit(face),
        geometry_window: Some(0.4),
        ..SimulationOptions::default()
    };
    let session = simulate_session_with(3, options, &mut |_, _| {});
    assert_eq!(session.topology.triangles(), face.mask.topology.triangles());
    assert_eq!(session.template.neutral, face.template.neutral);
    assert_eq!(session.template.shapes, face.template.shapes);
    assert_eq!(session.captures.len(), 52);
    let again = simulate_session_with(3, options, &mut |_, _| {});
    assert_eq!(
        likeness::session::file::encode(&session).expect("encodes"),
        likeness::session::file::encode(&again).expect("encodes"),
        "a seed makes the same session on ARKit's mesh every time"
    );
}
