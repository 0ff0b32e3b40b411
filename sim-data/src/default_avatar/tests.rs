//! Tests of the default avatar: they fail if its geometry, its truth or
//! its shapes break.

use super::*;
use crate::face_mask::face_mask;
use std::collections::{BTreeMap, BTreeSet};

fn avatar() -> &'static DefaultAvatar {
    default_avatar()
}

fn target<'a>(part: &'a AvatarPart, mesh: &AvatarMesh, name: &str) -> Option<&'a Vec<Vec3>> {
    let t = mesh.target_names.iter().position(|n| n == name)?;
    part.targets.get(t)
}

fn part_target(a: &DefaultAvatar, part: usize, name: &str) -> Vec<Vec3> {
    let p = &a.avatar.parts()[part];
    target(p, &a.avatar.meshes()[p.mesh], name)
        .cloned()
        .unwrap_or_else(|| vec![Vec3::ZERO; p.positions.len()])
}

#[test]
fn default_avatar_has_about_twenty_thousand_vertices() {
    let n = avatar().avatar.vertex_count();
    assert!((18_000..=24_000).contains(&n), "{n} vertices");
}

#[test]
fn default_avatar_triangles_are_valid_and_not_degenerate() {
    for p in avatar().avatar.parts() {
        assert!(!p.triangles.is_empty(), "{}", p.name);
        for t in &p.triangles {
            assert!(
                t.iter().all(|&i| (i as usize) < p.positions.len()),
                "{}",
                p.name
            );
            let [a, b, c] = t.map(|i| p.positions[i as usize]);
            let longest = (b - a).length().max((c - b).length()).max((a - c).length());
            let area = 0.5 * (b - a).cross(c - a).length();
            assert!(area > 1e-3 * longest * longest, "{}: sliver {t:?}", p.name);
        }
    }
}

#[test]
fn default_avatar_closed_parts_face_outwards() {
    let a = avatar();
    let mut closed = vec![a.ears, a.tongue];
    closed.extend(a.eyes.iter().chain(&a.teeth).chain(&a.gums));
    for i in closed {
        let p = &a.avatar.parts()[i];
        // Signed volume by the divergence theorem: Σ a·(b × c) / 6 > 0.
        let volume: f32 = p
            .triangles
            .iter()
            .map(|t| {
                let [x, y, z] = t.map(|i| p.positions[i as usize]);
                x.dot(y.cross(z)) / 6.0
            })
            .sum();
        assert!(volume > 0.0, "{} has volume {volume}", p.name);
    }
}

#[test]
fn default_avatar_face_lies_exactly_on_the_mask() {
    let a = avatar();
    let mask = face_mask();
    let skin = &a.avatar.parts()[a.skin];
    assert!(a.true_correspondence.len() > 5_000);
    for (v, m) in a.true_correspondence.iter().enumerate() {
        let b = m.barycentric;
        assert!(b.iter().all(|&x| x >= 0.0) && (b.iter().sum::<f64>() - 1.0).abs() < 1e-12);
        let expected = face::mask_position(mask, m).as_vec3();
        assert!(skin.positions[v].distance(expected) < 1e-6, "vertex {v}");
    }
    // It is the avatar's own sampling, not the mask's vertices.
    let on_vertex = a
        .true_correspondence
        .iter()
        .filter(|m| m.barycentric.contains(&1.0))
        .count();
    assert!(on_vertex < a.true_correspondence.len() / 10);
}

/// Boundary loops of a triangle set: each boundary edge used once.
fn boundary_loops(triangles: &[[u32; 3]]) -> Vec<Vec<u32>> {
    let mut count: BTreeMap<(u32, u32), usize> = BTreeMap::new();
    for t in triangles {
        for k in 0..3 {
            let (a, b) = (t[k], t[(k + 1) % 3]);
            *count.entry((a.min(b), a.max(b))).or_default() += 1;
        }
    }
    assert!(
        count.values().all(|&c| c <= 2),
        "an edge has more than two triangles"
    );
    let mut next: BTreeMap<u32, u32> = BTreeMap::new();
    for t in triangles {
        for k in 0..3 {
            let (a, b) = (t[k], t[(k + 1) % 3]);
            if count[&(a.min(b), a.max(b))] == 1 {
                assert!(
                    next.insert(a, b).is_none(),
                    "boundary vertex {a} is pinched"
                );
            }
        }
    }
    let mut loops = Vec::new();
    while let Some((&start, _)) = next.iter().next() {
        let mut l = vec![start];
        let mut at = next.remove(&start).expect("present");
        while at != start {
            l.push(at);
            at = next.remove(&at).expect("loops close");
        }
        loops.push(l);
    }
    loops
}

#[test]
fn default_avatar_skin_is_one_surface_with_four_openings() {
    let a = avatar();
    let skin = &a.avatar.parts()[a.skin];
    let unique: BTreeSet<[u32; 3]> = skin
        .triangles
        .iter()
        .map(|t| {
            let mut s = *t;
            s.sort();
            s
        })
        .collect();
    assert_eq!(unique.len(), skin.triangles.len(), "duplicate triangles");
    let loops = boundary_loops(&skin.triangles);
    assert_eq!(
        loops.len(),
        4,
        "eyes, mouth, neck: {:?}",
        loops.iter().map(Vec::len).collect::<Vec<_>>()
    );
    let bottom: BTreeSet<u32> = a.neck_bottom.iter().copied().collect();
    assert!(
        loops
            .iter()
            .any(|l| l.iter().copied().collect::<BTreeSet<_>>() == bottom)
    );
    // The mouth's opening is the face's; the eyes' are the lids' margins'
    // inner edges.
    let nf = a.true_correspondence.len() as u32;
    assert_eq!(
        loops.iter().filter(|l| l.iter().all(|&v| v < nf)).count(),
        1
    );
    let margin = &a.lid_margin_vertices;
    let of_margins = |l: &&Vec<u32>| l.iter().all(|&v| margin.contains(&(v as usize)));
    assert_eq!(loops.iter().filter(of_margins).count(), 2);
    // Connected: a walk over the triangles reaches every vertex.
    let mut parent: Vec<u32> = (0..skin.positions.len() as u32).collect();
    fn find(p: &mut [u32], x: u32) -> u32 {
        let mut r = x;
        while p[r as usize] != r {
            r = p[r as usize];
        }
        p[x as usize] = r;
        r
    }
    for t in &skin.triangles {
        for k in 1..3 {
            let (x, y) = (find(&mut parent, t[0]), find(&mut parent, t[k]));
            parent[x as usize] = y;
        }
    }
    let root = find(&mut parent, 0);
    assert!((0..skin.positions.len() as u32).all(|v| find(&mut parent, v) == root));
}

#[test]
fn default_avatar_has_all_52_arkit_targets() {
    let a = avatar();
    let names: BTreeSet<&str> = a
        .avatar
        .meshes()
        .iter()
        .flat_map(|m| m.target_names.iter().map(String::as_str))
        .collect();
    for s in Blendshape::ALL {
        assert!(names.contains(s.name()), "{} missing", s.name());
    }
    assert_eq!(names.len(), 52);
    let expected: Vec<&str> = Blendshape::ALL.iter().map(|s| s.name()).collect();
    for m in a.avatar.meshes() {
        assert_eq!(m.target_names, expected);
    }
    for p in a.avatar.parts() {
        assert_eq!(
            p.targets.len(),
            a.avatar.meshes()[p.mesh].target_names.len()
        );
        assert!(p.targets.iter().all(|t| t.len() == p.positions.len()));
    }
}

#[test]
fn default_avatar_jaw_open_moves_the_mandible_only() {
    let a = avatar();
    let moved = |part: usize| {
        part_target(a, part, "jawOpen")
            .iter()
            .map(|d| d.length())
            .fold(0.0, f32::max)
    };
    let least = |part: usize| {
        part_target(a, part, "jawOpen")
            .iter()
            .map(|d| d.length())
            .fold(1.0, f32::min)
    };
    assert!(least(a.teeth[1]) > 0.005 && least(a.tongue) > 0.005 && least(a.gums[1]) > 0.005);
    assert_eq!(moved(a.teeth[0]), 0.0);
    assert_eq!(moved(a.gums[0]), 0.0);
    let skin = &a.avatar.parts()[a.skin];
    let d = part_target(a, a.skin, "jawOpen");
    let nf = a.true_correspondence.len();
    let (mut under_chin, mut top) = (0.0f32, 0.0f32);
    for (v, p) in skin.positions.iter().enumerate().skip(nf) {
        if p.y < -0.105 && p.y > -0.13 && p.z > -0.03 {
            under_chin = under_chin.max(d[v].length());
        }
        if p.y > 0.06 {
            top = top.max(d[v].length());
        }
    }
    assert!(under_chin > 0.01, "under the chin moves {under_chin}");
    assert_eq!(top, 0.0);
    // Lower teeth move as the mandible does: where the generic jaw joint
    // takes them.
    let teeth = &a.avatar.parts()[a.teeth[1]];
    let jaw = crate::shape_spec::GENERIC_JAW;
    let angle = crate::shape_spec::JAW_OPEN_ANGLE;
    for (p, d) in teeth
        .positions
        .iter()
        .zip(part_target(a, a.teeth[1], "jawOpen"))
    {
        let expected = jaw.open(p.as_dvec3(), angle).as_vec3();
        assert!((*p + d).distance(expected) < 1e-6);
    }
}

#[test]
fn default_avatar_eye_look_rotates_one_eyeball_rigidly() {
    let a = avatar();
    for (side, name) in [(0, "eyeLookOutLeft"), (1, "eyeLookOutRight")] {
        let eye = &a.avatar.parts()[a.eyes[side]];
        let d = part_target(a, a.eyes[side], name);
        let c = a.eye_centres[side];
        let moved: Vec<Vec3> = eye.positions.iter().zip(&d).map(|(p, d)| *p + *d).collect();
        for i in (0..eye.positions.len()).step_by(37) {
            assert!((moved[i].distance(c) - eye.positions[i].distance(c)).abs() < 1e-6);
            let j = (i * 7 + 11) % eye.positions.len();
            let before = eye.positions[i].distance(eye.positions[j]);
            assert!((moved[i].distance(moved[j]) - before).abs() < 1e-6);
        }
        // The front pole (vertex 0) turns outwards by the documented angle.
        let gaze = (moved[0] - c).normalize();
        let out = if side == 0 { 1.0 } else { -1.0 };
        assert!(gaze.x * out > 0.0);
        let angle = gaze.angle_between(Vec3::Z) as f64;
        assert!((angle - eyes::LOOK_HORIZONTAL).abs() < 1e-4, "{angle}");
        // Only this eyeball.
        let other = part_target(a, a.eyes[1 - side], name);
        assert!(other.iter().all(|d| *d == Vec3::ZERO));
        assert!(
            part_target(a, a.skin, name)
                .iter()
                .all(|d| d.length() < 0.003)
        );
    }
}

#[test]
fn default_avatar_blink_closes_over_the_eyeball_without_entering_it() {
    let a = avatar();
    let mask = face_mask();
    let skin = &a.avatar.parts()[a.skin];
    for (side, name) in [(0, "eyeBlinkLeft"), (1, "eyeBlinkRight")] {
        let d = part_target(a, a.skin, name);
        let c = a.eye_centres[side].as_dvec3();
        for w in [0.0, 0.2, 0.4, 0.6, 0.8, 1.0] {
            for (p, dv) in skin.positions.iter().zip(&d) {
                let q = (*p + w * *dv).as_dvec3();
                let dist = eyes::eye_distance(q, c, DMat3::IDENTITY);
                assert!(
                    dist > 0.0,
                    "{name} at {w}: skin {q:?} inside the eye by {dist}"
                );
            }
        }
        // The lids meet: every upper-lid vertex of the mask lands on its
        // lower-lid partner, and so do the avatar's lid vertices there.
        let lm = &mask.landmarks;
        for (&u, &l) in lm.upper_lid[side].iter().zip(&lm.lower_lid[side]) {
            let find = |m: u32| {
                a.true_correspondence
                    .iter()
                    .position(|p| {
                        let t = mask.topology.triangles()[p.triangle as usize];
                        (0..3).any(|k| t[k] == m && p.barycentric[k] == 1.0)
                    })
                    .expect("lid vertices are on the avatar's lid")
            };
            let (vu, vl) = (find(u), find(l));
            let gap = (skin.positions[vu] + d[vu]).distance(skin.positions[vl] + d[vl]);
            assert!(gap < 1e-6, "lids {gap} apart");
        }
    }
}

#[test]
fn default_avatar_sockets_lie_behind_the_skin_around_the_eyeballs() {
    let a = avatar();
    let skin = &a.avatar.parts()[a.skin];
    let sockets = &a.avatar.parts()[a.sockets];
    for c in a.eye_centres {
        let c = c.as_dvec3();
        // The eyeball, turned any way, stays inside the lining.
        let reach = eyes::cornea_offset() + eyes::cornea_radius();
        assert!(reach < eyes::SOCKET_RADIUS);
        // No skin vertex lies behind the lining's opening inside its sphere.
        for p in &skin.positions {
            let d = p.as_dvec3() - c;
            let theta = d.angle_between(DVec3::Z);
            if theta >= eyes::SOCKET_OPENING {
                assert!(d.length() > eyes::SOCKET_RADIUS, "skin {p:?} in the socket");
            }
        }
        assert!(
            sockets
                .positions
                .iter()
                .any(|p| p.as_dvec3().distance(c) < 0.0146)
        );
    }
}

#[test]
fn default_avatar_mouth_lining_stays_behind_the_skin_and_around_the_mouth() {
    let a = avatar();
    let skin = &a.avatar.parts()[a.skin];
    let lining = &a.avatar.parts()[a.mouth_cavity];
    // Every lining vertex lies behind the skin: the skin vertex nearest to
    // it in (x, y) is in front of it.
    for q in &lining.positions {
        let nearest = skin
            .positions
            .iter()
            .filter(|p| p.z > 0.0)
            .min_by(|p, r| {
                let dp = (p.x - q.x).hypot(p.y - q.y);
                let dr = (r.x - q.x).hypot(r.y - q.y);
                dp.total_cmp(&dr)
            })
            .expect("a face");
        if (nearest.x - q.x).hypot(nearest.y - q.y) < 0.002 {
            assert!(
                nearest.z > q.z + 0.002,
                "lining {q:?} at the skin {nearest:?}"
            );
        }
    }
    // Teeth and tongue lie within its ellipsoid (the molars' gums may
    // touch it).
    let inside = |p: Vec3| {
        let q = (p.as_dvec3() - mouth::CAVITY_CENTRE) / mouth::CAVITY_RADII;
        q.length() < 1.0
    };
    for part in [a.teeth[0], a.teeth[1], a.tongue] {
        let p = &a.avatar.parts()[part];
        let share =
            p.positions.iter().filter(|x| inside(**x)).count() as f64 / p.positions.len() as f64;
        assert!(share > 0.9, "{}: {share}", p.name);
    }
}

#[test]
fn default_avatar_eyeballs_sit_behind_the_open_lids() {
    let a = avatar();
    let skin = &a.avatar.parts()[a.skin];
    for side in 0..2 {
        let c = a.eye_centres[side].as_dvec3();
        let nearest = skin
            .positions
            .iter()
            .map(|p| eyes::eye_distance(p.as_dvec3(), c, DMat3::IDENTITY))
            .fold(f64::INFINITY, f64::min);
        assert!(
            (LID_CLEARANCE * 0.99..0.002).contains(&nearest),
            "{nearest}"
        );
    }
}

#[test]
fn default_avatar_no_shape_moves_the_back_of_the_head() {
    let a = avatar();
    for (i, p) in a.avatar.parts().iter().enumerate() {
        let names = &a.avatar.meshes()[p.mesh].target_names;
        for (t, name) in p.targets.iter().zip(names) {
            for (x, d) in p.positions.iter().zip(t) {
                if x.z < -0.09 || (i == a.skin && x.y > 0.09) {
                    assert_eq!(*d, Vec3::ZERO, "{name} moves {} at {x:?}", p.name);
                }
            }
        }
    }
}

#[test]
fn default_avatar_tongue_out_leaves_the_mouth_and_cheek_puff_inflates() {
    let a = avatar();
    let tongue = &a.avatar.parts()[a.tongue];
    let d = part_target(a, a.tongue, "tongueOut");
    let tip = tongue
        .positions
        .iter()
        .zip(&d)
        .map(|(p, d)| (*p + *d).z)
        .fold(f32::MIN, f32::max);
    let lips = face_mask().neutral[face_mask().landmarks.lower_lip[5] as usize].z;
    assert!(tip > lips, "tongue tip {tip}, lips {lips}");
    let skin = &a.avatar.parts()[a.skin];
    let puff = part_target(a, a.skin, "cheekPuff");
    let outward = skin
        .positions
        .iter()
        .zip(&puff)
        .filter(|(p, _)| p.x.abs() > 0.04 && p.y < -0.02 && p.y > -0.06)
        .map(|(p, d)| d.x * p.x.signum())
        .fold(0.0, f32::max);
    assert!(outward > 0.004, "cheeks move out {outward}");
}

#[test]
fn default_avatar_head_has_no_folds() {
    let a = avatar();
    let skin = &a.avatar.parts()[a.skin];
    let nf = a.true_correspondence.len() as u32;
    let normal = |t: &[u32; 3]| {
        let [p, q, r] = t.map(|i| skin.positions[i as usize]);
        (q - p).cross(r - p).normalize()
    };
    let mut edge: BTreeMap<(u32, u32), Vec<usize>> = BTreeMap::new();
    for (k, t) in skin.triangles.iter().enumerate() {
        for j in 0..3 {
            let (x, y) = (t[j], t[(j + 1) % 3]);
            edge.entry((x.min(y), x.max(y))).or_default().push(k);
        }
    }
    // The lids' margins turn into the socket by design (tested below).
    let margin = |k: usize| a.lid_margin_triangles.contains(&k);
    for (e, ts) in &edge {
        if ts.len() == 2 && (e.0 >= nf || e.1 >= nf) && !ts.iter().any(|&k| margin(k)) {
            let c = normal(&skin.triangles[ts[0]]).dot(normal(&skin.triangles[ts[1]]));
            assert!(c > 0.0, "fold at {:?}", skin.positions[e.0 as usize]);
        }
    }
}

#[test]
fn default_avatar_glb_reads_back_with_all_52_targets_and_its_materials() {
    use likeness::avatar::glb::{check_avatar, read_avatar_bytes};
    let bytes = default_avatar_glb().unwrap();
    assert_eq!(&bytes[..4], b"glTF");
    let glb = read_avatar_bytes(&bytes, "default avatar").unwrap();
    assert_eq!(check_avatar(&glb).unwrap().found(), 52);
    assert_eq!(glb.avatar.vertex_count(), avatar().avatar.vertex_count());
    let materials: Vec<&str> = glb.json()["materials"]
        .as_array()
        .unwrap()
        .iter()
        .map(|m| m["name"].as_str().unwrap())
        .collect();
    assert_eq!(
        materials,
        [
            "skin", "lips", "socket", "mouth", "sclera", "iris", "pupil", "teeth", "gums", "tongue"
        ]
    );
    // The lips are a primitive of their own sharing the skin's vertices:
    // read back, one part again, with the skin's triangles.
    let built = &avatar().avatar;
    assert_eq!(glb.avatar.parts().len(), built.parts().len());
    let skin = avatar().skin;
    assert_eq!(
        glb.avatar.parts()[skin].triangles,
        built.parts()[skin].triangles
    );
    assert_eq!(glb.splits[skin].len(), 1);
    assert_eq!(
        default_avatar_glb().unwrap(),
        bytes,
        "the same bytes every time"
    );
}

#[test]
fn default_avatar_jaw_open_opens_a_rounded_mouth_that_mouth_close_closes_as_before() {
    let a = avatar();
    let skin = &a.avatar.parts()[a.skin];
    let nf = a.true_correspondence.len() as u32;
    let (open, close) = (
        part_target(a, a.skin, "jawOpen"),
        part_target(a, a.skin, "mouthClose"),
    );
    // The mouth: of the face's three openings, the lowest.
    let mouth = boundary_loops(&skin.triangles)
        .into_iter()
        .filter(|l| l.iter().all(|&v| v < nf))
        .min_by(|x, y| {
            let y_of = |l: &[u32]| skin.positions[l[0] as usize].y;
            y_of(x).total_cmp(&y_of(y))
        })
        .expect("a mouth opening");
    let p = |v: u32| skin.positions[v as usize];
    let half_width = mouth.iter().map(|&v| p(v).x.abs()).fold(0.0, f32::max);
    let lip_line = crate::face_mask::MOUTH_CENTRE[1] as f32;
    // The opening's height under jawOpen at `s` of the half-width: the
    // lower lip's drop less the upper lip's, at the nearest loop vertices.
    let height = |s: f32| {
        let drop = |lower: bool| {
            mouth
                .iter()
                .filter(|&&v| (p(v).y < lip_line) == lower)
                .min_by(|&&u, &&v| {
                    let d = |w: u32| (p(w).x - s * half_width).abs();
                    d(u).total_cmp(&d(v))
                })
                .map(|&v| -open[v as usize].y)
                .expect("both lips")
        };
        drop(true) - drop(false)
    };
    let centre = height(0.0);
    assert!(centre > 0.015, "jawOpen opens the mouth {centre} m");
    // An ellipse through corners moving a third of the way (0.91, 0.63 of
    // the centre's drop); the template's rectangle keeps 0.96 and 0.87.
    let (half, near_corner) = (height(0.5) / centre, height(0.9) / centre);
    eprintln!(
        "jawOpen's opening: {centre} m at the centre, {half} of it at half the width, {near_corner} at 0.9"
    );
    assert!(half > 0.8, "pinched: {half} at half the width");
    assert!(
        near_corner < 0.72,
        "square: {near_corner} at 0.9 of the width"
    );
    // jawOpen + mouthClose is the template's, lips closed as before.
    let template = crate::template::generic_template();
    let mask_tris = face_mask().topology.triangles();
    let t = shapes::face_targets(&a.true_correspondence, &template, mask_tris);
    let (jo, mc) = (Blendshape::JawOpen.index(), Blendshape::MouthClose.index());
    let mut changed = 0.0f64;
    for v in 0..nf as usize {
        let sum = (open[v] + close[v]).as_dvec3();
        assert!(sum.distance(t[jo][v] + t[mc][v]) < 1e-6, "vertex {v}");
        changed = changed.max(open[v].as_dvec3().distance(t[jo][v]));
    }
    assert!(changed > 0.004, "jawOpen is the template's: {changed}");
}

#[test]
fn the_lids_margins_hide_the_sockets_and_stay_clear_of_the_eyes() {
    use likeness::geometry::front_visibility::visible_from;
    let a = avatar();
    // The skin, the eyeballs and the sockets as one mesh, seen from the
    // front: how much of the sockets shows through the eyes' openings,
    // with the margins and without.
    let mut positions = Vec::new();
    let mut triangles = Vec::new();
    let mut sockets = Vec::new();
    let mut margins = Vec::new();
    for part in [a.skin, a.eyes[0], a.eyes[1], a.sockets] {
        let p = &a.avatar.parts()[part];
        let o = positions.len() as u32;
        for (k, t) in p.triangles.iter().enumerate() {
            if part == a.sockets {
                sockets.push(triangles.len());
            }
            if part == a.skin && a.lid_margin_triangles.contains(&k) {
                margins.push(triangles.len());
            }
            triangles.push(t.map(|i| i + o));
        }
        positions.extend(p.positions.iter().map(|x| x.as_dvec3()));
    }
    let shown = |triangles: &[[u32; 3]], sockets: &[usize]| {
        let seen = visible_from(&positions, triangles, DVec3::Z, 0.0002);
        sockets.iter().filter(|&&k| seen[k]).count()
    };
    let with = shown(&triangles, &sockets);
    let mut without: Vec<[u32; 3]> = triangles.clone();
    for &k in margins.iter().rev() {
        without.remove(k);
    }
    let shift = |k: usize| k - margins.iter().filter(|&&m| m < k).count();
    let sockets_without: Vec<usize> = sockets.iter().map(|&k| shift(k)).collect();
    let before = shown(&without, &sockets_without);
    println!("socket triangles seen from the front: {before} without the margins, {with} with");
    assert!(
        before > 50,
        "{before}: the openings show the sockets without the margins"
    );
    assert_eq!(with, 0, "the margins hide the sockets");
    // The margins' vertices stay clear of the eyeballs at rest, at every
    // blink weight and at every gaze.
    let skin = &a.avatar.parts()[a.skin];
    for side in 0..2 {
        let c = a.eye_centres[side].as_dvec3();
        let blink = part_target(a, a.skin, ["eyeBlinkLeft", "eyeBlinkRight"][side]);
        for v in a.lid_margin_vertices.clone() {
            for w in [0.0, 0.25, 0.5, 0.75, 1.0] {
                let q = (skin.positions[v] + w * blink[v]).as_dvec3();
                for s in eye_shapes(side) {
                    let d = eyes::eye_distance(q, c, shape_rotation(side, s));
                    assert!(
                        d > 0.0,
                        "margin vertex {v} in eye {side} at blink {w}, {s:?}: {d}"
                    );
                }
            }
        }
    }
}
