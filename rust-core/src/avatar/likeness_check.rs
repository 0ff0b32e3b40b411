//! §4.2, Fig. 7 and 8: does the animated avatar look like the person?
//!
//! Each test expression is animated on the avatar three ways from its
//! tracked weights `w` ([`Animation`]): manual retargeting (the avatar's own
//! shape `j` driven by weight `j`, what Unity Live Capture and Live Link
//! do), automatic retargeting (`Σ w_j A_j`, Eq. 4) and the personalized
//! avatar (`Σ w_j` of the implanted shapes). Each is compared on the
//! avatar's face region with the person's own expression carried onto the
//! avatar: its displacement from the neutral face on the mask, turned and
//! scaled by the registration's similarity and mapped by `M`. The person's
//! expression is the simulator's noise-free face where the session has it,
//! else the recorded test mesh against the neutral scan.
//!
//! Errors are in millimetres at the mask's scale (the avatar's units
//! divided by the similarity's scale), per face vertex and as RMSE and
//! maximum over the face region or a part of it ([`face_vertices_near`]:
//! the mouth corners, the lip contour).

use super::model::Avatar;
use super::registration::FaceRegistration;
use super::retargeting::Retargeting;
use super::target_names::arkit_targets;
use crate::arkit::{Blendshape, Weights};
use crate::personalize::evaluation::MeshError;
use crate::session::Session;
use glam::{DVec3, Vec3};

/// How the avatar is animated from ARKit's 52 weights.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Animation {
    /// The avatar's own target named after ARKit shape `j`, driven by
    /// weight `j`.
    Manual,
    /// Eq. (4): `A_j`, the avatar's own targets combined to approximate the
    /// person's shape `j`.
    Automatic,
    /// The person's shapes implanted (§3.3).
    Personalized,
}

impl Animation {
    /// The three, in the paper's order (worst expected first).
    pub const ALL: [Animation; 3] = [
        Animation::Manual,
        Animation::Automatic,
        Animation::Personalized,
    ];

    /// Its name in reports.
    pub const fn name(self) -> &'static str {
        match self {
            Animation::Manual => "manual",
            Animation::Automatic => "automatic",
            Animation::Personalized => "personalized",
        }
    }
}

/// The avatar's 52 shapes under each [`Animation`]: for each ARKit shape
/// (Apple's order), the displacement of every avatar vertex (as
/// [`Avatar::positions`]).
#[derive(Clone, Debug)]
pub struct AnimationShapes {
    /// [`Animation::Manual`]: the avatar's targets named after ARKit's.
    pub manual: Vec<Vec<Vec3>>,
    /// [`Animation::Automatic`]: `A_j`.
    pub automatic: Vec<Vec<Vec3>>,
    /// [`Animation::Personalized`]: the implanted shapes.
    pub personalized: Vec<Vec<Vec3>>,
}

impl AnimationShapes {
    /// The three sets for `avatar`: its own targets for ARKit's shapes
    /// (`target_names::arkit_targets`, halves summed), `A_j` of
    /// `retargeting`, and `implanted` (the implanted shapes, as
    /// [`super::partial_transfer::Implanted::shapes`]).
    pub fn new(
        avatar: &Avatar,
        retargeting: &Retargeting,
        implanted: Vec<Vec<Vec3>>,
    ) -> AnimationShapes {
        let own = arkit_targets(avatar);
        AnimationShapes {
            manual: Blendshape::ALL
                .iter()
                .map(|&b| own.displacement(avatar, b))
                .collect(),
            automatic: retargeting.displacements(avatar),
            personalized: implanted,
        }
    }

    /// The shapes of `animation`.
    pub fn get(&self, animation: Animation) -> &[Vec<Vec3>] {
        match animation {
            Animation::Manual => &self.manual,
            Animation::Automatic => &self.automatic,
            Animation::Personalized => &self.personalized,
        }
    }
}

/// `Σ_j w_j D_j`: the displacement of every avatar vertex under `weights`
/// (summed in double precision), `shapes` one displacement field per ARKit
/// shape (Apple's order).
pub fn animate(shapes: &[Vec<Vec3>], weights: &Weights) -> Vec<DVec3> {
    let n = shapes.first().map_or(0, Vec::len);
    let mut out = vec![DVec3::ZERO; n];
    for (b, field) in Blendshape::ALL.iter().zip(shapes) {
        let w = f64::from(weights.get(*b));
        if w == 0.0 {
            continue;
        }
        for (o, d) in out.iter_mut().zip(field) {
            *o += d.as_dvec3() * w;
        }
    }
    out
}

/// The person's expression on the avatar's face: `delta` (one displacement
/// per mask vertex, metres) turned and scaled by the registration's
/// similarity and mapped by `M`, one displacement per face vertex (in the
/// order of [`super::registration::CorrespondenceMap::face`]).
pub fn reference_on_face(registration: &FaceRegistration, delta: &[DVec3]) -> Vec<DVec3> {
    let turned: Vec<DVec3> = delta
        .iter()
        .map(|d| registration.similarity.apply_vector(*d))
        .collect();
    registration.map.apply(&turned)
}

/// Each face vertex's error (mm at the mask's scale) of the avatar's
/// displacement `animated` (every avatar vertex, as [`animate`] gives it)
/// against `reference` (per face vertex, as [`reference_on_face`] gives
/// it).
pub fn face_errors_mm(
    registration: &FaceRegistration,
    animated: &[DVec3],
    reference: &[DVec3],
) -> Vec<f64> {
    let per_mm = registration.similarity.scale / 1000.0;
    registration
        .map
        .face
        .iter()
        .zip(reference)
        .map(|(f, r)| {
            let got = animated.get(f.vertex as usize).copied().unwrap_or_default();
            (got - *r).length() / per_mm
        })
        .collect()
}

/// RMSE and maximum of `errors_mm` over `subset` (indices into it), or
/// over all of it when `subset` is `None`; zero for an empty set.
pub fn summarize(errors_mm: &[f64], subset: Option<&[usize]>) -> MeshError {
    let (mut sum, mut max, mut n) = (0.0, 0.0f64, 0usize);
    let mut add = |e: f64| {
        sum += e * e;
        max = max.max(e);
        n += 1;
    };
    match subset {
        Some(indices) => indices
            .iter()
            .filter_map(|&i| errors_mm.get(i))
            .for_each(|e| add(*e)),
        None => errors_mm.iter().for_each(|e| add(*e)),
    }
    MeshError {
        rmse_mm: (sum / n.max(1) as f64).sqrt(),
        max_mm: max,
    }
}

/// The face vertices (indices into the map's face list) whose point on the
/// mask lies within `within` metres of one of `points`; `mask` gives the
/// mask's positions (e.g. the template's neutral) in which `points` are
/// given.
pub fn face_vertices_near(
    registration: &FaceRegistration,
    mask: &[DVec3],
    points: &[DVec3],
    within: f64,
) -> Vec<usize> {
    registration
        .map
        .apply(mask)
        .iter()
        .enumerate()
        .filter(|(_, p)| points.iter().any(|c| (**p - *c).length() < within))
        .map(|(i, _)| i)
        .collect()
}

/// One test expression on the avatar.
#[derive(Clone, Debug)]
pub struct AvatarTestError {
    /// The test expression's id.
    pub id: String,
    /// Each face vertex's error (mm), per [`Animation`] in the order of
    /// [`Animation::ALL`].
    pub errors_mm: [Vec<f64>; 3],
    /// RMSE and maximum over the face region, in the same order.
    pub face: [MeshError; 3],
}

/// Each animation's face RMSE and maximum averaged over `tests`, in the
/// order of [`Animation::ALL`] (zero when there are none).
pub fn mean_face_errors(tests: &[AvatarTestError]) -> [MeshError; 3] {
    let n = tests.len().max(1) as f64;
    [0, 1, 2].map(|m| MeshError {
        rmse_mm: tests.iter().map(|t| t.face[m].rmse_mm).sum::<f64>() / n,
        max_mm: tests.iter().map(|t| t.face[m].max_mm).sum::<f64>() / n,
    })
}

/// The person's displacement from the neutral face at test expression `k`:
/// the simulator's noise-free face where known, else the recorded mesh
/// against the neutral scan.
pub fn test_delta(session: &Session, k: usize) -> Vec<DVec3> {
    let truth = session.truth.as_ref().and_then(|t| {
        t.tests
            .get(k)
            .map(|mesh| (mesh.as_slice(), t.neutral.as_slice()))
    });
    let (mesh, neutral) = truth.unwrap_or_else(|| {
        (
            session
                .tests
                .get(k)
                .map_or(&[][..], |t| t.vertices.as_slice()),
            session.neutral.as_slice(),
        )
    });
    mesh.iter()
        .zip(neutral)
        .map(|(p, n)| (*p - *n).as_dvec3())
        .collect()
}

/// Every test expression of `session` animated three ways on the avatar
/// found by `registration` and compared on its face region (module docs).
pub fn likeness_on_avatar(
    session: &Session,
    registration: &FaceRegistration,
    shapes: &AnimationShapes,
) -> Vec<AvatarTestError> {
    session
        .tests
        .iter()
        .enumerate()
        .map(|(k, test)| {
            let reference = reference_on_face(registration, &test_delta(session, k));
            let errors_mm = Animation::ALL.map(|a| {
                face_errors_mm(
                    registration,
                    &animate(shapes.get(a), &test.weights),
                    &reference,
                )
            });
            let face = [0, 1, 2].map(|m| summarize(&errors_mm[m], None));
            AvatarTestError {
                id: test.id.clone(),
                errors_mm,
                face,
            }
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::avatar::Avatar;
    use crate::avatar::registration::{
        CorrespondenceMap, FaceVertex, FoundFace, PartRole, Similarity,
    };
    use glam::DMat3;

    /// A registration of two avatar vertices onto a one-triangle mask,
    /// the avatar twice the mask's size.
    fn two_vertex_registration() -> FaceRegistration {
        let avatar = Avatar::one_triangle("face");
        let found = FoundFace {
            similarity: Similarity {
                scale: 2.0,
                rotation: DMat3::IDENTITY,
                translation: DVec3::ZERO,
            },
            mask_on_avatar: vec![DVec3::ZERO; 3],
            features_left_out: Vec::new(),
            map: CorrespondenceMap {
                mask_triangles: vec![[0, 1, 2]],
                face: vec![
                    FaceVertex {
                        vertex: 0,
                        triangle: 0,
                        barycentric: [1.0, 0.0, 0.0],
                    },
                    FaceVertex {
                        vertex: 2,
                        triangle: 0,
                        barycentric: [0.0, 0.5, 0.5],
                    },
                ],
            },
            residual_mean_mm: 0.0,
            residual_max_mm: 0.0,
            icp_iterations: 0,
            roles: vec![PartRole::Skin],
            eyeballs: Vec::new(),
            coverage: 1.0,
            nonrigid_steps: (0, 0),
            seconds: 0.0,
        };
        FaceRegistration::new(found, &avatar, 3).unwrap()
    }

    #[test]
    fn animation_is_the_weighted_sum() {
        let mut shapes = vec![vec![Vec3::ZERO; 2]; 52];
        shapes[Blendshape::JawOpen.index()] = vec![Vec3::X, Vec3::Y];
        shapes[Blendshape::EyeBlinkLeft.index()] = vec![Vec3::Z, Vec3::Z];
        let mut w = Weights::default();
        w.set(Blendshape::JawOpen, 0.5);
        w.set(Blendshape::EyeBlinkLeft, 0.25);
        let moved = animate(&shapes, &w);
        assert_eq!(
            moved,
            vec![DVec3::new(0.5, 0.0, 0.25), DVec3::new(0.0, 0.5, 0.25)]
        );
    }

    #[test]
    fn errors_are_measured_at_the_masks_scale_on_the_face_only() {
        let registration = two_vertex_registration();
        // 1 mm up at mask vertex 0, 2 mm up at vertices 1 and 2.
        let delta = vec![DVec3::Y * 0.001, DVec3::Y * 0.002, DVec3::Y * 0.002];
        let reference = reference_on_face(&registration, &delta);
        assert!((reference[0] - DVec3::Y * 0.002).length() < 1e-12);
        assert!((reference[1] - DVec3::Y * 0.004).length() < 1e-12);
        // The avatar moves vertex 0 exactly and vertex 2 not at all;
        // vertex 1 is not on the face and is not counted.
        let animated = vec![DVec3::Y * 0.002, DVec3::X, DVec3::ZERO];
        let errors = face_errors_mm(&registration, &animated, &reference);
        assert_eq!(errors.len(), 2);
        assert!(errors[0].abs() < 1e-6 && (errors[1] - 2.0).abs() < 1e-6);
        let all = summarize(&errors, None);
        assert!((all.rmse_mm - 2.0f64.sqrt()).abs() < 1e-6);
        assert!((all.max_mm - 2.0).abs() < 1e-6);
        let first = summarize(&errors, Some(&[0]));
        assert!(first.rmse_mm.abs() < 1e-6 && first.max_mm.abs() < 1e-6);
    }

    #[test]
    fn means_over_tests_per_animation() {
        let test = |rmse: f64, max: f64| AvatarTestError {
            id: String::new(),
            errors_mm: [Vec::new(), Vec::new(), Vec::new()],
            face: [MeshError {
                rmse_mm: rmse,
                max_mm: max,
            }; 3],
        };
        let means = mean_face_errors(&[test(1.0, 2.0), test(3.0, 6.0)]);
        assert_eq!(
            means[1],
            MeshError {
                rmse_mm: 2.0,
                max_mm: 4.0
            }
        );
        assert_eq!(mean_face_errors(&[])[0].rmse_mm, 0.0);
    }

    #[test]
    fn vertices_near_a_point_are_found_on_the_mask() {
        let registration = two_vertex_registration();
        let mask = vec![DVec3::ZERO, DVec3::X, DVec3::Y];
        // Face vertex 0 sits at mask vertex 0, face vertex 1 at (0.5, 0.5).
        let near = face_vertices_near(&registration, &mask, &[DVec3::ZERO], 0.1);
        assert_eq!(near, vec![0]);
        let both = face_vertices_near(&registration, &mask, &[DVec3::new(0.3, 0.3, 0.0)], 0.5);
        assert_eq!(both, vec![0, 1]);
    }
}
