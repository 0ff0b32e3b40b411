//! Automatic retargeting, Eq. (4) of §3.3: each ARKit shape `B_j`, carried
//! onto the avatar's face by the correspondence map `M`, approximated by a
//! combination of the avatar's own `k` blendshapes `B̃_i`. Beyond the
//! paper, the ridge pulls the weights towards the avatar's own shape of
//! the same name (`e_j`: 1 for the avatar's target named `j`, both halves
//! of a split one, 0 elsewhere), at the amount `s_j` the person shows of it
//! (below), instead of towards zero:
//!
//! ```text
//! E_j(w̃) = ‖Σ_i w̃_i B̃_i − M B_j‖² + Σ_i (μ + U_i) (w̃_i − s_j e_ji)²,
//! w̃_j = argmin E_j over 0 ≤ w̃_i ≤ 1 (module docs: one may pass 1),
//! ```
//!
//! with `G` (3F × k) the displacements of the avatar's `k` blendshapes (its
//! morph targets grouped by name across meshes, [`avatar_blendshapes`]) at
//! the `F` face vertices and `U` the diagonal of the `U_i` (below). All 52
//! shapes share the `k × k` matrix `GᵀG + μI + U`; without the bounds each
//! would solve `(GᵀG + μI + U) w̃_j = Gᵀ M B_j + (μI + U) s_j e_j`.
//! `M B_j` is the mask's displacement carried into the avatar's frame by
//! the registration's similarity (`s R δ`, then `M`).
//!
//! **Like with like.** `M B_j` is a field at the mask's resolution: linear
//! across each mask triangle. `G`'s columns are therefore the avatar's
//! targets seen the same way, `M S(B̃_i)`: fitted at the mask's vertices
//! and carried back by `M` ([`crate::avatar::own_shapes`]). Compared with
//! the targets themselves,
//! a person who moves exactly as the avatar's `jawOpen` would leave a
//! residual of detail finer than the mask (at the lips' rims), and other
//! targets would be mixed in to fit it (on the default avatar the round
//! trip's `mouthRollLower` moved the tongue by 18% of the shape's motion).
//!
//! **Why the prior.** With the paper's `μ Σ w̃_i²`, a target the face does
//! not see (eyeLook rotating an eyeball, tongueOut moving the tongue) gets
//! weight 0 in every `A_j`, so the retargeted avatar's eyes never turn and
//! its tongue never comes out; and a target with a tiny footprint on the
//! face is used at large weights to fit details of `M B_j`, dragging the
//! eyeballs or the tongue along. Pulling towards `e_j` keeps what the face
//! cannot tell as the avatar's artist made it, and lets the face data
//! decide the rest.
//!
//! **What the face cannot see.** A target that moves skin beyond the face
//! region moves it there in every `A_j` that uses it, and nothing checks
//! that motion against the person. So a departure from `e_j` also costs
//! what it moves there, `U_i = Σ_{v unseen} ‖B̃_i[v]‖²` (in the same units
//! as the fit's terms): the ridge on weight `i` is `μ + U_i`. Without it,
//! a person's jawOpen on ICT-FaceKit was fitted with mouthFunnel at −0.8,
//! mouthLowerDown at −0.8 and jawLeft and jawRight at +0.6 each, and the
//! insides of the lips, which the mask does not cover, moved 5–10 mm
//! towards each other. The lids round the eyeballs (skin within
//! [`LIDS_REACH`] eyeball radii of an eyeball's centre) do not count:
//! their contacts and the eyelid repair look after them, and pinning their
//! targets put a lid of the default avatar 0.09 mm into the eyeball when
//! the person squinted looking up.
//!
//! **How much of the own shape.** The prior is the own shape at the amount
//! of it the person's motion shows on the face, `s_j e_j` with `s_j =
//! ⟨G e_j, M B_j⟩ / ‖G e_j‖²` clamped to `[0, 1]` ([`own_amount`]; 1 where
//! the face does not see the own shape): what the face cannot see moves as
//! the artist made it, as far as the face shows the person moving. Pulled
//! towards the own shape at full weight, a person who puffs their cheeks a
//! third as far as ICT-FaceKit's cheekPuff kept that target near weight 1
//! (what it moves beyond the face, `U_i`, held it there), and `A_j` moved
//! the face three to four times further from the person's shape than
//! standing still would (simulated people, seeds 2–5: cheekPuff and
//! mouthRight 302–411%; the skin beyond the face swelled as the artist's
//! puff while the face moved as the person's). A shape whose own target
//! moves the lids (the skin round an eyeball, [`LIDS_REACH`]) or turns an
//! eyeball or the jaw, by at least [`TURNS_SHARE`] of its largest motion,
//! keeps the full weight as its prior: a blink at weight 1 is the eye
//! closed, however far the artist's lids travel to close it (scaled to the
//! mask's lid travel, the MPFB body's blinks left 2–3% of the eyeball seen
//! for three of ten people), the lids' contacts with the eyeball are the
//! artist's (a committed subject's eyeSquintRight with eyeLookUpRight put
//! a lid 0.21 mm into the eyeball), and a gaze or a jaw at weight 1 is the
//! artist's rotation, which the chin on the mask does not measure.
//!
//! **μ.** `μ = μ₀ · tr(GᵀG) / k` with the dimensionless [`RELATIVE_RIDGE`]
//! μ₀: both terms of `E_j` are then in the same units (the avatar's
//! length², summed over its face vertices), so μ₀ means the same on a
//! centimetre and a metre avatar and at any mesh resolution. A departure
//! from `e_j` must explain more than `μ₀` of an average target's energy on
//! the face to be made.
//!
//! **Weights in `[0, 1]`.** As the paper notes (§4), the unconstrained
//! optimum leaves `[0, 1]`, and by far: for people on ARKit's own mesh,
//! `browDownLeft` on the default avatar came out as its own `browDownLeft`
//! at 2.7, `eyeLookUpLeft` at 2.5, `eyeBlinkLeft` at 1.3 and both brow
//! raises at −1.1 to −1.2. A rig is made for weights in `[0, 1]` (Lewis et
//! al. 2014, *Practice and Theory of Blendshape Facial Models*, §5.2, the
//! usual constraint of retargeting): the avatar's own `browDownLeft` at
//! 2.7 alone folds 81 of its triangles, where at 1 it folds none. Here the
//! face itself takes the person's motion from step 1 of the transfer
//! ([`crate::avatar::partial_transfer`]); `A_j` gives the avatar's own detail
//! and moves what the mask does not see, so it is kept to what the rig was
//! made for, and each `w̃_j` is the least of `E_j` over the box
//! ([`crate::geometry::box_quadratic`]). One weight may pass 1: the
//! avatar's own target of shape `j`, where that target turns the jaw (it
//! moves the teeth or the tongue, by at least [`TURNS_SHARE`] of its
//! largest motion). It stands for a rotation a person can
//! take further than the artist posed it (a person who opens wider than
//! the avatar's jawOpen, as the chin on the mask shows), and past 1 it
//! keeps turning the same way; capped at 1, the teeth and the neck stayed
//! behind the person's chin, and a committed subject's jawOpen bent the
//! neck 25.1° where the rig alone bends it 16.5°.
//!
//! `A_j = Σ_i w̃_ji B̃_i` over the whole avatar (eyes, teeth, neck included)
//! is the automatic retargeting; the weights themselves are a product on
//! their own (a map from ARKit's 52 weights to the avatar's targets).

use super::head_skin::eyeball_flags;
use super::model::Avatar;
use super::own_shapes::{MaskOnSkin, face_part_triangles};
use super::registration::FaceRegistration;
use super::target_names::{ArkitTargets, TargetName, arkit_targets};
use crate::arkit::{BLENDSHAPE_COUNT, Blendshape, Blendshapes};
use crate::geometry::box_quadratic::{Bounds, minimize};
use crate::personalize::blendshape_fit::in_parallel_map;
use faer::Mat;
use glam::{DVec3, Vec3};
use serde::{Deserialize, Serialize};

/// μ₀, the ridge weight relative to the mean energy `tr(GᵀG) / k` of the
/// avatar's blendshapes on the face (module docs).
pub const RELATIVE_RIDGE: f64 = 1e-3;

/// Skin within this many eyeball radii of an eyeball's centre is the lids'
/// (module docs): the 24 mm eyeball's radius is 12 mm, and the lids reach
/// 6 mm beyond it.
pub const LIDS_REACH: f64 = 1.5;

/// Displacements shorter than this share of the avatar's bounding-box
/// diagonal are written as zero (a micrometre on a metre-sized avatar).
pub const NEGLIGIBLE: f64 = 1e-6;

/// The length below which a displacement on an avatar is invisible:
/// [`NEGLIGIBLE`] of its bounding box's diagonal. Written as zero, such
/// displacements keep a sparse target sparse.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct NegligibleLength(f64);

impl NegligibleLength {
    /// The length for an avatar whose vertices are at `positions` (zero
    /// when their box is not finite: nothing is then negligible).
    pub fn of(positions: impl IntoIterator<Item = DVec3>) -> Self {
        let (lo, hi) = positions.into_iter().fold(
            (DVec3::splat(f64::INFINITY), DVec3::splat(f64::NEG_INFINITY)),
            |(lo, hi), p| (lo.min(p), hi.max(p)),
        );
        let cut = NEGLIGIBLE * (hi - lo).length();
        NegligibleLength(if cut.is_finite() { cut } else { 0.0 })
    }

    /// `d` as written: zero when shorter than the negligible length.
    pub fn written(self, d: DVec3) -> Vec3 {
        if d.length() < self.0 {
            Vec3::ZERO
        } else {
            d.as_vec3()
        }
    }
}

/// Why no retargeting could be computed.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
pub enum RetargetError {
    /// The avatar has no morph targets that move its face.
    #[error(
        "none of the avatar's {0} morph targets moves its face region: nothing to retarget onto"
    )]
    NoFaceTargets(usize),
    /// The mask shapes do not fit the registration.
    #[error("the ARKit shapes have {found} vertices, the registered mask {expected}")]
    MaskSize {
        /// Vertices of the registered mask.
        expected: usize,
        /// Vertices of the shapes given.
        found: usize,
    },
    /// The normal equations could not be factored.
    #[error("the retargeting system could not be solved")]
    Singular,
}

/// One of the avatar's blendshapes as the weights refer to it: every morph
/// target of that name, on whichever meshes have it (engines drive the
/// targets of one name together: jawOpen on the head, the teeth and the
/// tongue is one blendshape).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct AvatarBlendshape {
    /// The targets' name as read.
    pub name: String,
    /// Its targets, `(mesh, index within the mesh)`.
    pub targets: Vec<(usize, usize)>,
}

/// The avatar's blendshapes: its morph targets grouped by name, in the
/// order each name first appears; a target `found` takes whole for one of
/// ARKit's shapes goes by ARKit's name, as the avatar is written
/// (`AK_18_JawOpen` on the head and `jawOpen` on the teeth are one).
pub fn avatar_blendshapes(avatar: &Avatar, found: &ArkitTargets) -> Vec<AvatarBlendshape> {
    let mut out: Vec<AvatarBlendshape> = Vec::new();
    for (m, t) in avatar.target_ids() {
        let name = match found.taken_as(m, t) {
            TargetName::Arkit(shape) => shape.name(),
            _ => &avatar.meshes()[m].target_names[t],
        };
        match out.iter_mut().find(|b| b.name == name) {
            Some(b) => b.targets.push((m, t)),
            None => out.push(AvatarBlendshape {
                name: name.to_string(),
                targets: vec![(m, t)],
            }),
        }
    }
    out
}

/// Eq. (4) solved for all 52 shapes.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Retargeting {
    /// The avatar's blendshapes, `k` of them, in the order of each row of
    /// `weights`.
    pub targets: Vec<AvatarBlendshape>,
    /// `w̃_j` for each ARKit shape `j` in Apple's order: `weights[j][i]` is
    /// the weight of target `i` that reproduces shape `j`.
    pub weights: Vec<Vec<f64>>,
    /// μ₀ (dimensionless; module docs).
    pub relative_ridge: f64,
    /// μ, in the avatar's length² (summed over the face vertices).
    pub mu: f64,
    /// Relative residual `‖G w̃_j − M B_j‖ / ‖M B_j‖` per shape (0 where
    /// `M B_j` vanishes).
    pub relative_residual: Vec<f64>,
    /// The same with `‖M B_j‖` floored at
    /// [`super::implant_check::RESIDUAL_FLOOR_MM`] RMS over the face
    /// vertices (mask scale): what the avatar stage's check compares, so a
    /// shape that hardly moves does not make a tiny residual look large.
    pub floored_residual: Vec<f64>,
}

impl Retargeting {
    /// The smallest and largest weight over all shapes and targets.
    pub fn weight_range(&self) -> (f64, f64) {
        self.weights
            .iter()
            .flatten()
            .fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), w| {
                (lo.min(*w), hi.max(*w))
            })
    }

    /// `A_j`: the displacement of every avatar vertex (as
    /// `Avatar::positions`) under ARKit shape `shape`, `Σ_i w̃_ji B̃_i`.
    pub fn displacement(&self, avatar: &Avatar, shape: Blendshape) -> Vec<Vec3> {
        let own = self.blendshape_displacements(avatar);
        self.combine(avatar.vertex_count(), &own, shape, NegligibleLength(0.0))
    }

    /// `A_j` for all 52 shapes, each avatar blendshape's displacement
    /// computed once. Displacements shorter than [`NEGLIGIBLE`] of the
    /// avatar's size are set to zero: invisible, and they would keep a
    /// sparse target from being sparse.
    pub fn displacements(&self, avatar: &Avatar) -> Vec<Vec<Vec3>> {
        let own = self.blendshape_displacements(avatar);
        let positions = avatar.positions();
        let cut = NegligibleLength::of(positions.iter().map(|p| p.as_dvec3()));
        in_parallel_map(Blendshape::ALL.len(), |j| {
            self.combine(positions.len(), &own, Blendshape::ALL[j], cut)
        })
    }

    /// Each avatar blendshape's displacement, as the vertices it moves
    /// (index and displacement): targets move a small part of the head, so
    /// combining 52 of them touches only those.
    fn blendshape_displacements(&self, avatar: &Avatar) -> Vec<Vec<(usize, Vec3)>> {
        in_parallel_map(self.targets.len(), |i| {
            let d = avatar.summed_displacement(&self.targets[i].targets);
            d.into_iter()
                .enumerate()
                .filter(|(_, x)| *x != Vec3::ZERO)
                .collect()
        })
    }

    /// `Σ_i w̃_ji B̃_i` over `n` vertices from the blendshapes' moved
    /// vertices `own`, lengths below `cut` set to zero.
    fn combine(
        &self,
        n: usize,
        own: &[Vec<(usize, Vec3)>],
        shape: Blendshape,
        cut: NegligibleLength,
    ) -> Vec<Vec3> {
        let mut out = vec![DVec3::ZERO; n];
        if let Some(row) = self.weights.get(shape.index()) {
            for (d, w) in own.iter().zip(row) {
                if *w != 0.0 {
                    for (v, x) in d {
                        if let Some(o) = out.get_mut(*v) {
                            *o += x.as_dvec3() * *w;
                        }
                    }
                }
            }
        }
        out.into_iter().map(|d| cut.written(d)).collect()
    }
}

/// `M B_j` for every ARKit shape: the deltas of `shapes` (mask topology)
/// carried into the avatar's frame at its face vertices.
pub fn mapped_shapes(
    registration: &FaceRegistration,
    shapes: &Blendshapes,
) -> Result<Vec<Vec<DVec3>>, RetargetError> {
    let expected = registration.mask_on_avatar.len();
    if shapes.vertex_count() != expected {
        return Err(RetargetError::MaskSize {
            expected,
            found: shapes.vertex_count(),
        });
    }
    let s = registration.similarity;
    Ok(Blendshape::ALL
        .iter()
        .map(|b| {
            let field: Vec<DVec3> = shapes
                .delta(*b)
                .iter()
                .map(|d| s.apply_vector(*d))
                .collect();
            registration.map.apply(&field)
        })
        .collect())
}

/// The vertices whose motion the face does not see, for `U_i` (module
/// docs): those of the face's parts beyond the face region, but the lids
/// ([`lid_vertices`]).
fn unseen_vertices(
    avatar: &Avatar,
    registration: &FaceRegistration,
    positions: &[DVec3],
    lids: &[bool],
) -> Vec<bool> {
    let offsets = avatar.vertex_offsets();
    let mut hidden = vec![false; positions.len()];
    for &i in &registration.face_parts() {
        if i + 1 < offsets.len() {
            hidden[offsets[i]..offsets[i + 1]].fill(true);
        }
    }
    for f in &registration.map.face {
        if let Some(x) = hidden.get_mut(f.vertex as usize) {
            *x = false;
        }
    }
    for (x, lid) in hidden.iter_mut().zip(lids) {
        if *lid {
            *x = false;
        }
    }
    hidden
}

/// The vertices within [`LIDS_REACH`] eyeball radii of an eyeball's
/// centre, the eyeballs' own (`in_eyeball`) aside: the lids and the skin
/// round them.
fn lid_vertices(
    registration: &FaceRegistration,
    positions: &[DVec3],
    in_eyeball: &[bool],
) -> Vec<bool> {
    let mut lids = vec![false; positions.len()];
    for eyeball in &registration.eyeballs {
        let points: Vec<DVec3> = eyeball
            .iter()
            .filter_map(|&v| positions.get(v as usize).copied())
            .collect();
        let centre = points.iter().sum::<DVec3>() / points.len().max(1) as f64;
        let radius = points
            .iter()
            .map(|p| p.distance(centre))
            .fold(0.0, f64::max);
        for (p, x) in positions.iter().zip(lids.iter_mut()) {
            if p.distance(centre) <= LIDS_REACH * radius {
                *x = true;
            }
        }
    }
    for (x, eyeball) in lids.iter_mut().zip(in_eyeball) {
        *x &= !eyeball;
    }
    lids
}

/// Whether each avatar vertex belongs to a piece the jaw turns: the teeth
/// and the tongue (by the parts' roles). Not the eyeballs: the mask sees
/// the jaw's motion on the chin, but never an eyeball's, so a weight past
/// 1 on an eyeLook target would turn the eyeball further than anything
/// measured (and, squinting, into the lid: 0.29 mm on the default
/// avatar).
fn jaw_piece_vertices(avatar: &Avatar, registration: &FaceRegistration) -> Vec<bool> {
    use super::registration::part_roles::PartRole;
    let offsets = avatar.vertex_offsets();
    let mut jaw = vec![false; avatar.vertex_count()];
    for (part, role) in registration.roles.iter().enumerate() {
        let turned = matches!(
            role,
            PartRole::UpperTeeth | PartRole::LowerTeeth | PartRole::Teeth | PartRole::Tongue
        );
        if turned && part + 1 < offsets.len() {
            jaw[offsets[part]..offsets[part + 1]].fill(true);
        }
    }
    jaw
}

/// Solves Eq. (4) for all 52 ARKit shapes of `shapes` (module docs).
pub fn retarget(
    avatar: &Avatar,
    registration: &FaceRegistration,
    shapes: &Blendshapes,
) -> Result<Retargeting, RetargetError> {
    let found = arkit_targets(avatar);
    let targets = avatar_blendshapes(avatar, &found);
    let face = &registration.map.face;
    let rows = 3 * face.len();
    // G: each target's displacement seen through the mask as the person's
    // shapes are, `M S(B̃_i)`; targets that do not move the face get a
    // zero column (and weight 0).
    let positions: Vec<DVec3> = avatar.positions().iter().map(|p| p.as_dvec3()).collect();
    let on_skin = MaskOnSkin::new(
        registration,
        &positions,
        &face_part_triangles(avatar, registration),
    );
    let in_eyeball = eyeball_flags(avatar, registration);
    let lids = lid_vertices(registration, &positions, &in_eyeball);
    let hidden = unseen_vertices(avatar, registration, &positions, &lids);
    let jaw = jaw_piece_vertices(avatar, registration);
    let mut unseen = vec![0.0; targets.len()];
    let mut turns_the_jaw = vec![false; targets.len()];
    let mut turns_an_eye = vec![false; targets.len()];
    let mut moves_the_lids = vec![false; targets.len()];
    let mut g = Mat::<f64>::zeros(rows, targets.len());
    for (i, blendshape) in targets.iter().enumerate() {
        let d: Vec<DVec3> = avatar
            .summed_displacement(&blendshape.targets)
            .iter()
            .map(|d| d.as_dvec3())
            .collect();
        let largest = d.iter().map(|x| x.length()).fold(0.0, f64::max);
        turns_the_jaw[i] = turns_a_piece(&d, largest, &jaw);
        turns_an_eye[i] = turns_a_piece(&d, largest, &in_eyeball);
        moves_the_lids[i] = turns_a_piece(&d, largest, &lids);
        unseen[i] = d
            .iter()
            .zip(&hidden)
            .filter(|(_, h)| **h)
            .map(|(d, _)| d.length_squared())
            .sum();
        let seen = registration.map.apply(&on_skin.see(&d));
        for (r, v) in seen.iter().enumerate() {
            for axis in 0..3 {
                g[(3 * r + axis, i)] = v[axis];
            }
        }
    }
    let gram = g.transpose() * &g;
    let k = targets.len();
    let mean = (0..k).map(|i| gram[(i, i)]).sum::<f64>() / k.max(1) as f64;
    if mean <= 0.0 {
        return Err(RetargetError::NoFaceTargets(k));
    }
    let mu = RELATIVE_RIDGE * mean;
    let mut system = gram.clone();
    for i in 0..k {
        system[(i, i)] += mu;
    }
    let mapped = mapped_shapes(registration, shapes)?;
    let mut rhs = Mat::<f64>::zeros(rows, BLENDSHAPE_COUNT);
    for (j, field) in mapped.iter().enumerate() {
        for (r, d) in field.iter().enumerate() {
            for axis in 0..3 {
                rhs[(3 * r + axis, j)] = d[axis];
            }
        }
    }
    let mut gt_b = g.transpose() * &rhs;
    // What each target moves where the face cannot see it (`U_i`, summed
    // in the loop above): a departure from the prior costs that much more
    // (module docs).
    for (i, u) in unseen.iter().enumerate() {
        system[(i, i)] += u;
    }
    // The prior: each ARKit shape is the avatar's own target taken for it
    // (both halves of a split one; not one passed over for another).
    let own_of: Vec<Option<usize>> = targets
        .iter()
        .map(|b| {
            (b.targets.iter())
                .find_map(|&(m, t)| found.shape_of(m, t))
                .map(Blendshape::index)
        })
        .collect();
    for j in 0..BLENDSHAPE_COUNT {
        let own: Vec<usize> = (0..k).filter(|&i| own_of[i] == Some(j)).collect();
        // A shape that moves the lids, or turns an eyeball or the jaw,
        // keeps the artist's full weight (module docs).
        let full = own
            .iter()
            .any(|&i| moves_the_lids[i] || turns_an_eye[i] || turns_the_jaw[i]);
        let amount = match full {
            true => 1.0,
            false => own_amount(&gram, &own, |i| gt_b[(i, j)]),
        };
        for &i in &own {
            gt_b[(i, j)] += (mu + unseen[i]) * amount;
        }
    }
    // Each shape's weights, the least of E_j over the box (module docs).
    let mut w = Mat::<f64>::zeros(k, BLENDSHAPE_COUNT);
    for j in 0..BLENDSHAPE_COUNT {
        let hi: Vec<f64> = (0..k)
            .map(|i| match own_of[i] == Some(j) && turns_the_jaw[i] {
                true => f64::INFINITY,
                false => 1.0,
            })
            .collect();
        let bounds = Bounds::new(vec![0.0; k], hi).map_err(|_| RetargetError::Singular)?;
        let c: Vec<f64> = (0..k).map(|i| gt_b[(i, j)]).collect();
        let least = minimize(&system, &c, &bounds).map_err(|_| RetargetError::Singular)?;
        for (i, x) in least.w.into_iter().enumerate() {
            w[(i, j)] = x;
        }
    }
    let fitted = &g * &w;
    let floor = face.len() as f64
        * (super::implant_check::RESIDUAL_FLOOR_MM * 1e-3 * registration.similarity.scale).powi(2);
    let (relative_residual, floored_residual) = (0..BLENDSHAPE_COUNT)
        .map(|j| {
            let (mut err, mut norm) = (0.0, 0.0);
            for r in 0..rows {
                err += (fitted[(r, j)] - rhs[(r, j)]).powi(2);
                norm += rhs[(r, j)].powi(2);
            }
            let relative = if norm > 0.0 { (err / norm).sqrt() } else { 0.0 };
            (relative, (err / norm.max(floor)).sqrt())
        })
        .unzip();
    Ok(Retargeting {
        targets,
        weights: (0..BLENDSHAPE_COUNT)
            .map(|j| (0..k).map(|i| w[(i, j)]).collect())
            .collect(),
        relative_ridge: RELATIVE_RIDGE,
        mu,
        relative_residual,
        floored_residual,
    })
}

/// A target turns a rigid piece (the jaw's teeth, gums and tongue, or an
/// eyeball), or moves the lids, when it moves some vertex of them by more
/// than this share of the most it moves any vertex: a rig's jaw shapes move the
/// lower teeth as far as the chin, or nearly (ICT-FaceKit's jawOpen,
/// jawLeft, jawRight and jawForward 81–100%), while a rig made from scans
/// can leave a little noise on pieces its other shapes do not move
/// (ICT-FaceKit's cheekPuff and mouthStretchRight move the teeth by 1.2%
/// and 2.8% of their largest motion).
pub const TURNS_SHARE: f64 = 0.25;

/// Whether displacement `d`, at most `largest` long, turns (or moves) the
/// piece whose vertices `piece` flags ([`TURNS_SHARE`]).
fn turns_a_piece(d: &[DVec3], largest: f64, piece: &[bool]) -> bool {
    let on_piece = d
        .iter()
        .zip(piece)
        .filter(|(_, p)| **p)
        .map(|(x, _)| x.length())
        .fold(0.0, f64::max);
    on_piece > 0.0 && on_piece > TURNS_SHARE * largest
}

/// `s_j`, how much of the avatar's own shape `j` the person's motion shows
/// on the face (module docs, "How much of the own shape"): the
/// least-squares scale of the own targets `own` (both halves of a split
/// one) to the person's motion, `⟨G e_j, M B_j⟩ / ‖G e_j‖²` from `GᵀG`
/// (`gram`) and `Gᵀ M B_j` (`along(i)` for target `i`), clamped to
/// `[0, 1]`; 1 where the face does not see the own shape (eyeLook, a
/// tongue) or the avatar has none.
pub fn own_amount(gram: &Mat<f64>, own: &[usize], along: impl Fn(usize) -> f64) -> f64 {
    let seen: f64 = own
        .iter()
        .flat_map(|&a| own.iter().map(move |&b| gram[(a, b)]))
        .sum();
    let along: f64 = own.iter().map(|&i| along(i)).sum();
    if seen > 0.0 && along.is_finite() {
        (along / seen).clamp(0.0, 1.0)
    } else {
        1.0
    }
}
