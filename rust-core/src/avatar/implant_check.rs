//! The product checks its own output: the person's avatar measured against
//! the avatar's own rig before it is written, shape by shape.
//!
//! Each measure compares a personalized shape with the avatar's own shape
//! of the same name, so a rig's own choices (a lid tucked under a cornea
//! shell, a stretchy lip) never count against the implant:
//!
//! | what | rule | limit |
//! |---|---|---|
//! | torn edges ([`torn_edges`]) | a head edge stretched past [`TORN_STRETCH`]× its rest length where the own shape keeps it under [`OWN_STRETCH`]× | [`TORN_SHARE`] of the head's edges |
//! | folded triangles ([`folded_triangles`]) | a head triangle turned past [`FOLD_ANGLE`] where the own shape turns it under [`OWN_FOLD_ANGLE`] | [`FOLDED_SHARE`] of the head's triangles |
//! | the blink seen from the front ([`eyeball_seen_share`]) | the share of the eyeball's front half a ray from straight ahead reaches | the own blink's share + [`BLINK_SLACK`] |
//! | a lid in an eyeball ([`deepest_lid`]) | the deepest a skin vertex goes inside an eyeball where the own shape keeps it out | [`LID_DEPTH_MM`] |
//! | the inside showing ([`super::showing_through`]) | a vertex from behind the skin (a lining, teeth, tongue) in front of it, seen from straight ahead, where the own shape keeps it behind | [`SHOWING_DEPTH_MM`] |
//! | the retargeting residual | `‖G w̃_j − M B_j‖` of Eq. (4) against the person's motion, floored at [`RESIDUAL_FLOOR_MM`] RMS | [`MAX_RELATIVE_RESIDUAL`] |
//!
//! Each leaves an avatar that still animates, and is written with a
//! warning ([`Fault`]) that names the shape and where. The person's face
//! at rest is checked before the shapes are implanted on it
//! ([`super::rest_check`]).

pub use super::head_skin::{bounding_sphere, eyeball_flags, head_edges, head_triangles};
use super::model::Avatar;
use super::registration::FaceRegistration;
use super::registration::find_face::arkit_displacement;
use super::showing_through::InsideProbe;
use crate::arkit::Blendshape;
use crate::geometry::closest_point::TriangleTree;
use crate::geometry::inside_surface::{facing_outwards, inside, is_open};
use crate::geometry::ray_cover::RayCover;
use crate::personalize::blendshape_fit::in_parallel_map;
use glam::{DVec3, Vec3};
use std::fmt;

/// An edge counts as torn when the shape stretches it more than this many
/// times its rest length …
pub const TORN_STRETCH: f32 = 2.0;

/// … where the avatar's own shape stretches it less than this.
pub const OWN_STRETCH: f32 = 1.5;

/// Most torn edges one shape may leave, as a share of the head's edges.
pub const TORN_SHARE: f64 = 0.005;

/// A triangle counts as folded when the shape turns its normal by more
/// than this (radians, 90°) …
pub const FOLD_ANGLE: f64 = std::f64::consts::FRAC_PI_2;

/// … where the avatar's own shape turns it by less than this (45°).
pub const OWN_FOLD_ANGLE: f64 = std::f64::consts::FRAC_PI_4;

/// Most folded triangles one shape may leave, as a share of the head's
/// triangles.
pub const FOLDED_SHARE: f64 = 0.002;

/// How much more of an eyeball's front a personalized blink may leave seen
/// than the avatar's own blink does (2 points of the share).
pub const BLINK_SLACK: f64 = 0.02;

/// The deepest a lid may go inside an eyeball where the avatar's own shape
/// keeps it out (mm at the mask's scale): the lids of ARKit's template rest
/// 0.4–0.6 mm apart, so 0.2 mm is below anything a capture can tell.
pub const LID_DEPTH_MM: f64 = 0.2;

/// How far in front of the skin (mm at the mask's scale) a vertex from
/// behind it (the mouth's lining, teeth, tongue, a socket's lining) may
/// come where the avatar's own shape keeps it behind
/// ([`super::showing_through`]): as far as a lid may go into an eyeball.
pub const SHOWING_DEPTH_MM: f64 = 0.2;

/// The person's motion on the face rows of Eq. (4) is floored at this RMS
/// (mm at the mask's scale) before the residual is compared with it, so a
/// shape that hardly moves (a tongueOut on a mask that has no tongue)
/// does not make a tiny residual look large.
pub const RESIDUAL_FLOOR_MM: f64 = 1.0;

/// The largest residual of Eq. (4), relative to the person's motion: past
/// it the avatar's own shapes, combined, move the face three times further
/// from the person's shape than standing still would, and the skin next
/// to the face follows a motion that is not the person's. A rig whose
/// mouth works otherwise than ARKit's leaves residuals of 1–2 (ICT-FaceKit
/// on simulated people: mouthClose, mouthLeft and mouthRight up to 1.96),
/// which the face region's own motion covers; a failed retargeting leaves
/// thousands.
pub const MAX_RELATIVE_RESIDUAL: f64 = 3.0;

/// What the check found wrong with one shape of the person's avatar.
#[derive(Clone, Debug, PartialEq)]
pub enum Fault {
    /// The shape tears more head edges than [`TORN_SHARE`] allows.
    Torn {
        /// The shape.
        shape: Blendshape,
        /// Edges torn.
        edges: usize,
        /// The limit.
        limit: usize,
        /// An end of the most stretched torn edge (avatar vertex).
        vertex: u32,
    },
    /// The shape folds more head triangles than [`FOLDED_SHARE`] allows.
    Folded {
        /// The shape.
        shape: Blendshape,
        /// Triangles folded.
        triangles: usize,
        /// The limit.
        limit: usize,
        /// A corner of the most turned folded triangle (avatar vertex).
        vertex: u32,
    },
    /// The blink leaves more of the eyeball seen than the own blink.
    BlinkOpen {
        /// The blink.
        shape: Blendshape,
        /// Share of the eyeball's front seen under the own blink.
        own: f64,
        /// Under the person's.
        personalized: f64,
    },
    /// A lid goes into an eyeball.
    LidInEyeball {
        /// The shape.
        shape: Blendshape,
        /// How deep (mm at the mask's scale).
        depth_mm: f64,
        /// The deepest lid vertex (avatar vertex).
        vertex: u32,
    },
    /// What lies behind the skin comes out in front of it.
    InsideShowing {
        /// The shape.
        shape: Blendshape,
        /// Places (vertices and triangles' centres) in front of the skin by
        /// more than [`SHOWING_DEPTH_MM`].
        points: usize,
        /// The farthest (mm at the mask's scale).
        depth_mm: f64,
        /// That vertex (avatar vertex).
        vertex: u32,
    },
    /// Eq. (4) reproduces nothing of the person's shape.
    Residual {
        /// The shape.
        shape: Blendshape,
        /// The residual relative to the person's motion (floored).
        relative: f64,
    },
}

impl Fault {
    /// The shape the fault is in.
    pub fn shape(&self) -> Blendshape {
        match self {
            Fault::Torn { shape, .. }
            | Fault::Folded { shape, .. }
            | Fault::BlinkOpen { shape, .. }
            | Fault::LidInEyeball { shape, .. }
            | Fault::InsideShowing { shape, .. }
            | Fault::Residual { shape, .. } => *shape,
        }
    }
}

impl fmt::Display for Fault {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Fault::Torn {
                shape,
                edges,
                limit,
                vertex,
            } => write!(
                f,
                "{shape} tears {edges} edges of the head (limit {limit}), the worst at vertex {vertex}"
            ),
            Fault::Folded {
                shape,
                triangles,
                limit,
                vertex,
            } => write!(
                f,
                "{shape} folds {triangles} triangles of the head (limit {limit}), the worst at vertex {vertex}"
            ),
            Fault::BlinkOpen {
                shape,
                own,
                personalized,
            } => write!(
                f,
                "{shape} leaves {:.1}% of the eyeball seen from the front (the avatar's own: {:.1}%)",
                100.0 * personalized,
                100.0 * own
            ),
            Fault::LidInEyeball {
                shape,
                depth_mm,
                vertex,
            } => write!(
                f,
                "{shape} takes a lid {depth_mm:.2} mm into the eyeball (limit {LID_DEPTH_MM} mm) at vertex {vertex}"
            ),
            Fault::InsideShowing {
                shape,
                points,
                depth_mm,
                vertex,
            } => write!(
                f,
                "{shape} brings {points} points from behind the skin (the mouth's or a socket's lining, teeth, tongue) out in front of it, up to {depth_mm:.2} mm (limit {SHOWING_DEPTH_MM} mm), the farthest at vertex {vertex}"
            ),
            Fault::Residual { shape, relative } => write!(
                f,
                "the avatar's own shapes reproduce little of the person's {shape} (residual {:.0}% of its motion): the skin next to the face follows it loosely",
                100.0 * relative
            ),
        }
    }
}

/// The avatar's own displacement for ARKit shape `b` (zero without one).
pub fn own_shape(avatar: &Avatar, b: Blendshape) -> Vec<Vec3> {
    arkit_displacement(avatar, b)
        .map(|d| d.iter().map(|x| x.as_vec3()).collect())
        .unwrap_or_else(|| vec![Vec3::ZERO; avatar.vertex_count()])
}

/// The edges of `edges` torn by `got` where `own` does not tear them
/// (module docs), most stretched first; `rest` the avatar's rest
/// positions, the shapes displacements.
pub fn torn_edges(
    rest: &[Vec3],
    own: &[Vec3],
    got: &[Vec3],
    edges: &[(u32, u32)],
) -> Vec<(u32, u32)> {
    let stretch = |d: &[Vec3], a: usize, b: usize| {
        let at_rest = (rest[a] - rest[b]).length();
        ((rest[a] + d[a]) - (rest[b] + d[b])).length() / at_rest.max(f32::MIN_POSITIVE)
    };
    let mut torn: Vec<(f32, (u32, u32))> = edges
        .iter()
        .map(|&(a, b)| (stretch(got, a as usize, b as usize), (a, b)))
        .filter(|&(s, (a, b))| {
            s > TORN_STRETCH && stretch(own, a as usize, b as usize) < OWN_STRETCH
        })
        .collect();
    torn.sort_by(|x, y| y.0.total_cmp(&x.0));
    torn.into_iter().map(|(_, e)| e).collect()
}

/// The cosine of the angle by which displacement `d` turns triangle `t`'s
/// normal (1 for a degenerate triangle), clamped to [−1, 1]: compared with
/// an angle's cosine, it says whether the turn is past the angle without an
/// arccosine.
fn turn_cosine(rest: &[Vec3], d: &[Vec3], t: [u32; 3]) -> f64 {
    let normal = |p: [Vec3; 3]| (p[1] - p[0]).cross(p[2] - p[0]).as_dvec3();
    let at = t.map(|v| rest[v as usize]);
    let moved = t.map(|v| rest[v as usize] + d[v as usize]);
    let (a, b) = (normal(at), normal(moved));
    if a.length_squared() == 0.0 || b.length_squared() == 0.0 {
        return 1.0;
    }
    (a.dot(b) / (a.length_squared() * b.length_squared()).sqrt()).clamp(-1.0, 1.0)
}

/// The triangles of `triangles` that `got` turns past [`FOLD_ANGLE`] where
/// `own` turns them under [`OWN_FOLD_ANGLE`], most turned first.
pub fn folded_triangles(
    rest: &[Vec3],
    own: &[Vec3],
    got: &[Vec3],
    triangles: &[[u32; 3]],
) -> Vec<[u32; 3]> {
    let (past, under) = (FOLD_ANGLE.cos(), OWN_FOLD_ANGLE.cos());
    let mut folded: Vec<(f64, [u32; 3])> = triangles
        .iter()
        .map(|t| (turn_cosine(rest, got, *t), *t))
        .filter(|(cosine, t)| *cosine < past && turn_cosine(rest, own, *t) > under)
        .map(|(cosine, t)| (cosine.acos(), t))
        .collect();
    folded.sort_by(|x, y| y.0.total_cmp(&x.0));
    folded.into_iter().map(|(_, t)| t).collect()
}

/// The share of eyeball `eye`'s vertices on its front half (towards
/// `forward` from its centre, at rest) that are seen from straight ahead
/// under displacement `d`: no triangle of the avatar's other vertices
/// within three eyeball radii crosses the ray from the vertex along
/// `forward`.
pub fn eyeball_seen_share(
    avatar: &Avatar,
    found: &FaceRegistration,
    eye: &[u32],
    d: &[Vec3],
    forward: DVec3,
) -> f64 {
    let rest: Vec<DVec3> = avatar.positions().iter().map(|p| p.as_dvec3()).collect();
    let posed = |v: usize| rest[v] + d[v].as_dvec3();
    let (centre, radius) = bounding_sphere(&rest, eye);
    let in_eyeball = eyeball_flags(avatar, found);
    let cover = RayCover::new(
        avatar
            .triangles()
            .iter()
            .filter(|t| t.iter().all(|&v| !in_eyeball[v as usize]))
            .map(|t| t.map(|v| posed(v as usize)))
            .filter(|t| t.iter().any(|p| (*p - centre).length() < 3.0 * radius))
            .collect(),
        forward,
    );
    let front: Vec<usize> = eye
        .iter()
        .map(|&v| v as usize)
        .filter(|&v| (rest[v] - centre).dot(forward) > 0.0)
        .collect();
    let seen = front
        .iter()
        .filter(|&&v| {
            let o = posed(v) + forward * 1e-6 * radius;
            !cover.covers(o)
        })
        .count();
    seen as f64 / front.len().max(1) as f64
}

/// An eyeball and the skin near it (within 1.5 of its radii), prepared
/// once for [`EyeProbe::deepest_lid`] over every shape.
pub struct EyeProbe {
    /// The avatar's rest positions.
    rest: Vec<DVec3>,
    /// The eyeball's vertices.
    eye: Vec<u32>,
    /// The eyeball's triangles, over its own vertices (`eye`'s order), at
    /// rest.
    tree: TriangleTree,
    /// Skin vertices near it, in no eyeball.
    near: Vec<usize>,
    /// Whether its triangles leave a boundary ([`is_open`]).
    open: bool,
}

impl EyeProbe {
    /// Prepares eyeball `eye` of `avatar` found as `found`.
    pub fn new(avatar: &Avatar, found: &FaceRegistration, eye: &[u32]) -> EyeProbe {
        let rest: Vec<DVec3> = avatar.positions().iter().map(|p| p.as_dvec3()).collect();
        let mut local = vec![u32::MAX; rest.len()];
        for (k, &v) in eye.iter().enumerate() {
            local[v as usize] = k as u32;
        }
        let triangles: Vec<[u32; 3]> = avatar
            .triangles()
            .iter()
            .map(|t| t.map(|v| local[v as usize]))
            .filter(|t| t.iter().all(|&k| k != u32::MAX))
            .collect();
        let (centre, radius) = bounding_sphere(&rest, eye);
        let in_eyeball = eyeball_flags(avatar, found);
        let near: Vec<usize> = (0..rest.len())
            .filter(|&v| !in_eyeball[v] && (rest[v] - centre).length() < 1.5 * radius)
            .collect();
        let at_rest: Vec<DVec3> = eye.iter().map(|&v| rest[v as usize]).collect();
        // Its inner side read from its normals: wound inside out, turned.
        let triangles = facing_outwards(&at_rest, &triangles);
        EyeProbe {
            open: is_open(&triangles),
            tree: TriangleTree::new(&at_rest, &triangles),
            rest,
            eye: eye.to_vec(),
            near,
        }
    }

    /// How deep each of the near vertices `which` lies inside the eyeball
    /// under displacement `d`: by the eyeball's closest triangle as
    /// displaced by the same shape, facing outwards (0 outside).
    fn depths(&self, d: &[Vec3], which: &[usize]) -> Vec<f64> {
        let posed = |v: usize| self.rest[v] + d[v].as_dvec3();
        let eye_posed: Vec<DVec3> = self.eye.iter().map(|&v| posed(v as usize)).collect();
        let grid = self.tree.moved_to(&eye_posed);
        // Nothing farther from the posed eyeball's centre than its radius
        // is inside it.
        let (centre, radius) =
            bounding_sphere(&eye_posed, &(0..eye_posed.len() as u32).collect::<Vec<_>>());
        which
            .iter()
            .map(|&v| {
                let p = posed(v);
                if (p - centre).length() > radius {
                    return 0.0;
                }
                inside(&grid, p, self.open).map_or(0.0, |(c, _)| (c - p).length())
            })
            .collect()
    }

    /// The deepest (avatar units) a near skin vertex lies inside the
    /// eyeball under `got` where it lies outside under `own`, and that
    /// vertex; `(0, 0)` at once where `got` moves neither the eyeball nor
    /// the skin near it by `still` (avatar units): nothing can then go
    /// deeper into the eyeball than `still` past where it lies at rest,
    /// which is the rig's own. Only the vertices `got` takes inside are
    /// looked up under `own`.
    pub fn deepest_lid(&self, own: &[Vec3], got: &[Vec3], still: f64) -> (f64, u32) {
        let moves = |v: usize| f64::from(got[v].length()) > still;
        if !self.near.iter().any(|&v| moves(v)) && !self.eye.iter().any(|&v| moves(v as usize)) {
            return (0.0, 0);
        }
        let (inside, got_depth): (Vec<usize>, Vec<f64>) = self
            .near
            .iter()
            .zip(self.depths(got, &self.near))
            .filter(|(_, g)| *g > 0.0)
            .map(|(v, g)| (*v, g))
            .unzip();
        if inside.is_empty() {
            return (0.0, 0);
        }
        inside
            .iter()
            .zip(self.depths(own, &inside).iter().zip(&got_depth))
            .filter(|(_, (o, _))| **o == 0.0)
            .map(|(v, (_, g))| (*g, *v as u32))
            .fold((0.0, 0), |a, b| if b.0 > a.0 { b } else { a })
    }
}

/// [`EyeProbe::deepest_lid`] for one eyeball and one shape.
pub fn deepest_lid(
    avatar: &Avatar,
    found: &FaceRegistration,
    eye: &[u32],
    own: &[Vec3],
    got: &[Vec3],
) -> (f64, u32) {
    EyeProbe::new(avatar, found, eye).deepest_lid(own, got, 0.0)
}

/// Whether the eyeball `eye` lies on the person's left (ARKit's +x).
pub fn on_left(rest: &[Vec3], found: &FaceRegistration, eye: &[u32]) -> bool {
    let c = eye
        .iter()
        .map(|&v| rest[v as usize].as_dvec3())
        .sum::<DVec3>()
        / eye.len() as f64;
    (found.similarity.rotation.transpose() * (c - found.similarity.translation)).x > 0.0
}

/// The eyes blink `b` (`eyeBlinkLeft` or `eyeBlinkRight`; nothing for any
/// other shape) leaves more of the eyeball seen from the front under `got`
/// than under the avatar's own blink `own` (both per avatar vertex), by
/// more than [`BLINK_SLACK`].
pub fn open_blinks(
    avatar: &Avatar,
    found: &FaceRegistration,
    b: Blendshape,
    (own, got): (&[Vec3], &[Vec3]),
) -> Vec<Fault> {
    let left = match b {
        Blendshape::EyeBlinkLeft => true,
        Blendshape::EyeBlinkRight => false,
        _ => return Vec::new(),
    };
    let rest = avatar.positions();
    let forward = found.similarity.rotation * DVec3::Z;
    found
        .eyeballs
        .iter()
        .filter(|e| on_left(&rest, found, e) == left)
        .filter_map(|eye| {
            let own_seen = eyeball_seen_share(avatar, found, eye, own, forward);
            let got_seen = eyeball_seen_share(avatar, found, eye, got, forward);
            (got_seen > own_seen + BLINK_SLACK).then_some(Fault::BlinkOpen {
                shape: b,
                own: own_seen,
                personalized: got_seen,
            })
        })
        .collect()
}

/// Checks the person's `shapes` (displacements per avatar vertex, Apple's
/// order) on `avatar` found as `found` against the avatar's own (module
/// docs); `relative_residual` is Eq. (4)'s per shape, already floored.
pub fn check_shapes(
    avatar: &Avatar,
    found: &FaceRegistration,
    shapes: &[Vec<Vec3>],
    relative_residual: &[f64],
) -> Vec<Fault> {
    let rest = avatar.positions();
    let edges = head_edges(avatar, found);
    let triangles = head_triangles(avatar, found);
    let to_mm = 1000.0 / found.similarity.scale;
    // Skin that moves less than a quarter of the lid limit cannot take a
    // lid past it.
    let still = 0.25 * LID_DEPTH_MM / to_mm;
    let torn_limit = (TORN_SHARE * edges.len() as f64) as usize;
    let folded_limit = (FOLDED_SHARE * triangles.len() as f64) as usize;
    let inside = InsideProbe::new(avatar, found);
    let probes: Vec<EyeProbe> = found
        .eyeballs
        .iter()
        .map(|eye| EyeProbe::new(avatar, found, eye))
        .collect();
    let check = |b: Blendshape| -> Vec<Fault> {
        let Some(got) = shapes.get(b.index()) else {
            return Vec::new();
        };
        let own = own_shape(avatar, b);
        let mut faults = Vec::new();
        let torn = torn_edges(&rest, &own, got, &edges);
        if torn.len() > torn_limit {
            faults.push(Fault::Torn {
                shape: b,
                edges: torn.len(),
                limit: torn_limit,
                vertex: torn[0].0,
            });
        }
        let folded = folded_triangles(&rest, &own, got, &triangles);
        if folded.len() > folded_limit {
            faults.push(Fault::Folded {
                shape: b,
                triangles: folded.len(),
                limit: folded_limit,
                vertex: folded[0][0],
            });
        }
        for probe in &probes {
            let (depth, vertex) = probe.deepest_lid(&own, got, still);
            if depth * to_mm > LID_DEPTH_MM {
                faults.push(Fault::LidInEyeball {
                    shape: b,
                    depth_mm: depth * to_mm,
                    vertex,
                });
            }
        }
        let showing = inside.showing(&own, got, SHOWING_DEPTH_MM / to_mm);
        if showing.points > 0 {
            faults.push(Fault::InsideShowing {
                shape: b,
                points: showing.points,
                depth_mm: showing.depth * to_mm,
                vertex: showing.vertex,
            });
        }
        faults.extend(open_blinks(avatar, found, b, (&own, got)));
        if let Some(r) = relative_residual
            .get(b.index())
            .filter(|r| **r > MAX_RELATIVE_RESIDUAL)
        {
            faults.push(Fault::Residual {
                shape: b,
                relative: *r,
            });
        }
        faults
    };
    // The shapes are independent: over the cores, in Apple's order.
    in_parallel_map(Blendshape::ALL.len(), |i| check(Blendshape::ALL[i]))
        .into_iter()
        .flatten()
        .collect()
}
