//! The product's check of its own output
//! (`likeness::avatar::implant_check`): quiet on a good avatar, and loud,
//! naming the shape, on each kind of breakage it measures.

use glam::{DVec3, Vec3};
use likeness::Blendshape;
use likeness::avatar::glb::read::{GlbAvatar, read_avatar_bytes};
use likeness::avatar::implant_check::{EyeProbe, Fault, check_shapes, head_edges, head_triangles};
use likeness::avatar::personal_avatar::{AvatarWarning, PersonalAvatar};
use likeness::avatar::registration::part_roles::PartRole;
use likeness::avatar::rest_check::{REST_CREASE_SHARE, rest_creases, rest_spike};
use likeness::avatar::showing_through::InsideProbe;

fn default_glb() -> GlbAvatar {
    let bytes = likeness_sim::default_avatar::default_avatar_glb().expect("builds");
    read_avatar_bytes(&bytes, "default avatar").expect("reads")
}

fn subject_1(glb: &GlbAvatar) -> PersonalAvatar {
    likeness_tests::committed::personal_avatar_of(1, glb).expect("makes the avatar")
}

/// Committed subject 1's avatar with the subject's face taken.
fn subject_1_with_face(glb: &GlbAvatar) -> PersonalAvatar {
    likeness_tests::committed::personal_avatar_with(
        1,
        glb,
        likeness::avatar::personal_avatar::RestFace::Person,
    )
    .expect("makes the avatar")
}

/// Committed subject 1's implanted shapes on `made` (displacements per
/// avatar vertex), to break.
fn shapes_of(made: &PersonalAvatar) -> Vec<Vec<Vec3>> {
    made.implanted
        .as_ref()
        .expect("personalized")
        .shapes
        .clone()
}

#[test]
fn a_good_avatar_passes_the_check_in_silence() {
    let glb = default_glb();
    let made = subject_1(&glb);
    let faults: Vec<&AvatarWarning> = made
        .warnings
        .iter()
        .filter(|w| matches!(w, AvatarWarning::Fault(_)))
        .collect();
    assert!(faults.is_empty(), "{faults:?}");
}

#[test]
fn each_breakage_is_named_with_its_shape() {
    let glb = default_glb();
    let made = subject_1(&glb);
    let found = &made.registration;
    let avatar = &glb.avatar;
    let mut shapes = shapes_of(&made);
    let rest = avatar.positions();
    let face: Vec<u32> = found.map.face.iter().map(|f| f.vertex).collect();
    // A blink that no longer closes.
    shapes[Blendshape::EyeBlinkLeft.index()].fill(Vec3::ZERO);
    // A smile that turns the face inside out (its depth mirrored).
    let smile = &mut shapes[Blendshape::MouthSmileRight.index()];
    let depth = |p: Vec3| (found.similarity.rotation.transpose() * p.as_dvec3()).z;
    let mean_depth = face.iter().map(|&v| depth(rest[v as usize])).sum::<f64>() / face.len() as f64;
    let forward = (found.similarity.rotation * DVec3::Z).as_vec3();
    for &v in &face {
        let d = depth(rest[v as usize]) - mean_depth;
        smile[v as usize] = -2.0 * d as f32 * forward;
    }
    // A jaw that pulls every other face vertex 5 cm forward: torn edges.
    let jaw = &mut shapes[Blendshape::JawOpen.index()];
    for &v in face.iter().step_by(2) {
        jaw[v as usize] += 0.05 * forward;
    }
    // A retargeting that reproduced nothing of browInnerUp.
    let mut residual = made.retargeting.floored_residual.clone();
    residual[Blendshape::BrowInnerUp.index()] = 50.0;

    let faults = check_shapes(avatar, found, &shapes, &residual);
    let has =
        |b: Blendshape, kind: fn(&Fault) -> bool| faults.iter().any(|f| f.shape() == b && kind(f));
    assert!(
        has(Blendshape::EyeBlinkLeft, |f| matches!(
            f,
            Fault::BlinkOpen { .. }
        )),
        "{faults:?}"
    );
    assert!(
        has(Blendshape::MouthSmileRight, |f| matches!(
            f,
            Fault::Folded { .. }
        )),
        "{faults:?}"
    );
    assert!(
        has(Blendshape::JawOpen, |f| matches!(f, Fault::Torn { .. })),
        "{faults:?}"
    );
    assert!(
        has(Blendshape::BrowInnerUp, |f| matches!(
            f,
            Fault::Residual { .. }
        )),
        "{faults:?}"
    );
    for f in &faults {
        assert!(f.to_string().contains(f.shape().name()), "{f}");
    }
    // Nothing else was broken.
    let broken = [
        Blendshape::EyeBlinkLeft,
        Blendshape::MouthSmileRight,
        Blendshape::JawOpen,
        Blendshape::BrowInnerUp,
    ];
    assert!(
        faults.iter().all(|f| broken.contains(&f.shape())),
        "{faults:?}"
    );
}

/// The first eyeball of `found` on the default avatar: the skin vertices
/// by their distance from its centre, nearest first, and the change that
/// takes a vertex half a radius in front of the centre, deep inside.
struct FirstEye {
    skin: Vec<usize>,
    inside: Vec<Vec3>,
    radius: f64,
    centre: DVec3,
}

fn first_eye(
    avatar: &likeness::avatar::Avatar,
    found: &likeness::avatar::registration::FaceRegistration,
) -> FirstEye {
    let rest: Vec<DVec3> = avatar.positions().iter().map(|p| p.as_dvec3()).collect();
    let eye = &found.eyeballs[0];
    let centre = eye.iter().map(|&v| rest[v as usize]).sum::<DVec3>() / eye.len() as f64;
    let radius = eye
        .iter()
        .map(|&v| (rest[v as usize] - centre).length())
        .fold(0.0, f64::max);
    let forward = found.similarity.rotation * DVec3::Z;
    let mut skin: Vec<usize> = (0..rest.len())
        .filter(|v| !found.eyeballs.iter().flatten().any(|e| *e as usize == *v))
        .collect();
    skin.sort_by(|a, b| {
        (rest[*a] - centre)
            .length()
            .total_cmp(&(rest[*b] - centre).length())
    });
    let inside = rest
        .iter()
        .map(|p| (centre + 0.5 * radius * forward - *p).as_vec3())
        .collect();
    FirstEye {
        skin,
        inside,
        radius,
        centre,
    }
}

#[test]
fn a_lid_pushed_into_the_eyeball_is_found() {
    lid_pushed_into_the_eyeball_is_found(&default_glb());
}

/// The same on the low-poly variant, whose eyeballs are wound inside out:
/// read from their own normals, a lid inside them looked outside, and the
/// check could not see it.
#[test]
fn a_lid_pushed_into_an_eyeball_wound_inside_out_is_found() {
    let variant = likeness_sim::avatar_variants::avatar_variants()
        .into_iter()
        .find(|v| v.name == "low-poly")
        .expect("the variant");
    lid_pushed_into_the_eyeball_is_found(
        &read_avatar_bytes(&variant.glb, variant.name).expect("reads"),
    );
}

/// Subject 1's eyeSquintLeft on `glb`, with the skin vertex nearest the
/// first eyeball's centre taken inside it, is warned of.
fn lid_pushed_into_the_eyeball_is_found(glb: &GlbAvatar) {
    let made = subject_1(glb);
    let found = &made.registration;
    let avatar = &glb.avatar;
    let mut shapes = shapes_of(&made);
    let eye = first_eye(avatar, found);
    // eyeSquintLeft takes the skin vertex nearest the eyeball's centre
    // deep inside.
    let nearest = eye.skin[0];
    let rest = avatar.positions()[nearest].as_dvec3();
    assert!((rest - eye.centre).length() < 1.5 * eye.radius);
    shapes[Blendshape::EyeSquintLeft.index()][nearest] = eye.inside[nearest];
    let faults = check_shapes(avatar, found, &shapes, &made.retargeting.floored_residual);
    assert!(
        faults.iter().any(|f| matches!(
            f,
            Fault::LidInEyeball {
                shape: Blendshape::EyeSquintLeft,
                ..
            }
        )),
        "{faults:?}"
    );
}

/// A vertex of the mouth's lining brought out through the skin in
/// subject 1's mouthSmileLeft is warned of, naming the shape; the same
/// vertex moved as far back into the head is not.
#[test]
fn the_mouths_lining_brought_through_the_skin_is_found() {
    let glb = default_glb();
    let made = subject_1(&glb);
    let found = &made.registration;
    let avatar = &glb.avatar;
    let mut shapes = shapes_of(&made);
    let smile = Blendshape::MouthSmileLeft.index();
    let probe = InsideProbe::new(avatar, found);
    let forward = probe.forward();
    let rest = avatar.positions();
    let mm = found.similarity.scale / 1000.0;
    // The lining's vertices (parts that are neither skin, eyeball, teeth
    // nor tongue) the probe looks at.
    let offsets = avatar.vertex_offsets();
    let lining = |v: u32| {
        let part = offsets.iter().rposition(|&o| o <= v as usize).unwrap_or(0);
        found.roles.get(part) == Some(&PartRole::Other)
    };
    let got = &shapes[smile];
    let posed = |v: u32, by: f64| (rest[v as usize] + got[v as usize]).as_dvec3() + forward * by;
    // The first lining vertex that 10 mm forward lies more than 1 mm in
    // front of the skin.
    let (v, by) = probe
        .places()
        .iter()
        .filter(|p| p[0] == p[1] && lining(p[0]))
        .find_map(|p| {
            let v = p[0];
            let d = probe.depths_near(
                |u| {
                    if u == v {
                        posed(u, 10.0 * mm)
                    } else {
                        posed(u, 0.0)
                    }
                },
                &[*p],
            );
            (d[0] > mm).then_some((v, 10.0 * mm))
        })
        .expect("a lining vertex within 10 mm of the skin");
    let residual = &made.retargeting.floored_residual;
    assert!(
        !check_shapes(avatar, found, &shapes, residual)
            .iter()
            .any(|f| matches!(f, Fault::InsideShowing { .. })),
        "subject 1's own shapes show nothing"
    );
    let mut back = shapes.clone();
    back[smile][v as usize] -= (forward * by).as_vec3();
    assert!(
        !check_shapes(avatar, found, &back, residual)
            .iter()
            .any(|f| matches!(f, Fault::InsideShowing { .. })),
        "moved back into the head, it does not show"
    );
    shapes[smile][v as usize] += (forward * by).as_vec3();
    let faults = check_shapes(avatar, found, &shapes, residual);
    assert!(
        faults.iter().any(|f| matches!(
            f,
            Fault::InsideShowing {
                shape: Blendshape::MouthSmileLeft,
                ..
            }
        )),
        "{faults:?}"
    );
    let text = faults
        .iter()
        .find(|f| matches!(f, Fault::InsideShowing { .. }))
        .map(|f| f.to_string())
        .unwrap_or_default();
    assert!(
        text.contains("mouthSmileLeft") && text.contains("behind the skin"),
        "{text}"
    );
}

#[test]
fn a_lid_counts_only_where_the_own_shape_keeps_it_out() {
    let glb = default_glb();
    let made = subject_1(&glb);
    let found = &made.registration;
    let avatar = &glb.avatar;
    let eye = first_eye(avatar, found);
    // The two skin vertices nearest the eyeball's centre, each taken deep
    // inside by a shape.
    let (a, b) = (eye.skin[0], eye.skin[1]);
    let inside = |v: usize| eye.inside[v];
    let probe = EyeProbe::new(avatar, found, &found.eyeballs[0]);
    let none = vec![Vec3::ZERO; avatar.vertex_count()];
    let mut own = none.clone();
    own[a] = inside(a);
    let mut got = own.clone();
    // Where the own shape takes the lid in too, it is the rig's own.
    assert_eq!(probe.deepest_lid(&own, &got, 0.0).0, 0.0);
    // Where only the person's shape takes it in, it is found.
    got[b] = inside(b);
    let (depth, vertex) = probe.deepest_lid(&own, &got, 0.0);
    assert_eq!(vertex as usize, b);
    assert!(depth > 0.0);
    // Without an own shape, the lid the own shape took in counts too.
    let (alone, _) = probe.deepest_lid(&none, &own, 0.0);
    assert!(alone > 0.0);
}

#[test]
fn a_spike_at_rest_is_found_naming_its_part() {
    let glb = default_glb();
    let made = subject_1_with_face(&glb);
    let taken = made.taken_face.as_ref().expect("the person's face");
    let found = &made.registration;
    assert_eq!(
        rest_spike(&glb.avatar, found, &taken.moved, taken.asked_largest_mm),
        None
    );
    // One vertex of the mouth's lining (off the face) thrown 20 cm.
    let mut moved = taken.moved.clone();
    let lining = glb
        .avatar
        .parts()
        .iter()
        .position(|p| p.name.contains("mouth") || p.name.contains("Mouth"))
        .unwrap_or(3);
    let v = glb.avatar.vertex_offsets()[lining] + 5;
    moved[v] += DVec3::new(0.0, 0.0, 0.2);
    let spike = rest_spike(&glb.avatar, found, &moved, taken.asked_largest_mm).expect("a spike");
    assert_eq!(spike.vertex as usize, v);
    assert!(spike.moved_mm > 150.0 && spike.asked_mm < 20.0, "{spike:?}");
    assert!(spike.to_string().contains(&spike.part), "{spike}");
}

/// A simulated person's face bends the default avatar's skin gently and is
/// taken; the same change with a patch of the head's skin crumpled (every
/// other vertex pushed in and out) is found as creases.
#[test]
fn a_face_that_creases_the_skin_at_rest_is_found() {
    let glb = default_glb();
    let made = subject_1_with_face(&glb);
    let taken = made.taken_face.as_ref().expect("the person's face");
    let found = &made.registration;
    // The scan bending nothing: every crease is the taking's.
    let flat = vec![0.0; glb.avatar.vertex_count()];
    assert_eq!(rest_creases(&glb.avatar, found, &taken.moved, &flat), None);
    // Crumple the head's skin round one point of the face: 1.5 mm in and
    // out on alternate vertices, where the skin's triangles are 1–2 mm.
    let rest = glb.avatar.positions();
    let triangles = head_triangles(&glb.avatar, found);
    let centre = rest[triangles[triangles.len() / 2][0] as usize];
    let mm = found.similarity.scale / 1000.0;
    let mut moved = taken.moved.clone();
    let forward = found.similarity.rotation * DVec3::Z;
    for (v, p) in rest.iter().enumerate() {
        if (*p - centre).length() < 15.0 * mm as f32 {
            let sign = if v % 2 == 0 { 1.0 } else { -1.0 };
            moved[v] += forward * (sign * 1.5 * mm);
        }
    }
    let creases = rest_creases(&glb.avatar, found, &moved, &flat).expect("creases");
    assert!(creases.edges > creases.limit, "{creases:?}");
    assert_eq!(
        creases.limit,
        (REST_CREASE_SHARE * head_edges(&glb.avatar, found).len() as f64).floor() as usize
    );
    assert!(
        creases.to_string().contains("keeps its own face"),
        "{creases}"
    );
    // Where the scan itself bends as much (less 22.5°), the edges are the
    // person's: a scan bending the mask by 180° allows any crumple.
    let bent = vec![std::f64::consts::PI; glb.avatar.vertex_count()];
    assert_eq!(rest_creases(&glb.avatar, found, &moved, &bent), None);
    // A smooth new shape is no crease, however far it turns the skin: a
    // bump 20 mm high and 8 mm wide (σ) at the same place turns the skin
    // round it by up to 57°.
    let mut bump = taken.moved.clone();
    for (v, p) in rest.iter().enumerate() {
        let r = f64::from((*p - centre).length()) / mm;
        bump[v] += forward * (20.0 * mm * (-r * r / (2.0 * 8.0 * 8.0)).exp());
    }
    let turned = triangles
        .iter()
        .filter(|t| {
            let normal = |d: &[DVec3]| {
                let [a, b, c] = t.map(|v| rest[v as usize].as_dvec3() + d[v as usize]);
                (b - a).cross(c - a)
            };
            normal(&taken.moved).angle_between(normal(&bump)) > std::f64::consts::FRAC_PI_4
        })
        .count();
    assert!(turned > 50, "{turned} triangles turned past 45°");
    assert_eq!(rest_creases(&glb.avatar, found, &bump, &flat), None);
}
