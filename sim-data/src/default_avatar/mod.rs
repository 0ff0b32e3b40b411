//! The project's own default avatar, built procedurally: a head with neck
//! and the top of the shoulders, ears, two eyeballs, teeth with gums and a
//! tongue, about 20,000 vertices, with its own generic ARKit blendshapes.
//!
//! Its face region is the simulator's mask resampled at a finer, different
//! triangulation, so the true correspondence between avatar and mask is
//! known exactly ([`DefaultAvatar::true_correspondence`]); registration
//! tests use it as ground truth.
//!
//! | what | where | how |
//! |---|---|---|
//! | face skin | [`face`] | mask's parameter plane resampled (1.7 mm hex grid), each vertex at a barycentric point of a mask triangle |
//! | nostrils | [`nostrils`] | two dark ovals painted on the nose's underside, a tint per skin vertex |
//! | shading | [`shading`] | the mask's vertex normals interpolated on the face (Phong), the head's own, blended across the outline |
//! | lips | [`lips`] | the red of the lips in the mask's parameter plane, a material of its own ending on edges along the vermilion border |
//! | materials | [`looks`], [`part_looks`], [`MATERIALS`], [`PART_MATERIALS`] | a plain PBR material per kind of part: skin, lips, sockets, mouth lining, sclera, iris, pupil, teeth, gums, tongue |
//! | skin and its shapes at any spacing | [`skin`] | face region and head joined at the outline, the template continued past it (the low-poly test avatar resamples it coarser) |
//! | head, neck, shoulders | [`head`] | star-shaped implicit surface about `head::CENTRE`, joined to the face's outline |
//! | the head's vertices and triangles | [`meridians`] | rings 5.5 mm apart in arc length down every meridian, triangulated in a nearly conformal plane |
//! | ears | [`ears`] | pressed ellipsoid shells, roots sunk into the head |
//! | lids' thickness | [`lid_margin`] | a band from each eye hole's rim back to the eyeball, clear of it at every gaze and blink weight; the eyes 0.8 mm further back to make room |
//! | eyeballs, sockets | [`eyes`] | 24 mm globe with an 11.5 mm cornea bulging 2.5 mm, placed as far forward as the lids allow; an iris and a pupil painted on the cornea (their own parts); a 29 mm bowl behind each |
//! | teeth, gums, tongue, mouth lining | [`mouth`] | 14 rounded-box crowns per jaw on a parabolic arch, tube gums, flattened ellipsoid tongue, an ellipsoid lining open towards the lips |
//! | rounded mouth opening | [`mouth_opening`] | jawOpen's weight taken towards the corners' share (0.34, measured on ICT-FaceKit) along an ellipse, mouthClose taking it back |
//! | closed surfaces pole to pole (ears, crowns, tongue, eyeballs) | [`uv_sphere`] | rings of vertices at given polar angles, fans at the poles |
//! | blendshapes | [`shapes`] | template interpolated on the face, continued past the outline; jaw, gaze and tongue motions |
//!
//! Coordinates are ARKit's face-anchor space in metres: +x the person's
//! left, +y up, +z out of the face. Every constant and its source is also
//! listed in `sim-data/README.md` (section "The default avatar").

pub mod ears;
pub mod eyes;
pub mod face;
pub mod head;
pub mod lid_margin;
pub mod lips;
#[cfg(test)]
mod look_tests;
pub mod meridians;
pub mod mouth;
pub mod mouth_opening;
pub mod nostrils;
pub mod shading;
pub mod shapes;
pub mod skin;
#[cfg(test)]
mod tests;
pub mod uv_sphere;

use crate::face_mask::EYE_CENTRE;
use crate::template::generic_template;
use face::{FaceRegion, MaskPoint};
use glam::{DMat3, DVec3, Vec3};
use likeness::avatar::model::{Avatar, AvatarMesh, AvatarPart};
use likeness::{Blendshape, Blendshapes};
use std::sync::OnceLock;

/// How far the eyeballs stay from every lid and socket vertex, at rest, at
/// every blink weight and at every gaze (m).
pub const LID_CLEARANCE: f64 = 0.0004;

/// The default avatar and what is known about it by construction.
#[derive(Clone, Debug)]
pub struct DefaultAvatar {
    /// The avatar: meshes `head` (parts `skin`, `ears`, `sockets`,
    /// `mouthCavity`), `eyeLeft`,
    /// `eyeRight`, `teeth` (`teethUpper`, `teethLower`), `gums`
    /// (`gumsUpper`, `gumsLower`), `tongue`. Every mesh carries all 52 ARKit
    /// targets in Apple's order (as Ready Player Me's avatars do), zero
    /// where a shape does not move it, so `targets[shape.index()]` is
    /// always that shape.
    pub avatar: Avatar,
    /// For skin vertex `v < true_correspondence.len()`, the point of the
    /// mask it lies on (mask triangle and barycentric coordinates). The
    /// face vertices are the skin's first ones.
    pub true_correspondence: Vec<MaskPoint>,
    /// Skin vertices of the face's outline, in order.
    pub face_outline: Vec<u32>,
    /// Skin vertices of the cut through neck and shoulders, in order.
    pub neck_bottom: Vec<u32>,
    /// Index in `avatar.parts()` of the skin.
    pub skin: usize,
    /// Index of the ears part.
    pub ears: usize,
    /// Indices of the eyeball parts (the globe and cornea, white),
    /// `[left, right]`.
    pub eyes: [usize; 2],
    /// Indices of the parts painted on each eye's cornea, `[left, right]`,
    /// each `[iris, pupil]`; they turn with their eyeball.
    pub irises: [[usize; 2]; 2],
    /// Index of the eye sockets' lining (in the head mesh, both sides).
    pub sockets: usize,
    /// Index of the mouth's lining (in the head mesh).
    pub mouth_cavity: usize,
    /// Indices of the teeth parts, `[upper, lower]`.
    pub teeth: [usize; 2],
    /// Indices of the gum parts, `[upper, lower]`.
    pub gums: [usize; 2],
    /// Index of the tongue part.
    pub tongue: usize,
    /// Centres of the eyeballs `[left, right]` (m).
    pub eye_centres: [Vec3; 2],
    /// The skin's vertices of the lids' margins ([`lid_margin`]), after the
    /// face's and the head's.
    pub lid_margin_vertices: std::ops::Range<usize>,
    /// The skin's triangles of the lids' margins, just before the lips'.
    pub lid_margin_triangles: std::ops::Range<usize>,
    /// Index of the skin's first triangle on the red of the lips: the
    /// skin's triangles from it on wear the lips' material ([`lips`]).
    pub lips_from: usize,
    /// Share of the nostrils' colour at each skin vertex
    /// ([`nostrils::nostril_share`]).
    pub nostril_share: Vec<f32>,
    /// The skin's shading normals, one per skin vertex
    /// ([`shading::skin_normals`]: the mask's normals interpolated on the
    /// face, the head's own, blended at the outline).
    pub skin_normals: Vec<Vec3>,
    /// Radius of the eyeballs' globe (m); the cornea reaches
    /// `eyes::cornea_offset() + eyes::cornea_radius()` from the centre.
    pub eye_radius: f32,
}

/// The default avatar, built once per process (deterministic).
pub fn default_avatar() -> &'static DefaultAvatar {
    static AVATAR: OnceLock<DefaultAvatar> = OnceLock::new();
    AVATAR.get_or_init(build_default_avatar)
}

impl DefaultAvatar {
    /// The avatar's own rig as the mask sees it: the generic template,
    /// its jawOpen rounded and its mouthClose taking that back at the
    /// mask's vertices ([`mouth_opening::on_mask`]), the rounding the
    /// avatar's face interpolates. Implanting or retargeting this rig
    /// gives back the avatar's own shapes.
    pub fn own_rig_on_mask(&self) -> Blendshapes {
        let template = generic_template()
            .blendshapes()
            .expect("the generic template is checked");
        let rounding = mouth_opening::on_mask();
        let mut deltas = template.deltas().to_vec();
        for (v, r) in rounding.iter().enumerate() {
            deltas[Blendshape::JawOpen.index()][v] += *r;
            deltas[Blendshape::MouthClose.index()][v] -= *r;
        }
        Blendshapes::new(template.neutral().to_vec(), deltas)
            .expect("the rounded template is checked")
    }

    /// Every part of the two eyes (eyeballs, irises, pupils), increasing.
    pub fn eye_parts(&self) -> Vec<usize> {
        let mut parts: Vec<usize> = self.eyes.to_vec();
        parts.extend(self.irises.iter().flatten());
        parts.sort_unstable();
        parts
    }

    /// The side (0 left, 1 right) of the eye a part belongs to, if any.
    pub fn eye_side(&self, part: usize) -> Option<usize> {
        (0..2).find(|&s| self.eyes[s] == part || self.irises[s].contains(&part))
    }
}

/// The shapes that move a part, in ARKit's order.
fn shapes_where(keep: impl Fn(Blendshape) -> bool) -> Vec<Blendshape> {
    Blendshape::ALL.into_iter().filter(|s| keep(*s)).collect()
}

/// One displacement field per ARKit shape, in Apple's order: `moves(s)`
/// or zero.
fn every_shape(n: usize, moves: impl Fn(Blendshape) -> Option<Vec<DVec3>>) -> Vec<Vec<DVec3>> {
    Blendshape::ALL
        .iter()
        .map(|&s| moves(s).unwrap_or_else(|| vec![DVec3::ZERO; n]))
        .collect()
}

fn eye_shapes(side: usize) -> Vec<Blendshape> {
    let suffix = if side == 0 { "Left" } else { "Right" };
    shapes_where(|s| s.name().starts_with("eyeLook") && s.name().ends_with(suffix))
}

/// Gaze rotation of `side` under `shape` at weight one (identity if the
/// shape is not one of that eye's gaze shapes).
pub fn shape_rotation(side: usize, shape: Blendshape) -> DMat3 {
    let name = shape.name();
    if !eye_shapes(side).contains(&shape) {
        return DMat3::IDENTITY;
    }
    let look = ["Out", "In", "Up", "Down"].map(|d| f64::from(u8::from(name.contains(d))));
    eyes::gaze_rotation(side, look)
}

/// The most forward eye depth keeping [`LID_CLEARANCE`] and room for the
/// lids' margins ([`lid_margin::MIN_DEPTH`]) from the skin near
/// the eye (face vertices within 22 mm) at rest, at blink weights ¼…1, at
/// full gaze in each direction, and with eyeWide and eyeSquint.
fn eye_depth(side: usize, face: &FaceRegion, targets: &[Vec<DVec3>]) -> f64 {
    let c = [
        if side == 0 { 1.0 } else { -1.0 } * EYE_CENTRE[0],
        EYE_CENTRE[1],
    ];
    let near: Vec<usize> = (0..face.uv.len())
        .filter(|&v| (face.uv[v][0] - c[0]).hypot(face.uv[v][1] - c[1]) < 0.022)
        .collect();
    let sided = |base: &str| {
        let name = format!("{base}{}", if side == 0 { "Left" } else { "Right" });
        Blendshape::ALL.into_iter().find(|s| s.name() == name)
    };
    let mut configs: Vec<(Option<Blendshape>, f64, DMat3)> = vec![(None, 0.0, DMat3::IDENTITY)];
    for w in [0.25, 0.5, 0.75, 1.0] {
        configs.push((sided("eyeBlink"), w, DMat3::IDENTITY));
    }
    for s in eye_shapes(side) {
        configs.push((Some(s), 1.0, shape_rotation(side, s)));
    }
    configs.push((sided("eyeWide"), 1.0, DMat3::IDENTITY));
    configs.push((sided("eyeSquint"), 1.0, DMat3::IDENTITY));
    let clear = |z: f64| {
        let centre = DVec3::new(c[0], c[1], z);
        configs.iter().all(|(shape, w, rot)| {
            near.iter().all(|&v| {
                let d = shape.map_or(DVec3::ZERO, |s| *w * targets[s.index()][v]);
                let clear = LID_CLEARANCE + lid_margin::MIN_DEPTH;
                eyes::eye_distance(face.positions[v] + d, centre, *rot) >= clear
            })
        })
    };
    let (mut lo, mut hi) = (-0.04, 0.03);
    for _ in 0..40 {
        let mid = 0.5 * (lo + hi);
        if clear(mid) {
            lo = mid;
        } else {
            hi = mid;
        }
    }
    lo
}

/// Every gaze the eye on `side` turns to, full and half weights of each
/// direction and their combinations.
fn gazes(side: usize) -> Vec<DMat3> {
    let steps: [f64; 5] = [-1.0, -0.5, 0.0, 0.5, 1.0];
    let mut out = Vec::new();
    for h in steps {
        for v in steps {
            let look = [h.max(0.0), (-h).max(0.0), v.max(0.0), (-v).max(0.0)];
            out.push(eyes::gaze_rotation(side, look));
        }
    }
    out
}

/// The skin with the lids' margins ([`lid_margin`]) inside both eye holes:
/// their vertices after the skin's, their triangles before the lips'.
fn with_lid_margins(
    mut skin: skin::Skin,
    eye_centres: &[Vec3; 2],
) -> (skin::Skin, std::ops::Range<usize>, std::ops::Range<usize>) {
    let first_vertex = skin.positions.len();
    let mut added = Vec::new();
    for (side, centre) in eye_centres.iter().enumerate() {
        let margin = lid_margin::margin(
            &skin.face.eye_rims[side],
            &skin.positions,
            &skin.targets,
            &skin.triangles,
            (centre.as_dvec3(), &gazes(side)),
            skin.positions.len() as u32,
        );
        skin.positions.extend(&margin.positions);
        for (all, more) in skin.targets.iter_mut().zip(&margin.targets) {
            all.extend(more);
        }
        added.extend(margin.triangles);
    }
    let lips = skin.triangles.split_off(skin.lips_from);
    skin.triangles.extend(added);
    let triangles = skin.lips_from..skin.triangles.len();
    skin.lips_from = skin.triangles.len();
    skin.triangles.extend(lips);
    let vertices = first_vertex..skin.positions.len();
    (skin, vertices, triangles)
}

fn to_f32(v: &[DVec3]) -> Vec<Vec3> {
    v.iter().map(|p| p.as_vec3()).collect()
}

fn part(
    name: &str,
    mesh: usize,
    primitive: usize,
    geometry: &mouth::Mesh,
    targets: Vec<Vec<DVec3>>,
) -> AvatarPart {
    AvatarPart {
        name: name.to_string(),
        mesh,
        primitive,
        positions: to_f32(&geometry.0),
        triangles: geometry.1.clone(),
        targets: targets.iter().map(|t| to_f32(t)).collect(),
    }
}

fn mesh(name: &str, shapes: &[Blendshape]) -> AvatarMesh {
    AvatarMesh {
        name: Some(name.to_string()),
        target_names: shapes.iter().map(|s| s.name().to_string()).collect(),
    }
}

fn build_default_avatar() -> DefaultAvatar {
    let skin = skin::skin(face::FACE_SPACING, head::HEAD_SPACING);
    let (face, face_t) = (&skin.face, &skin.face_targets);
    // Eyes.
    let all = Blendshape::ALL.to_vec();
    let eye_centres: [Vec3; 2] = [0, 1].map(|side| {
        let x = if side == 0 { 1.0 } else { -1.0 } * EYE_CENTRE[0];
        DVec3::new(x, EYE_CENTRE[1], eye_depth(side, face, face_t)).as_vec3()
    });
    let (skin, lid_margin_vertices, lid_margin_triangles) = with_lid_margins(skin, &eye_centres);
    let face = &skin.face;
    let skin_mesh = (skin.positions.clone(), skin.triangles.clone());
    // A share per skin vertex from the face's parameter plane, 0 on the head.
    let paint = |share: fn([f64; 2]) -> f64| -> Vec<f32> {
        let mut out: Vec<f32> = face.uv.iter().map(|uv| share(*uv) as f32).collect();
        out.resize(skin.positions.len(), 0.0);
        out
    };
    let nostril_share = paint(nostrils::nostril_share);
    let mut parts = vec![part("skin", 0, 0, &skin_mesh, skin.targets.clone())];
    let ear_mesh = {
        let mut m: mouth::Mesh = (Vec::new(), Vec::new());
        for side in 0..2 {
            let e = ears::ear(side);
            let o = m.0.len() as u32;
            m.0.extend(e.0);
            m.1.extend(e.1.into_iter().map(|t| t.map(|i| i + o)));
        }
        m
    };
    let ear_targets = vec![vec![DVec3::ZERO; ear_mesh.0.len()]; all.len()];
    parts.push(part("ears", 0, 1, &ear_mesh, ear_targets));
    let mut eye_parts = Vec::new();
    for (side, centre) in eye_centres.iter().enumerate() {
        let centre = centre.as_dvec3();
        let own = eye_shapes(side);
        let name = if side == 0 { "eyeLeft" } else { "eyeRight" };
        let [iris, pupil] = eyes::iris_and_pupil(centre);
        let pieces = [
            ("", eyes::eyeball(centre)),
            ("Iris", iris),
            ("Pupil", pupil),
        ];
        for (primitive, (suffix, piece)) in pieces.into_iter().enumerate() {
            let targets = every_shape(piece.0.len(), |s| {
                own.contains(&s)
                    .then(|| shapes::rotate_about(&piece.0, centre, shape_rotation(side, s)))
            });
            let part_name = format!("{name}{suffix}");
            eye_parts.push(part(&part_name, 1 + side, primitive, &piece, targets));
        }
    }
    let sockets = {
        let mut m: mouth::Mesh = (Vec::new(), Vec::new());
        for c in eye_centres {
            let e = eyes::socket(c.as_dvec3());
            let o = m.0.len() as u32;
            m.0.extend(e.0);
            m.1.extend(e.1.into_iter().map(|t| t.map(|i| i + o)));
        }
        m
    };
    let socket_targets = every_shape(sockets.0.len(), |_| None);
    parts.push(part("sockets", 0, 2, &sockets, socket_targets));
    let cavity = mouth::cavity();
    let cavity_targets: Vec<Vec<DVec3>> = shapes::jaw_part_targets(&cavity.0, &all)
        .into_iter()
        .map(|t| {
            t.iter()
                .zip(&cavity.0)
                .map(|(d, p)| mouth::cavity_jaw_weight(*p) * *d)
                .collect()
        })
        .collect();
    parts.push(part("mouthCavity", 0, 3, &cavity, cavity_targets));
    parts.extend(eye_parts);
    // Mouth: the upper row stays with the skull, the lower follows the jaw.
    let rows = [
        ("teethUpper", 3, 0, mouth::teeth(true)),
        ("teethLower", 3, 1, mouth::teeth(false)),
        ("gumsUpper", 4, 0, mouth::gums(true)),
        ("gumsLower", 4, 1, mouth::gums(false)),
    ];
    for (name, mesh, primitive, g) in rows {
        let t = if primitive == 0 {
            every_shape(g.0.len(), |_| None)
        } else {
            shapes::jaw_part_targets(&g.0, &all)
        };
        parts.push(part(name, mesh, primitive, &g, t));
    }
    let tg = mouth::tongue();
    let (back, tip) = (
        mouth::TONGUE_CENTRE.z - mouth::TONGUE_RADII.z,
        mouth::TONGUE_CENTRE.z + mouth::TONGUE_RADII.z,
    );
    let mut tongue_t = shapes::jaw_part_targets(&tg.0, &all);
    tongue_t[Blendshape::TongueOut.index()] =
        shapes::tongue_out(&tg.0, mouth::TONGUE_CENTRE, back, tip);
    parts.push(part("tongue", 5, 0, &tg, tongue_t));
    let meshes = ["head", "eyeLeft", "eyeRight", "teeth", "gums", "tongue"]
        .map(|name| mesh(name, &all))
        .to_vec();
    DefaultAvatar {
        avatar: Avatar::new(meshes, parts).expect("the default avatar's parts make an avatar"),
        true_correspondence: face.on_mask.clone(),
        face_outline: face.rim.clone(),
        neck_bottom: skin.neck_bottom.clone(),
        skin: 0,
        ears: 1,
        sockets: 2,
        mouth_cavity: 3,
        eyes: [4, 7],
        irises: [[5, 6], [8, 9]],
        teeth: [10, 11],
        gums: [12, 13],
        tongue: 14,
        eye_centres,
        lid_margin_vertices,
        lid_margin_triangles,
        lips_from: skin.lips_from,
        nostril_share,
        skin_normals: shading::skin_normals(
            &skin.positions,
            &skin.triangles,
            &face.on_mask,
            &face.rim,
        ),
        eye_radius: eyes::EYE_RADIUS as f32,
    }
}

/// The default avatar's materials, one per mesh in `avatar.meshes()` order:
/// skin for the head, white for the eyeballs, tooth for the teeth, gum pink
/// for the gums and the tongue. [`part_looks`] refines them.
pub fn looks(avatar: &Avatar) -> Vec<likeness::avatar::glb::MeshLook> {
    use likeness::avatar::glb::MeshLook;
    avatar
        .meshes()
        .iter()
        .map(|m| match m.name.as_deref() {
            Some(n) if n.starts_with("eye") => MeshLook::EYE_WHITE,
            Some("teeth") => MeshLook::TOOTH,
            Some("gums") | Some("tongue") => MeshLook::GUM,
            _ => MeshLook::SKIN,
        })
        .collect()
}

/// The default avatar's plain materials (no textures): name, linear RGB
/// base colour and roughness. Colours are from photographs of each tissue
/// under daylight turned linear, rounded; roughness from how glossy each
/// looks (the wet cornea and tongue glossy, skin matte).
pub const MATERIALS: [(&str, [f32; 3], f32); 10] = [
    ("skin", [0.80, 0.57, 0.46], 0.6),
    ("lips", [0.56, 0.24, 0.24], 0.45),
    ("socket", [0.45, 0.20, 0.20], 0.5),
    ("mouth", [0.35, 0.09, 0.10], 0.5),
    ("sclera", [0.90, 0.88, 0.85], 0.15),
    ("iris", [0.18, 0.10, 0.05], 0.1),
    ("pupil", [0.01, 0.01, 0.01], 0.05),
    ("teeth", [0.90, 0.88, 0.80], 0.3),
    ("gums", [0.75, 0.30, 0.33], 0.4),
    ("tongue", [0.70, 0.25, 0.27], 0.35),
];

/// Which of [`MATERIALS`] each of the default avatar's parts wears, by
/// part name.
pub const PART_MATERIALS: [(&str, &str); 15] = [
    ("skin", "skin"),
    ("ears", "skin"),
    ("sockets", "socket"),
    ("mouthCavity", "mouth"),
    ("eyeLeft", "sclera"),
    ("eyeRight", "sclera"),
    ("eyeLeftIris", "iris"),
    ("eyeRightIris", "iris"),
    ("eyeLeftPupil", "pupil"),
    ("eyeRightPupil", "pupil"),
    ("teethUpper", "teeth"),
    ("teethLower", "teeth"),
    ("gumsUpper", "gums"),
    ("gumsLower", "gums"),
    ("tongue", "tongue"),
];

/// The material of [`MATERIALS`] named `name`: its base colour and look.
fn material(name: &str) -> Option<([f32; 3], likeness::avatar::glb::MeshLook)> {
    use likeness::avatar::glb::MeshLook;
    let (_, [r, g, b], roughness) = MATERIALS.iter().find(|m| m.0 == name)?;
    Some(([*r, *g, *b], MeshLook::plain([*r, *g, *b, 1.0], *roughness)))
}

/// Each part's own material ([`PART_MATERIALS`]), in `avatar.parts()` order.
pub fn part_looks(avatar: &Avatar) -> Vec<Option<(String, likeness::avatar::glb::MeshLook)>> {
    avatar
        .parts()
        .iter()
        .map(|p| {
            let (_, name) = PART_MATERIALS.iter().find(|m| m.0 == p.name)?;
            Some((name.to_string(), material(name)?.1))
        })
        .collect()
}

/// Colour of the nostrils (linear RGB), a tint over the skin's: the
/// shadowed inside of the nose, dark and a little red.
pub const NOSTRIL_COLOUR: [f32; 3] = [0.10, 0.04, 0.04];

/// How the default avatar is written as a GLB: [`looks`], [`part_looks`],
/// the lips' triangles in the lips' material (sharing the skin's vertices,
/// from [`DefaultAvatar::lips_from`] on), the nostrils' colour as a tint of
/// the skin's vertices ([`NOSTRIL_COLOUR`] over the skin's, by
/// [`DefaultAvatar::nostril_share`]), the skin's shading normals
/// ([`DefaultAvatar::skin_normals`]), dense targets.
pub fn glb_options(built: &DefaultAvatar) -> likeness::avatar::glb::NewGlbOptions {
    let avatar = &built.avatar;
    let part_looks = part_looks(avatar);
    let skin_colour = material("skin").map_or([1.0; 3], |m| m.0);
    let nostril = Vec3::from(NOSTRIL_COLOUR) / Vec3::from(skin_colour);
    let mut part_colours = vec![None; avatar.parts().len()];
    part_colours[built.skin] = Some(
        (built.nostril_share.iter())
            .map(|&n| Vec3::ONE.lerp(nostril, n))
            .collect(),
    );
    let mut part_splits = vec![Vec::new(); avatar.parts().len()];
    if let Some((_, look)) = material("lips") {
        part_splits[built.skin] = vec![likeness::avatar::glb::MaterialSplit {
            first_triangle: built.lips_from,
            name: "lips".into(),
            look,
        }];
    }
    let mut part_normals = vec![None; avatar.parts().len()];
    part_normals[built.skin] = Some(built.skin_normals.clone());
    likeness::avatar::glb::NewGlbOptions {
        looks: looks(avatar),
        part_looks,
        part_colours,
        part_normals,
        part_splits,
        ..Default::default()
    }
}

/// The default avatar as the bytes of a GLB file, with its materials
/// ([`looks`]): what `likeness default-avatar` writes and what the app
/// personalizes when the person brings no avatar of their own.
pub fn default_avatar_glb() -> Result<Vec<u8>, likeness::avatar::glb::GlbError> {
    let built = default_avatar();
    likeness::avatar::glb::new_avatar_glb(
        &built.avatar,
        &glb_options(built),
        std::path::Path::new("default-avatar.glb"),
    )
}
