//! The seamless partial deformation transfer (§3.3, Fig. 3) on the default
//! avatar: the avatar's own rig as the mask sees it (the generic template,
//! its jawOpen rounded at the mask's vertices) implanted gives back the
//! avatar's own shapes (its face is the template's surface), and a
//! person's shapes meet the rest of the head without a seam.

mod implanted_subject;

use likeness_tests::seam::{outline_vertices, seam_statistics, seam_statistics_where};

use glam::Vec3;
use likeness::Blendshape;
use likeness::avatar::partial_transfer::{Implanted, implant};
use likeness::avatar::registration::{FaceRegistration, find_face};
use likeness::avatar::retargeting::retarget;
use likeness::avatar::target_names::arkit_targets;
use likeness_sim::default_avatar::default_avatar;
use likeness_sim::face_mask::face_mask;

/// Committed subject `n` implanted into the default avatar: the face found
/// and the result.
fn implanted_subject(n: u64) -> (FaceRegistration, Implanted) {
    let s = implanted_subject::implanted_subject(n);
    (s.found, s.implanted)
}

/// The default avatar's own shapes are its rig on the mask
/// (`DefaultAvatar::own_rig_on_mask`: the template, jawOpen rounded at the
/// mask's vertices), interpolated on its face and continued past it:
/// implanting that rig must give them back (measured: every shape within
/// 0.052 mm, jawOpen's of its 40 mm the farthest; the blinks 0.044 of 7.8).
#[test]
fn the_template_implanted_gives_back_the_avatars_own_shapes() {
    let built = default_avatar();
    let avatar = &built.avatar;
    let mask = face_mask();
    let rig = built.own_rig_on_mask();
    let found = find_face(avatar, &mask.topology, &rig).expect("a face");
    let retargeting = retarget(avatar, &found, &rig).expect("solves");
    let started = std::time::Instant::now();
    let implanted = implant(
        avatar,
        &found,
        &retargeting,
        &rig,
        (mask.topology.triangles(), rig.neutral()),
    )
    .expect("implants");
    let seconds = started.elapsed().as_secs_f64();
    eprintln!(
        "implant: {} face vertices, {} next to them, {:.0} ms for 52 shapes",
        implanted.face_vertices,
        implanted.adjacent_vertices,
        seconds * 1e3
    );
    assert!(implanted.adjacent_vertices > 1000);
    for shape in Blendshape::ALL {
        let own = arkit_targets(avatar).displacement(avatar, shape);
        let got = &implanted.shapes[shape.index()];
        let reach = own.iter().map(|d| d.length()).fold(0.0, f32::max);
        let worst = got
            .iter()
            .zip(&own)
            .map(|(a, b)| (*a - *b).length())
            .fold(0.0, f32::max);
        assert!(
            worst <= 0.02 * reach + 5e-5,
            "{shape}: {:.3} mm off of {:.2} mm",
            worst * 1e3,
            reach * 1e3
        );
    }
}

/// The seam statistic on the avatar's own rig on the mask implanted, where the truth (the
/// avatar's own shapes) has no seam: along the face border, and just inside
/// and outside it, the implant stretches and bends the skin as the avatar's
/// own jawOpen, mouthSmileLeft and browInnerUp do (within 10%, or 10⁻⁴).
///
/// On a person's shapes (committed subjects 1 and 2), the seam criterion
/// along the face's outline, where the person's face meets the
/// avatar's own head (Fig. 3): the mean edge strain and the mean dihedral
/// change of the border edges are no larger than the larger of the two
/// bands beside them (a border that is a local peak of either is a seam),
/// with the template check's tolerance (10%, or 10⁻⁴: subject 2's smile
/// strains the outline by 0.00079 against 0.00072 inside).
/// The rims of the eyes and the mouth, where step 1's upper lid meets step
/// 2's lower lid, are printed too (all borders), not asserted: there the
/// lids and lips bend by themselves. Before the blending margin
/// (`BLEND_MARGIN_MM`) browInnerUp's outline strain was 0.0079 against
/// 0.0021 inside.
#[test]
fn the_implant_adds_no_seam_where_the_truth_has_none() {
    use likeness::personalize::{Method, personalize};
    let session = likeness::session::file::read(likeness_tests::committed::path(1)).expect("reads");
    let built = default_avatar();
    let avatar = &built.avatar;
    let rig = session.template.blendshapes().expect("a template");
    let found = find_face(avatar, &session.topology, &rig).expect("a face");
    let skin = built.skin;
    let offsets = avatar.vertex_offsets();
    let part = &avatar.parts()[skin];
    let mut face = vec![false; part.positions.len()];
    for f in &found.map.face {
        let v = f.vertex as usize;
        if (offsets[skin]..offsets[skin + 1]).contains(&v) {
            face[v - offsets[skin]] = true;
        }
    }
    let outline = outline_vertices(&found, &session.topology, avatar, skin);
    let person = personalize(&session, Method::DEFAULT)
        .expect("personalizes")
        .shapes;
    let other = likeness::session::file::read(likeness_tests::committed::path(2)).expect("reads");
    let person_2 = personalize(&other, Method::DEFAULT)
        .expect("personalizes")
        .shapes;
    for (who, shapes) in [
        ("template", &built.own_rig_on_mask()),
        ("subject 1", &person),
        ("subject 2", &person_2),
    ] {
        let retargeting = retarget(avatar, &found, shapes).expect("solves");
        let implanted = implant(
            avatar,
            &found,
            &retargeting,
            shapes,
            (session.topology.triangles(), rig.neutral()),
        )
        .expect("implants");
        for shape in [
            Blendshape::JawOpen,
            Blendshape::MouthSmileLeft,
            Blendshape::BrowInnerUp,
        ] {
            let d = &implanted.shapes[shape.index()][offsets[skin]..offsets[skin + 1]];
            let got = seam_statistics(&part.positions, &part.triangles, &face, d);
            eprintln!(
                "{who}, {shape}: edge strain border {:.4} inside {:.4} outside {:.4}; dihedral change (rad) border {:.4} inside {:.4} outside {:.4}",
                got[0].0, got[1].0, got[2].0, got[0].1, got[1].1, got[2].1
            );
            if who != "template" {
                let at =
                    seam_statistics_where(&part.positions, &part.triangles, &face, d, &outline);
                eprintln!(
                    "{who}, {shape}, outline: edge strain border {:.4} inside {:.4} outside {:.4}; dihedral change (rad) border {:.4} inside {:.4} outside {:.4}",
                    at[0].0, at[1].0, at[2].0, at[0].1, at[1].1, at[2].1
                );
                // The template check's tolerance: 10%, or 10⁻⁴.
                let peak = |x: f64, a: f64, b: f64| x <= 1.1 * a.max(b) + 1e-4;
                assert!(
                    peak(at[0].0, at[1].0, at[2].0),
                    "{who}, {shape}: a strain seam along the outline {at:?}"
                );
                assert!(
                    peak(at[0].1, at[1].1, at[2].1),
                    "{who}, {shape}: a bending seam along the outline {at:?}"
                );
                continue;
            }
            let index = avatar.meshes()[part.mesh]
                .target_names
                .iter()
                .position(|n| n == shape.name())
                .expect("the avatar has it");
            let own = seam_statistics(
                &part.positions,
                &part.triangles,
                &face,
                &part.targets[index],
            );
            for (g, o) in got.iter().zip(&own) {
                assert!(
                    (g.0 - o.0).abs() <= 0.1 * o.0 + 1e-4,
                    "{shape}: strain {got:?} against {own:?}"
                );
                assert!(
                    (g.1 - o.1).abs() <= 0.1 * o.1 + 1e-4,
                    "{shape}: bend {got:?} against {own:?}"
                );
            }
        }
    }
}

/// After the transfer no lid vertex lies inside an eyeball, in any of the
/// 52 shapes of committed subject 1 nor in any of its test expressions'
/// weight combinations (measured: the repair had nothing to move on this
/// subject; its own unit test puts a lid back). A blink with a downward
/// gaze or a squint with an upward one, two shapes at full weight that no
/// capture combines, keeps every lid within the check's limit
/// ([`likeness::avatar::implant_check::LID_DEPTH_MM`]): each shape is
/// repaired on its own, and a sum of two is not. Measured: the blink with
/// the gaze 0; the squint looking up 0.19 mm (two lid vertices) since
/// Eq. (4)'s weights are kept in `[0, 1]` (its negative blink of −0.11 had
/// lifted the lid clear).
#[test]
fn no_lid_ends_inside_an_eyeball() {
    use likeness::avatar::partial_transfer::eyelid_repair::{Eyeball, repair_eyelids};
    let subject = implanted_subject::implanted_subject(1);
    let implanted = &subject.implanted;
    let built = default_avatar();
    let avatar = &built.avatar;
    let rest: Vec<glam::DVec3> = avatar.positions().iter().map(|p| p.as_dvec3()).collect();
    let offsets = avatar.vertex_offsets();
    let eyeballs: Vec<Eyeball> = built
        .eyes
        .iter()
        .map(|&i| Eyeball::new(&rest, avatar.part_triangles(&[i])))
        .collect();
    let skin: Vec<u32> = (offsets[built.skin] as u32..offsets[built.skin + 1] as u32).collect();
    // Counting what a repair with no offset would move counts the vertices inside.
    let inside = |d: &[Vec3]| {
        let mut d: Vec<glam::DVec3> = d.iter().map(|x| x.as_dvec3()).collect();
        repair_eyelids(&rest, &[], &mut d, &skin, &eyeballs, 0.0, 0.01)
    };
    eprintln!(
        "lid vertices repaired over the 52 shapes: {}",
        implanted.lids_repaired
    );
    for shape in Blendshape::ALL {
        assert_eq!(inside(&implanted.shapes[shape.index()]), 0, "{shape}");
    }
    let combine = |weights: &[(Blendshape, f32)]| -> Vec<Vec3> {
        let mut sum = vec![Vec3::ZERO; rest.len()];
        for &(shape, w) in weights {
            for (s, d) in sum.iter_mut().zip(&implanted.shapes[shape.index()]) {
                *s += w * *d;
            }
        }
        sum
    };
    for test in &subject.session.tests {
        let weights: Vec<(Blendshape, f32)> = test.weights.iter().collect();
        assert_eq!(inside(&combine(&weights)), 0, "test expression {}", test.id);
    }
    for pair in [
        [Blendshape::EyeBlinkLeft, Blendshape::EyeLookDownLeft],
        [Blendshape::EyeSquintRight, Blendshape::EyeLookUpRight],
    ] {
        let sum = combine(&[(pair[0], 1.0), (pair[1], 1.0)]);
        // How deep a lid is: how far a repair with no offset moves it.
        let before: Vec<glam::DVec3> = sum.iter().map(|x| x.as_dvec3()).collect();
        let mut repaired = before.clone();
        repair_eyelids(&rest, &[], &mut repaired, &skin, &eyeballs, 0.0, 0.01);
        let deepest = before
            .iter()
            .zip(&repaired)
            .map(|(a, b)| (*a - *b).length())
            .fold(0.0, f64::max);
        let to_mm = 1000.0 / subject.found.similarity.scale;
        eprintln!(
            "{} + {}: deepest lid {:.3} mm",
            pair[0],
            pair[1],
            deepest * to_mm
        );
        assert!(
            deepest * to_mm <= likeness::avatar::implant_check::LID_DEPTH_MM,
            "{} + {}: a lid {:.3} mm deep",
            pair[0],
            pair[1],
            deepest * to_mm
        );
    }
}

/// Eyeballs and teeth are found rigid from the avatar's own targets and stay
/// rigid in every implanted shape (A_j mixes rotations; the mix is replaced
/// by the closest rigid motion); the tongue, which tongueOut bends, is not
/// held rigid. Prints what was removed.
#[test]
fn eyes_and_teeth_stay_rigid() {
    use likeness::avatar::partial_transfer::rigid_parts::rigid_deviation;
    let (_, implanted) = implanted_subject(2);
    let built = default_avatar();
    let avatar = &built.avatar;
    for part in built.eyes.iter().chain(&built.teeth) {
        assert!(
            implanted.rigid_parts.contains(part),
            "{} not found rigid",
            avatar.parts()[*part].name
        );
    }
    assert!(!implanted.rigid_parts.contains(&built.tongue));
    let rest: Vec<glam::DVec3> = avatar.positions().iter().map(|p| p.as_dvec3()).collect();
    for (piece, removed) in implanted
        .rigid_pieces
        .iter()
        .zip(&implanted.rigid_deviation_removed)
    {
        let (part, vertices) = (piece.part, &piece.vertices);
        let worst = implanted
            .shapes
            .iter()
            .map(|d| {
                let d: Vec<glam::DVec3> = d.iter().map(|x| x.as_dvec3()).collect();
                rigid_deviation(&rest, &d, vertices)
            })
            .fold(0.0, f64::max);
        eprintln!(
            "{}: A_j's largest deviation from rigid {:.3} mm, after {:.5} mm",
            avatar.parts()[part].name,
            removed * 1e3,
            worst * 1e3
        );
        assert!(worst < 1e-5, "{}: {worst}", avatar.parts()[part].name);
    }
}

/// How far the person's implanted blink closes the avatar's eye: the
/// largest distance from a vertex of the avatar's upper lid row (those whose
/// true mask point lies on the mask's upper lid) to the lower lid row, as a
/// polyline from corner to corner (committed subject 1). Issue 11 asks
/// for 0.1 mm: before the lid contacts (`lid_contacts`) 0.93 mm (left) and
/// 0.84 mm (right), now below a micrometre.
#[test]
fn how_far_the_persons_blink_closes_the_avatars_eye() {
    let (found, implanted) = implanted_subject(1);
    let built = default_avatar();
    let avatar = &built.avatar;
    let mask = face_mask();
    let tris = mask.topology.triangles();
    let skin = avatar.vertex_offsets()[built.skin];
    for (side, shape) in [
        (0, Blendshape::EyeBlinkLeft),
        (1, Blendshape::EyeBlinkRight),
    ] {
        let corners = [
            mask.landmarks.eye_inner[side],
            mask.landmarks.eye_outer[side],
        ];
        let row = |lid: &[u32]| -> Vec<usize> {
            built
                .true_correspondence
                .iter()
                .enumerate()
                .filter(|(_, m)| {
                    let t = tris[m.triangle as usize];
                    let on: Vec<u32> = (0..3)
                        .filter(|&k| m.barycentric[k] > 1e-9)
                        .map(|k| t[k])
                        .collect();
                    on.iter().all(|i| lid.contains(i) || corners.contains(i))
                        && on.iter().any(|i| lid.contains(i))
                })
                .map(|(v, _)| skin + v)
                .collect()
        };
        let (upper, mut lower) = (
            row(&mask.landmarks.upper_lid[side]),
            row(&mask.landmarks.lower_lid[side]),
        );
        // The lower lid runs from corner to corner: the avatar vertices at
        // the corners end its polyline.
        lower.extend(
            built
                .true_correspondence
                .iter()
                .enumerate()
                .filter(|(_, m)| {
                    let t = tris[m.triangle as usize];
                    (0..3).any(|k| m.barycentric[k] > 1.0 - 1e-9 && corners.contains(&t[k]))
                })
                .map(|(v, _)| skin + v),
        );
        assert!(
            upper.len() >= 5 && lower.len() >= 5,
            "{} upper, {} lower",
            upper.len(),
            lower.len()
        );
        let rest = avatar.positions();
        let posed = |v: usize| rest[v] + implanted.shapes[shape.index()][v];
        // The lower lid as a polyline, its vertices in order across the eye.
        lower.sort_by(|a, b| rest[*a].x.total_cmp(&rest[*b].x));
        let lower_posed: Vec<glam::Vec3> = lower.iter().map(|&v| posed(v)).collect();
        let to_segment = |p: glam::Vec3, a: glam::Vec3, b: glam::Vec3| {
            let t = ((p - a).dot(b - a) / (b - a).length_squared().max(1e-20)).clamp(0.0, 1.0);
            (a + (b - a) * t - p).length()
        };
        let gap = upper
            .iter()
            .map(|&u| {
                let p = posed(u);
                lower_posed
                    .windows(2)
                    .map(|w| to_segment(p, w[0], w[1]))
                    .fold(f32::INFINITY, f32::min)
            })
            .fold(0.0, f32::max)
            / found.similarity.scale as f32
            * 1000.0;
        eprintln!(
            "{shape}: largest lid gap {gap:.3} mm over {} upper-lid vertices",
            upper.len()
        );
        assert!(gap <= 0.1, "{shape}: the lids stay {gap} mm apart");
    }
}

/// Whether the ray `o + s d`, `s > 0`, crosses triangle `abc`
/// ([`likeness_tests::avatar_quality::ray_hits`], in single precision).
fn ray_hits(o: glam::Vec3, d: glam::Vec3, t: [glam::Vec3; 3]) -> bool {
    likeness_tests::avatar_quality::ray_hits(o.as_dvec3(), d.as_dvec3(), t.map(|p| p.as_dvec3()))
}

/// With the person's blink implanted (committed subject 1), no point of
/// the closed eye's eyeball can be seen from the front: the ray from every
/// eyeball vertex towards the viewer (the face's forward axis) passes
/// through the skin.
#[test]
fn a_closed_eye_shows_no_eyeball_from_the_front() {
    let (found, implanted) = implanted_subject(1);
    let built = default_avatar();
    let avatar = &built.avatar;
    let rest = avatar.positions();
    let offsets = avatar.vertex_offsets();
    let forward = (found.similarity.rotation * glam::DVec3::Z).as_vec3();
    for (side, shape) in [
        (0, Blendshape::EyeBlinkLeft),
        (1, Blendshape::EyeBlinkRight),
    ] {
        let d = &implanted.shapes[shape.index()];
        let posed = |v: usize| rest[v] + d[v];
        // The eyeball of this side: the one the blink's lid covers, nearer
        // to the side's x sign in the face frame.
        let ball = found
            .eyeball_parts()
            .iter()
            .copied()
            .find(|&p| {
                let c = (offsets[p]..offsets[p + 1]).map(posed).sum::<glam::Vec3>()
                    / (offsets[p + 1] - offsets[p]) as f32;
                let x = (found.similarity.rotation.transpose()
                    * (c.as_dvec3() - found.similarity.translation))
                    .x;
                (x > 0.0) == (side == 0)
            })
            .expect("an eyeball on each side");
        let range = offsets[ball]..offsets[ball + 1];
        let centre = range.clone().map(posed).sum::<glam::Vec3>() / range.len() as f32;
        let skin: Vec<[glam::Vec3; 3]> = avatar
            .parts()
            .iter()
            .enumerate()
            .filter(|(i, _)| !found.eyeball_parts().contains(i))
            .flat_map(|(i, part)| {
                let o = offsets[i];
                part.triangles
                    .iter()
                    .map(move |t| t.map(|v| o + v as usize))
            })
            .map(|t| t.map(posed))
            .filter(|t| t.iter().any(|p| (*p - centre).length() < 0.03))
            .collect();
        let front: Vec<usize> = range
            .clone()
            .filter(|&v| (posed(v) - centre).dot(forward) > 0.0)
            .collect();
        let seen: Vec<usize> = front
            .iter()
            .copied()
            .filter(|&v| {
                let o = posed(v) + forward * 1e-5;
                !skin.iter().any(|t| ray_hits(o, forward, *t))
            })
            .collect();
        eprintln!(
            "{shape}: {} of {} front eyeball vertices seen from the front",
            seen.len(),
            front.len()
        );
        assert!(front.len() > 20);
        assert!(seen.is_empty(), "{shape}: eyeball vertices seen {seen:?}");
        // The same test sees the open eye at rest.
        let skin_at_rest: Vec<[glam::Vec3; 3]> = avatar
            .parts()
            .iter()
            .enumerate()
            .filter(|(i, _)| !found.eyeball_parts().contains(i))
            .flat_map(|(i, part)| {
                let (o, rest) = (offsets[i], &rest);
                part.triangles
                    .iter()
                    .map(move |t| t.map(|v| rest[o + v as usize]))
            })
            .collect();
        let open = range
            .clone()
            .filter(|&v| {
                let o = rest[v] + forward * 1e-5;
                (rest[v] - centre).dot(forward) > 0.0
                    && !skin_at_rest.iter().any(|t| ray_hits(o, forward, *t))
            })
            .count();
        assert!(
            open > 20,
            "{shape}: only {open} eyeball vertices seen at rest"
        );
    }
}

/// Beyond the blending margin of the face, the avatar follows `A_j`, in
/// every shape (committed subject 1): the correction of step 2 stops there
/// (`adjacent_step` docs), and a vertex no `A_j` moves stays exactly where
/// the avatar has it. Within the stay-put rule's still motion: what moves
/// less than `STILL_MM` is faded out (`stay_put`).
#[test]
fn beyond_the_blend_margin_the_avatar_follows_a_j_exactly() {
    use likeness::avatar::partial_transfer::stay_put::STILL_MM;
    use likeness::avatar::partial_transfer::{BLEND_MARGIN_MM, adjacent_step::within};
    let s = implanted_subject::implanted_subject(1);
    let (found, implanted) = (&s.found, &s.implanted);
    let built = default_avatar();
    let avatar = &built.avatar;
    let retargeted = s.retargeting.displacements(avatar);
    let positions: Vec<glam::DVec3> = avatar.positions().iter().map(|p| p.as_dvec3()).collect();
    let offsets = avatar.vertex_offsets();
    let triangles = avatar.part_triangles(&found.face_parts());
    let mut face = vec![false; positions.len()];
    for f in &found.map.face {
        face[f.vertex as usize] = true;
    }
    let near = within(
        &positions,
        &triangles,
        &face,
        BLEND_MARGIN_MM * found.similarity.scale / 1000.0,
    );
    let beyond: Vec<usize> = (0..positions.len())
        .filter(|&v| {
            found
                .face_parts()
                .iter()
                .any(|&i| (offsets[i]..offsets[i + 1]).contains(&v))
                && !near[v]
        })
        .collect();
    let moved_by_some_a = beyond
        .iter()
        .filter(|&&v| retargeted.iter().any(|a| a[v] != Vec3::ZERO))
        .count();
    assert!(
        beyond.len() > 1000 && moved_by_some_a > 100,
        "{} vertices beyond the margin, {moved_by_some_a} of them moved by some A_j",
        beyond.len()
    );
    let still = (STILL_MM * found.similarity.scale / 1000.0) as f32;
    for (j, shape) in implanted.shapes.iter().enumerate() {
        let still_zero = beyond
            .iter()
            .filter(|&&v| retargeted[j][v] == Vec3::ZERO && shape[v] != Vec3::ZERO)
            .count();
        assert_eq!(still_zero, 0, "{}", Blendshape::ALL[j]);
        let off = beyond
            .iter()
            .filter(|&&v| (shape[v] - retargeted[j][v]).length() > still * 1.0001)
            .count();
        assert_eq!(
            off,
            0,
            "{}: {off} vertices beyond the margin do not follow A_j",
            Blendshape::ALL[j]
        );
    }
}

/// Each lip takes its own motion up to the mouth's slit
/// (`registration::lip_sides`): on committed subject 1 implanted into the
/// default avatar, every face vertex the map takes moves as the person's
/// mask does at the vertex's true point on it, within 0.3 mm, in the
/// shapes that move the lips apart or together (a vertex of one lip given
/// the other's motion would be off by the mouth's opening, up to 21 mm in
/// jawOpen); within 10 mm of the corners, where the smoothing of the
/// transfer's folds there reaches (`partial_transfer::crease_smoothing`),
/// within 4 mm (measured 2.2 mm in mouthClose, 2.9 in mouthPucker, 1.2 in
/// mouthSmileLeft, 0.2 in jawOpen), and elsewhere within 1 mm in the
/// shapes it smoothed (measured 0.7 mm, mouthSmileLeft's cheek beside the
/// corner); the animation's likeness over the whole face is checked in
/// `likeness_on_avatar.rs`. The lips' edges are taken (nine in ten at least) but within
/// 3 mm of the corners, where the lips meet (measured: 0.17 mm at most,
/// mouthPucker; 2 of the edges' 62 vertices left to step 2; 538 of
/// the face's vertices left to step 2 in all, the lids' margins and the
/// corners, against 658 before).
#[test]
fn each_lip_moves_as_the_persons_up_to_the_slit() {
    let subject = implanted_subject::implanted_subject(1);
    let built = default_avatar();
    let tris = face_mask().topology.triangles();
    let start = built.avatar.vertex_offsets()[built.skin];
    let taken: std::collections::HashSet<usize> = subject
        .found
        .map
        .face
        .iter()
        .map(|f| f.vertex as usize)
        .collect();
    let positions = &built.avatar.parts()[built.skin].positions;
    // The mouth's corners, and how near them the creases the transfer
    // folds there are smoothed out (`partial_transfer::crease_smoothing`:
    // the untaken corner vertices' triangles turned 100–176° in
    // mouthClose and mouthPucker; three rounds reach 9 mm past them).
    let [mx, my] = likeness_sim::face_mask::MOUTH_CENTRE.map(|x| x as f32);
    let half_width = likeness_sim::face_mask::MOUTH_HALF_WIDTH as f32;
    let corners = [
        glam::Vec2::new(mx - half_width, my),
        glam::Vec2::new(mx + half_width, my),
    ];
    const CORNER: f32 = 0.010;
    for shape in [
        Blendshape::JawOpen,
        Blendshape::MouthClose,
        Blendshape::MouthPucker,
        Blendshape::MouthSmileLeft,
        Blendshape::MouthFunnel,
    ] {
        let delta = subject.person.delta(shape);
        let got = &subject.implanted.shapes[shape.index()];
        let mut worst = (0.0f64, 0usize);
        let mut worst_at_corners = 0.0f64;
        for (v, m) in built.true_correspondence.iter().enumerate() {
            if !taken.contains(&(start + v)) {
                continue;
            }
            let t = tris[m.triangle as usize];
            let truth: glam::DVec3 = (0..3)
                .map(|k| m.barycentric[k] * delta[t[k] as usize])
                .sum();
            let off = (got[start + v].as_dvec3() - truth).length();
            let p = positions[v];
            let at_a_corner = corners
                .iter()
                .any(|c| (p.truncate() - *c).length() < CORNER);
            if at_a_corner {
                worst_at_corners = worst_at_corners.max(off);
            } else if off > worst.0 {
                worst = (off, v);
            }
        }
        eprintln!(
            "{shape}: taken face vertices within {:.3} mm of the person's motion (worst at {:?}), {:.3} mm by the corners",
            worst.0 * 1e3,
            positions[worst.1],
            worst_at_corners * 1e3
        );
        // Where the smoothing removed folds the transfer made (mouthClose,
        // mouthPucker, and mouthSmileLeft's cheek beside the corner), the
        // motion moves by up to 0.7 mm away from the corners; a lip given
        // the other's motion would be off by millimetres more.
        let smoothed = matches!(
            shape,
            Blendshape::MouthClose | Blendshape::MouthPucker | Blendshape::MouthSmileLeft
        );
        let limit = if smoothed { 1e-3 } else { 3e-4 };
        assert!(worst.0 < limit, "{shape}: {:.3} mm off", worst.0 * 1e3);
        assert!(
            worst_at_corners < 4e-3,
            "{shape}: {:.3} mm off by a corner",
            worst_at_corners * 1e3
        );
    }
    // The mouth's edges (the skin's boundary loop round the mouth) are
    // taken, but near the corners.
    let mouth_y = my;
    let edges: Vec<usize> = (0..built.true_correspondence.len())
        .filter(|&v| {
            let p = positions[v];
            (p.y - mouth_y).abs() < 4e-4 && p.x.abs() < half_width - 0.003
        })
        .collect();
    assert!(edges.len() > 20, "{} lip edge vertices", edges.len());
    let left = edges
        .iter()
        .filter(|v| !taken.contains(&(start + **v)))
        .count();
    eprintln!("lip edges: {} of {} left to step 2", left, edges.len());
    assert!(
        left * 10 <= edges.len(),
        "lip edges left to step 2: {left} of {}",
        edges.len()
    );
}
