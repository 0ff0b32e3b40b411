//! Tests of how the default avatar looks: a material per kind of part,
//! painted eyes, tinted lips. Each fails if that detail is lost.

use super::*;
use crate::face_mask::{MOUTH_CENTRE, MOUTH_HALF_WIDTH};

fn avatar() -> &'static DefaultAvatar {
    default_avatar()
}

#[test]
fn every_part_has_a_plain_material_of_its_own_kind() {
    let a = avatar();
    let looks = part_looks(&a.avatar);
    let material = |part: usize| looks[part].as_ref().map(|l| l.0.as_str());
    assert_eq!(material(a.skin), Some("skin"));
    for side in 0..2 {
        assert_eq!(material(a.eyes[side]), Some("sclera"));
        assert_eq!(material(a.irises[side][0]), Some("iris"));
        assert_eq!(material(a.irises[side][1]), Some("pupil"));
    }
    assert_eq!(material(a.teeth[0]), Some("teeth"));
    assert_eq!(material(a.gums[1]), Some("gums"));
    assert_eq!(material(a.tongue), Some("tongue"));
    assert!(looks.iter().all(Option::is_some), "every part named");
    // The pupil is darker than the iris, the iris than the sclera.
    let luminance = |part: usize| {
        let c = looks[part].as_ref().unwrap().1.base_colour;
        0.2126 * c[0] + 0.7152 * c[1] + 0.0722 * c[2]
    };
    assert!(luminance(a.irises[0][1]) < luminance(a.irises[0][0]));
    assert!(luminance(a.irises[0][0]) < 0.5 * luminance(a.eyes[0]));
}

#[test]
fn iris_and_pupil_sit_on_the_cornea_and_turn_with_the_eyeball() {
    let a = avatar();
    for side in 0..2 {
        let c = a.eye_centres[side].as_dvec3();
        let eye = &a.avatar.parts[a.eyes[side]];
        let sclera_front = eye.positions[0].as_dvec3();
        for (k, &part) in a.irises[side].iter().enumerate() {
            let p = &a.avatar.parts[part];
            assert_eq!(p.mesh, eye.mesh, "one mesh per eye");
            for q in &p.positions {
                let q = q.as_dvec3();
                // On the cornea, just outside it, in front of the globe.
                let d = eyes::eye_distance(q, c, DMat3::IDENTITY);
                assert!(d > 0.0 && d <= eyes::PAINT_LIFT + 1e-6, "{d}");
                let axis = (q - c).cross(DVec3::Z).length();
                let radius = [eyes::IRIS_RADIUS, eyes::PUPIL_RADIUS][k];
                assert!(axis <= radius + 1e-6);
            }
            // Each gaze shape turns it exactly as it turns the eyeball.
            for s in eye_shapes(side) {
                let rot = shape_rotation(side, s);
                let t = &p.targets[s.index()];
                for (q, d) in p.positions.iter().zip(t) {
                    let q = q.as_dvec3();
                    let turned = c + rot * (q - c);
                    assert!((q + d.as_dvec3()).distance(turned) < 1e-6);
                }
            }
            assert!(sclera_front.z > c.z);
        }
    }
}

#[test]
fn the_lips_are_tinted_and_the_rest_of_the_skin_is_not() {
    let a = avatar();
    let options = glb_options(a);
    let colours = options.part_colours[a.skin].as_ref().unwrap();
    let skin = &a.avatar.parts[a.skin];
    assert_eq!(colours.len(), skin.positions.len());
    let lip_height = lips::VERMILION_HEIGHT[1];
    let (mut lips, mut rest) = (0, 0);
    for (p, c) in skin.positions.iter().zip(colours) {
        let (u, v) = (p.x as f64 - MOUTH_CENTRE[0], p.y as f64 - MOUTH_CENTRE[1]);
        if u.abs() < 0.5 * MOUTH_HALF_WIDTH && v.abs() < 0.3 * lip_height && p.z > 0.03 {
            // The middle of the lips: redder than the skin.
            assert!(c.y < 0.6 && c.x > c.y, "{c}");
            lips += 1;
        } else if (u.hypot(v)) > 2.0 * MOUTH_HALF_WIDTH {
            assert_eq!(*c, Vec3::ONE);
            rest += 1;
        }
    }
    assert!(lips > 20 && rest > 5_000, "{lips} on the lips, {rest} off");
}
