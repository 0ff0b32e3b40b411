//! What nothing moves stays put: in every personalized shape on
//! the default avatar and on a variant of other proportions, a head vertex
//! moves only within `FADE_MM` (along the skin) of a vertex that the
//! person's mask, the avatar's own target or the retargeting `A_j` moves.
//! Before this, a personalized blink moved most of the default head by up
//! to 0.9 mm.

use glam::DVec3;
use likeness::Blendshape;
use likeness::avatar::glb::read::read_avatar_bytes;
use likeness::avatar::own_shapes::face_part_triangles;
use likeness::avatar::partial_transfer::stay_put::{FADE_MM, STILL_MM};
use likeness::avatar::registration::find_face::arkit_displacement;
use likeness::avatar::retargeting::mapped_shapes;
use likeness::geometry::edge_distance::edge_distances;
use likeness_sim::avatar_variants::avatar_variants;

fn assert_stays_put(name: &str, bytes: &[u8]) {
    let glb = read_avatar_bytes(bytes, name).expect("reads");
    let made = likeness_tests::committed::personal_avatar_of(1, &glb).expect("made");
    let avatar = &glb.avatar;
    let found = &made.registration;
    let implanted = made.implanted.as_ref().expect("personalized");
    let session = likeness_tests::committed::read(1).expect("reads");
    let person =
        likeness::personalize::personalize(&session, likeness::personalize::Method::DEFAULT)
            .expect("personalizes")
            .shapes;
    let person_moves = mapped_shapes(found, &person).expect("fits");
    let retargeted = made.retargeting.displacements(avatar);
    let positions: Vec<DVec3> = avatar.positions().iter().map(|p| p.as_dvec3()).collect();
    let triangles = face_part_triangles(avatar, found);
    let to_avatar = found.similarity.scale / 1000.0;
    let (still, fade) = (STILL_MM * to_avatar, FADE_MM * to_avatar);
    let mut head = vec![false; positions.len()];
    triangles
        .iter()
        .flatten()
        .for_each(|&v| head[v as usize] = true);
    for b in Blendshape::ALL {
        let j = b.index();
        let mut cause = vec![false; positions.len()];
        for (f, m) in found.map.face.iter().zip(&person_moves[j]) {
            cause[f.vertex as usize] |= m.length() > still;
        }
        if let Some(own) = arkit_displacement(avatar, b) {
            cause
                .iter_mut()
                .zip(&own)
                .for_each(|(c, o)| *c |= *o != DVec3::ZERO);
        }
        cause
            .iter_mut()
            .zip(&retargeted[j])
            .for_each(|(c, a)| *c |= f64::from(a.length()) > still);
        let distance = edge_distances(&positions, &triangles, &cause, fade);
        let strays = (0..positions.len())
            .filter(|&v| head[v] && implanted.shapes[j][v] != glam::Vec3::ZERO)
            .filter(|&v| distance[v] > fade * 1.0001)
            .count();
        assert_eq!(
            strays, 0,
            "{name}: {b} moves {strays} head vertices nothing moves"
        );
    }
}

#[test]
fn what_nothing_moves_stays_put_on_the_default_avatar_and_other_proportions() {
    let bytes = likeness_sim::default_avatar::default_avatar_glb().expect("builds");
    assert_stays_put("default avatar", &bytes);
    let other = avatar_variants()
        .into_iter()
        .find(|v| v.name == "other-proportions")
        .expect("a variant of other proportions");
    assert_stays_put(other.name, &other.glb);
}
