//! ARKit's own face mesh as a simulation basis: people simulated on the
//! topology and the template a real iPhone sends.
//!
//! The simulator's own mask ([`crate::face_mask`]) has ARKit's counts but
//! not its shape or its holes. ARKit's generic face (52 OBJs, what
//! `ARFaceGeometry(blendShapes:)` returns) lives at `../shared/arkit-face/`
//! and is never committed, so this module reads it at run time and carries
//! the simulator's models onto it:
//!
//! 1. **Correspondence.** The simulator's mask, with its generic template,
//!    is registered onto ARKit's neutral face by the product's own
//!    registration ([`likeness::avatar::registration::find_face()`], ARKit's
//!    face read as a one-part avatar with its 51 shapes as targets). Every
//!    ARKit vertex takes the parameter-plane position `(u, v)` of its
//!    closest point on the registered mask; a vertex beyond the mask's
//!    outline (ARKit's face wraps further round the cheeks) adds its offset
//!    from that closest point, taken in the surface's tangent plane. Every
//!    expression field of the simulator is a function of `(u, v)`
//!    ([`crate::regions`]), so the same fields act on ARKit's vertices.
//! 2. **Landmarks** from ARKit's own boundary loops: the outline, the two
//!    eye openings (corners at their extremes in x, the lid rows between),
//!    the mouth's slit (corners and the two lip rows). The rims' `(u, v)`
//!    are held on their own side of the eye and mouth lines, so a lid or a
//!    lip never takes the other's motion. Near the mouth, ARKit's own
//!    `jawOpen` says which lip each vertex is on, and holds the lips' curl
//!    behind the slit on its own side too.
//! 3. **The template** is ARKit's own 52 shapes (`tongueOut`, which does
//!    not move the mesh and has no file, is the neutral).
//!
//! How a person is made on it is [`crate::face_basis`].

use crate::face_mask::{EYE_CENTRE, FaceMask, Landmarks, MOUTH_CENTRE, face_mask, lip_row_offset};
use crate::face_model::{FaceModel, SparseField};
use crate::shape_spec::{GENERIC_JAW, JawJoint, generic_specs};
use crate::template::generic_template;
use glam::{DMat3, DVec3, Vec3};
use likeness::avatar::registration::lips_parting::{STILL, WITH_JAW};
use likeness::avatar::registration::{FaceRegistration, find_face};
use likeness::avatar::{Avatar, AvatarMesh, AvatarPart};
use likeness::geometry::closest_point::TriangleTree;
use likeness::geometry::mesh_boundary::boundary_loops;
use likeness::io::obj_reader::{ObjLimits, read_obj};
use likeness::{Blendshape, Template, Topology};
use std::path::{Path, PathBuf};

/// How far a rim vertex's `(u, v)` is held off the eye or mouth line on its
/// own side (m): the regions split the lids and the lips sharply at those
/// lines (0.1 mm), so half a millimetre keeps each row wholly on its side.
pub const RIM_SIDE_MARGIN: f64 = 0.0005;

/// ARKit's generic face, ready to simulate people on.
#[derive(Clone, Debug)]
pub struct ArkitFace {
    /// ARKit's topology, the `(u, v)` carried from the simulator's mask,
    /// ARKit's neutral and the landmarks found on its loops.
    pub mask: FaceMask,
    /// ARKit's own template (neutral and 52 shapes at weight one).
    pub template: Template,
    /// The simulator's mask registered onto ARKit's face.
    pub registration: FaceRegistration,
    /// The generic jaw joint placed on ARKit's face by the registration's
    /// similarity.
    pub jaw: JawJoint,
    /// What ARKit's template does beyond the simulator's generic field of
    /// each shape on ARKit's vertices, `T_j − G_j` in Apple's order; empty
    /// for [`PHYSICAL_SHAPES`] ([`crate::face_basis`]).
    pub offsets: Vec<SparseField>,
}

/// The shapes that take no offset from ARKit's template, because they are
/// physics rather than an artist's rig ([`crate::face_basis`]).
pub const PHYSICAL_SHAPES: [Blendshape; 4] = [
    Blendshape::EyeBlinkLeft,
    Blendshape::EyeBlinkRight,
    Blendshape::JawOpen,
    Blendshape::MouthClose,
];

/// Why ARKit's face could not be read.
#[derive(Debug, thiserror::Error)]
pub enum ArkitFaceError {
    /// An OBJ file could not be read or parsed.
    #[error("{path}: {message}")]
    Obj {
        /// The file.
        path: PathBuf,
        /// What went wrong.
        message: String,
    },
    /// The files do not make a face of ARKit's kind.
    #[error("{dir}: {message}")]
    NotArkit {
        /// The folder.
        dir: PathBuf,
        /// What does not fit.
        message: String,
    },
}

/// Where ARKit's face is in this workplace: `../shared/arkit-face/` beside
/// the project's root.
pub fn shared_arkit_face_dir() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../../shared/arkit-face")
}

/// ARKit's face from the shared folder, read once per process; `None` where
/// the folder is absent (a fresh clone). Under CI (`CI=true`), which has the
/// folder, its absence or a failure to read it panics.
pub fn shared_arkit_face() -> Option<&'static ArkitFace> {
    static FACE: std::sync::OnceLock<Option<ArkitFace>> = std::sync::OnceLock::new();
    FACE.get_or_init(|| {
        let dir = shared_arkit_face_dir();
        let required = std::env::var("CI").is_ok_and(|v| v == "true");
        if !dir.join("Neutral.obj").exists() {
            assert!(!required, "CI=true but {} is absent", dir.display());
            return None;
        }
        Some(read_arkit_face(&dir).unwrap_or_else(|e| panic!("ARKit's face: {e}")))
    })
    .as_ref()
}

fn read_mesh(path: &Path) -> Result<(Vec<Vec3>, Vec<[u32; 3]>), ArkitFaceError> {
    let mesh = read_obj(
        path,
        ObjLimits {
            max_vertices: 100_000,
        },
    )
    .map_err(|e| ArkitFaceError::Obj {
        path: path.to_path_buf(),
        message: e.to_string(),
    })?;
    Ok((mesh.positions, mesh.triangles))
}

/// Reads ARKit's face from `dir` (`Neutral.obj` and one OBJ per shape named
/// as ARKit names it) and carries the simulator's mask onto it (module
/// docs).
pub fn read_arkit_face(dir: &Path) -> Result<ArkitFace, ArkitFaceError> {
    let not_arkit = |message: String| ArkitFaceError::NotArkit {
        dir: dir.to_path_buf(),
        message,
    };
    let (neutral, triangles) = read_mesh(&dir.join("Neutral.obj"))?;
    let topology = Topology::new(neutral.len(), triangles).map_err(|e| not_arkit(e.to_string()))?;
    let mut shapes = Vec::with_capacity(Blendshape::ALL.len());
    for shape in Blendshape::ALL {
        let path = dir.join(format!("{}.obj", shape.name()));
        if shape == Blendshape::TongueOut && !path.exists() {
            shapes.push(neutral.clone());
            continue;
        }
        let (positions, _) = read_mesh(&path)?;
        if positions.len() != neutral.len() {
            return Err(not_arkit(format!(
                "{} has {} vertices, Neutral.obj {}",
                path.display(),
                positions.len(),
                neutral.len()
            )));
        }
        shapes.push(positions);
    }
    let template = Template::new(neutral.clone(), shapes).map_err(|e| not_arkit(e.to_string()))?;
    let registration = register_simulator_mask(&topology, &template).map_err(not_arkit)?;
    let positions: Vec<DVec3> = neutral.iter().map(|p| p.as_dvec3()).collect();
    let uv = carried_uv(&positions, &registration);
    let (found, _) = landmarks(&topology, &positions, uv.clone()).map_err(not_arkit)?;
    let uv = features_aligned(uv, &found);
    let (landmarks, uv) = landmarks(&topology, &positions, uv).map_err(not_arkit)?;
    let uv = lips_held_by_own_jaw(uv, &template, &positions, &landmarks);
    let mask = FaceMask {
        topology,
        uv,
        neutral,
        landmarks,
    };
    let s = &registration.similarity;
    let jaw = JawJoint {
        hinge: s.apply(GENERIC_JAW.hinge),
        glide: s.apply_vector(GENERIC_JAW.glide),
    };
    let offsets = template_offsets(&mask, &template, jaw);
    Ok(ArkitFace {
        mask,
        template,
        registration,
        jaw,
        offsets,
    })
}

/// `T_j − G_j`: ARKit's template less the simulator's generic field of each
/// shape on ARKit's vertices; empty for [`PHYSICAL_SHAPES`].
fn template_offsets(mask: &FaceMask, template: &Template, jaw: JawJoint) -> Vec<SparseField> {
    let neutral: Vec<DVec3> = mask.neutral.iter().map(|p| p.as_dvec3()).collect();
    let generic = FaceModel::build(mask, neutral, &generic_specs(), DMat3::IDENTITY, jaw);
    Blendshape::ALL
        .iter()
        .map(|b| {
            if PHYSICAL_SHAPES.contains(b) {
                return SparseField::default();
            }
            let ours = generic.shape(*b);
            let dense: Vec<DVec3> = template.shapes[b.index()]
                .iter()
                .zip(&ours)
                .map(|(t, g)| t.as_dvec3() - *g)
                .collect();
            SparseField::from_dense(&dense)
        })
        .collect()
}

/// The simulator's mask, with its generic template, registered onto ARKit's
/// face read as a one-part avatar.
fn register_simulator_mask(
    topology: &Topology,
    template: &Template,
) -> Result<FaceRegistration, String> {
    let names: Vec<String> = Blendshape::ALL
        .iter()
        .map(|b| b.name().to_string())
        .collect();
    let part = AvatarPart {
        name: "ARKit".to_string(),
        mesh: 0,
        primitive: 0,
        positions: template.neutral.clone(),
        triangles: topology.triangles().to_vec(),
        targets: Blendshape::ALL.iter().map(|b| template.delta(*b)).collect(),
    };
    let mesh = AvatarMesh {
        name: Some("ARKit".to_string()),
        target_names: names,
    };
    let avatar = Avatar::new(vec![mesh], vec![part]).map_err(|e| e.to_string())?;
    let ours = face_mask();
    let rig = generic_template()
        .blendshapes()
        .map_err(|e| e.to_string())?;
    find_face(&avatar, &ours.topology, &rig).map_err(|e| e.to_string())
}

/// Each ARKit vertex's parameter-plane position: its closest point's on the
/// registered mask, plus its tangential offset from there (module docs).
fn carried_uv(positions: &[DVec3], registration: &FaceRegistration) -> Vec<[f64; 2]> {
    let ours = face_mask();
    let grid = TriangleTree::new(&registration.mask_on_avatar, ours.topology.triangles());
    positions
        .iter()
        .map(|p| {
            let c = grid.closest(*p).expect("the registered mask has triangles");
            let t = grid.triangles()[c.triangle];
            let mut uv = [0.0; 2];
            for (k, &v) in t.iter().enumerate() {
                uv[0] += c.barycentric[k] * ours.uv[v as usize][0];
                uv[1] += c.barycentric[k] * ours.uv[v as usize][1];
            }
            let n = grid.triangle_normal(c.triangle);
            let off = *p - c.point;
            let tangential = (off - n * n.dot(off)) / registration.similarity.scale;
            [uv[0] + tangential.x, uv[1] + tangential.y]
        })
        .collect()
}

/// How far the correction that puts ARKit's eye and mouth corners onto the
/// simulator's reaches in the parameter plane (m, a Gaussian's σ): about
/// the distance from an eye's corner to the next feature, so the brows,
/// cheeks and chin between the features move with them and the outline
/// hardly at all.
pub const FEATURE_REACH: f64 = 0.02;

/// `uv` corrected so that ARKit's eye corners and mouth corners land on
/// the simulator's (the registration matches the faces' surfaces, not
/// their holes: ARKit's eyes are wider and further out, its mouth wider):
/// a Gaussian radial-basis displacement through those six pairs, so the
/// simulator's regions (a lid, a lip, the jaw) fall on ARKit's features.
fn features_aligned(uv: Vec<[f64; 2]>, lm: &Landmarks) -> Vec<[f64; 2]> {
    use crate::face_mask::{EYE_HALF_WIDTH, MOUTH_HALF_WIDTH};
    let [ex, ey] = EYE_CENTRE;
    let [mx, my] = MOUTH_CENTRE;
    let pairs: Vec<([f64; 2], [f64; 2])> = vec![
        (uv[lm.eye_inner[0] as usize], [ex - EYE_HALF_WIDTH, ey]),
        (uv[lm.eye_outer[0] as usize], [ex + EYE_HALF_WIDTH, ey]),
        (uv[lm.eye_inner[1] as usize], [-(ex - EYE_HALF_WIDTH), ey]),
        (uv[lm.eye_outer[1] as usize], [-(ex + EYE_HALF_WIDTH), ey]),
        (uv[lm.lip_corners[0] as usize], [mx + MOUTH_HALF_WIDTH, my]),
        (uv[lm.lip_corners[1] as usize], [mx - MOUTH_HALF_WIDTH, my]),
    ];
    let phi = |a: [f64; 2], b: [f64; 2]| {
        (-((a[0] - b[0]).powi(2) + (a[1] - b[1]).powi(2)) / (FEATURE_REACH * FEATURE_REACH)).exp()
    };
    let n = pairs.len();
    let a = faer::Mat::<f64>::from_fn(n, n, |i, j| phi(pairs[i].0, pairs[j].0));
    let rhs = faer::Mat::<f64>::from_fn(n, 2, |i, k| pairs[i].1[k] - pairs[i].0[k]);
    let weights = faer::linalg::solvers::Solve::solve(&a.partial_piv_lu(), &rhs);
    uv.into_iter()
        .map(|p| {
            let mut q = p;
            for (i, (s, _)) in pairs.iter().enumerate() {
                let w = phi(p, *s);
                q[0] += w * weights[(i, 0)];
                q[1] += w * weights[(i, 1)];
            }
            q
        })
        .collect()
}

/// `uv` with every vertex near the mouth held on the side of the mouth line
/// that ARKit's own `jawOpen` puts it on (step 2 of the module docs, beyond
/// the rims). ARKit's lips curl inwards: a ring behind the slit, the upper
/// lip's lining lies over the lower lip's, and its closest point on the
/// registered mask can be on the lower lip. Carried as it is, such a vertex
/// moved 23 mm with the jaw in a simulated `jawOpen` where ARKit's template
/// moves it 2.5 mm. Within the slit's half-width of its middle, a vertex
/// that ARKit's `jawOpen` leaves with the skull (at most [`STILL`] of its
/// largest motion there) is held above the line, one it moves with the jaw
/// (at least [`WITH_JAW`]) below it, as the rims are; the corners and the
/// cheeks between the two shares keep their carried place.
fn lips_held_by_own_jaw(
    mut uv: Vec<[f64; 2]>,
    template: &Template,
    p: &[DVec3],
    lm: &Landmarks,
) -> Vec<[f64; 2]> {
    let [a, b] = lm.lip_corners.map(|v| p[v as usize]);
    let (centre, radius) = ((a + b) / 2.0, a.distance(b) / 2.0);
    let jaw = template.delta(Blendshape::JawOpen);
    let near: Vec<usize> = (0..p.len())
        .filter(|&v| p[v].distance(centre) <= radius)
        .collect();
    let largest = near
        .iter()
        .map(|&v| f64::from(jaw[v].length()))
        .fold(0.0, f64::max);
    if largest <= 0.0 {
        return uv;
    }
    for v in near {
        let share = f64::from(jaw[v].length()) / largest;
        let u = uv[v][0];
        let half_gap = 0.5 * lip_row_offset(u);
        if share <= STILL {
            uv[v][1] = uv[v][1].max(MOUTH_CENTRE[1] + half_gap + RIM_SIDE_MARGIN);
        } else if share >= WITH_JAW {
            uv[v][1] = uv[v][1].min(MOUTH_CENTRE[1] - half_gap - RIM_SIDE_MARGIN);
        }
    }
    uv
}

/// A loop split at its two extremes in x into `(low corner, high corner,
/// upper row, lower row)`, each row from the low-x corner to the high-x
/// one, corners excluded.
fn split_at_corners(lp: &[u32], p: &[DVec3]) -> (u32, u32, Vec<u32>, Vec<u32>) {
    let by_x = |a: &&u32, b: &&u32| p[**a as usize].x.total_cmp(&p[**b as usize].x);
    let lo = lp
        .iter()
        .position(|v| *v == *lp.iter().min_by(by_x).expect("a loop"))
        .unwrap_or(0);
    let hi = lp
        .iter()
        .position(|v| *v == *lp.iter().max_by(by_x).expect("a loop"))
        .unwrap_or(0);
    let n = lp.len();
    let walk = |from: usize, to: usize| -> Vec<u32> {
        let mut out = Vec::new();
        let mut k = (from + 1) % n;
        while k != to {
            out.push(lp[k]);
            k = (k + 1) % n;
        }
        out
    };
    let mut a = walk(lo, hi);
    let mut b = walk(hi, lo);
    b.reverse();
    let mean_y =
        |row: &[u32]| row.iter().map(|v| p[*v as usize].y).sum::<f64>() / row.len().max(1) as f64;
    if mean_y(&a) < mean_y(&b) {
        std::mem::swap(&mut a, &mut b);
    }
    (lp[lo], lp[hi], a, b)
}

/// `row` resampled to `n` vertices by its x order: the blink pairs vertex k
/// of the upper lid with vertex k of the lower, so both rows must have as
/// many (the nearest in x stands in where one row has fewer).
fn paired(upper: &[u32], lower: &[u32], p: &[DVec3]) -> Vec<u32> {
    upper
        .iter()
        .map(|u| {
            *lower
                .iter()
                .min_by(|a, b| {
                    let da = (p[**a as usize].x - p[*u as usize].x).abs();
                    let db = (p[**b as usize].x - p[*u as usize].x).abs();
                    da.total_cmp(&db)
                })
                .expect("a lid row")
        })
        .collect()
}

/// ARKit's landmarks found on its boundary loops, and `uv` with the rims
/// held on their own sides of the eye and mouth lines.
fn landmarks(
    topology: &Topology,
    p: &[DVec3],
    mut uv: Vec<[f64; 2]>,
) -> Result<(Landmarks, Vec<[f64; 2]>), String> {
    let mut loops = boundary_loops(topology).map_err(|e| e.to_string())?;
    if loops.len() != 4 {
        return Err(format!(
            "{} boundary loops, ARKit's face has 4",
            loops.len()
        ));
    }
    let extent = |lp: &Vec<u32>| {
        let xs = lp.iter().map(|v| p[*v as usize].x);
        xs.clone().fold(f64::MIN, f64::max) - xs.fold(f64::MAX, f64::min)
    };
    loops.sort_by(|a, b| extent(b).total_cmp(&extent(a)));
    let outline = loops.remove(0);
    let centre_x =
        |lp: &Vec<u32>| lp.iter().map(|v| p[*v as usize].x).sum::<f64>() / lp.len() as f64;
    loops.sort_by(|a, b| centre_x(a).abs().total_cmp(&centre_x(b).abs()));
    let mouth = loops.remove(0);
    loops.sort_by(|a, b| centre_x(b).total_cmp(&centre_x(a)));
    let (mut eye_inner, mut eye_outer) = ([0; 2], [0; 2]);
    let (mut upper_lid, mut lower_lid): ([Vec<u32>; 2], [Vec<u32>; 2]) = Default::default();
    for (side, lp) in loops.iter().enumerate() {
        let (lo, hi, mut up, mut down) = split_at_corners(lp, p);
        // Inner (nasal) first: the left eye's (+x) inner corner is its low x.
        let (inner, outer) = if side == 0 { (lo, hi) } else { (hi, lo) };
        if side == 1 {
            up.reverse();
            down.reverse();
        }
        let cy = EYE_CENTRE[1];
        for v in &up {
            uv[*v as usize][1] = uv[*v as usize][1].max(cy + RIM_SIDE_MARGIN);
        }
        for v in &down {
            uv[*v as usize][1] = uv[*v as usize][1].min(cy - RIM_SIDE_MARGIN);
        }
        eye_inner[side] = inner;
        eye_outer[side] = outer;
        lower_lid[side] = paired(&up, &down, p);
        upper_lid[side] = up;
    }
    let (lo, hi, upper_lip, mut lower_lip) = split_at_corners(&mouth, p);
    for v in &upper_lip {
        let u = uv[*v as usize][0];
        let line = MOUTH_CENTRE[1] + 0.5 * lip_row_offset(u) + RIM_SIDE_MARGIN;
        uv[*v as usize][1] = uv[*v as usize][1].max(line);
    }
    for v in &lower_lip {
        let u = uv[*v as usize][0];
        let line = MOUTH_CENTRE[1] - 0.5 * lip_row_offset(u) - RIM_SIDE_MARGIN;
        uv[*v as usize][1] = uv[*v as usize][1].min(line);
    }
    // From the right corner (−x) to the left, as the simulator's mask.
    lower_lip = paired(&upper_lip, &lower_lip, p);
    let nose_tip = (0..p.len())
        .max_by(|a, b| p[*a].z.total_cmp(&p[*b].z))
        .expect("vertices") as u32;
    let chin = *outline
        .iter()
        .filter(|v| p[**v as usize].x.abs() < 0.02)
        .min_by(|a, b| p[**a as usize].y.total_cmp(&p[**b as usize].y))
        .ok_or("no outline vertex near the midline")?;
    Ok((
        Landmarks {
            eye_inner,
            eye_outer,
            upper_lid,
            lower_lid,
            lip_corners: [hi, lo],
            upper_lip,
            lower_lip,
            nose_tip,
            chin,
            outline,
        },
        uv,
    ))
}
