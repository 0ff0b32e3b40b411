//! A face that can make expressions: neutral positions, one delta field per
//! ARKit shape, and the nonlinear behaviour of a real face.
//!
//! The *linear* model is what ARKit's template is and what personalization
//! fits: `B₀ + Σ wⱼ Bⱼ`. A simulated person is not linear:
//! - the mandible rotates about the hinge (a point on the chin travels on an
//!   arc, not along the chord that a linear shape interpolates), and the
//!   rotation carries whatever the other shapes did to the lower face;
//! - mouthClose only closes the lips as far as the jaw is open (its effect is
//!   `a_close · a_jaw · C`, a product);
//! - a smile with an open jaw pulls the corners down and in (a corrective
//!   `a_smile · a_jaw · K`);
//! - a closing upper lid slides over the cornea and bulges forward halfway
//!   (`4a(1 − a)` times a bulge).

use crate::face_mask::FaceMask;
use crate::regions::{Region, jaw_weight, kernel, lower_lid_share, region_weight};
use crate::shape_spec::{Handle, JawJoint, ShapeSpec, Special};
use glam::{DMat3, DVec3};
use likeness::{BLENDSHAPE_COUNT, Blendshape};

/// A shape's delta field, stored sparsely (only vertices that move).
#[derive(Clone, Debug, Default)]
pub struct SparseField {
    /// `(vertex, displacement)` pairs.
    pub entries: Vec<(u32, DVec3)>,
}

impl SparseField {
    /// The nonzero entries of a dense field.
    pub fn from_dense(dense: &[DVec3]) -> SparseField {
        SparseField {
            entries: dense
                .iter()
                .enumerate()
                .filter(|(_, d)| d.length_squared() > 1e-18)
                .map(|(i, d)| (i as u32, *d))
                .collect(),
        }
    }

    /// Adds `map` applied to each of `other`'s displacements to this field.
    pub fn add_scaled(&mut self, other: &SparseField, map: DMat3) {
        let mut merged: std::collections::BTreeMap<u32, DVec3> =
            self.entries.iter().copied().collect();
        for (i, d) in &other.entries {
            *merged.entry(*i).or_insert(DVec3::ZERO) += map * *d;
        }
        self.entries = merged.into_iter().collect();
    }

    /// Adds `scale` times the field to `positions`.
    pub fn add_to(&self, positions: &mut [DVec3], scale: f64) {
        for (i, d) in &self.entries {
            positions[*i as usize] += scale * *d;
        }
    }
}

/// Nonlinear extras of a person (none for the linear template).
#[derive(Clone, Debug, Default)]
pub struct Nonlinear {
    /// Forward bulge field of each closing upper lid, `[left, right]`.
    pub blink_bulge: [SparseField; 2],
    /// Smile-with-open-jaw corrective per side.
    pub smile_jaw: [SparseField; 2],
}

/// Neutral face plus 52 delta fields, and optionally nonlinear behaviour.
#[derive(Clone, Debug)]
pub struct FaceModel {
    /// Neutral positions `B₀` (m).
    pub neutral: Vec<DVec3>,
    /// Linear delta blendshapes `B₁…B₅₂` at weight one (m).
    pub deltas: Vec<SparseField>,
    /// The mandible's joint.
    pub jaw: JawJoint,
    /// Jaw opening at weight one (rad).
    pub jaw_angle: f64,
    /// How much each vertex follows the mandible.
    pub jaw_weights: Vec<f64>,
    /// Nonlinear behaviour; `None` for a purely linear face.
    pub nonlinear: Option<Nonlinear>,
}

fn handle_field(mask: &FaceMask, h: &Handle, scale: DVec3) -> Vec<DVec3> {
    mask.uv
        .iter()
        .map(|uv| {
            let t = (((uv[0] - h.centre[0]) / h.radius[0]).powi(2)
                + ((uv[1] - h.centre[1]) / h.radius[1]).powi(2))
            .sqrt();
            let w = kernel(t) * region_weight(h.region, *uv);
            w * scale * h.displacement
        })
        .collect()
}

/// Blink field: lid vertices meet (or, with a `gap`, stop that far apart
/// on the line between them, each lid short by its share of the travel);
/// skin nearby follows its lid. Returns the linear delta and the forward
/// bulge of the upper-lid side.
fn blink_field(
    mask: &FaceMask,
    neutral: &[DVec3],
    side: usize,
    meet: f64,
    bulge: f64,
    reach: [f64; 2],
    gap: f64,
) -> (Vec<DVec3>, Vec<DVec3>) {
    let lm = &mask.landmarks;
    let (upper, lower) = (&lm.upper_lid[side], &lm.lower_lid[side]);
    let n = neutral.len();
    let mut delta = vec![DVec3::ZERO; n];
    let mut bulge_field = vec![DVec3::ZERO; n];
    let mut lid_delta: Vec<(usize, DVec3, bool)> = Vec::new();
    for (&u, &l) in upper.iter().zip(lower) {
        let (pu, pl) = (neutral[u as usize], neutral[l as usize]);
        let m = pl + meet * (pu - pl);
        let (mu, ml) = if gap > 0.0 {
            // Never wider than the open eye: a lid does not move backwards.
            let apart = (pu - pl).normalize_or_zero() * gap.min(pu.distance(pl));
            (m + (1.0 - meet) * apart, m - meet * apart)
        } else {
            (m, m)
        };
        lid_delta.push((u as usize, mu - pu, true));
        lid_delta.push((l as usize, ml - pl, false));
    }
    let corners = [lm.eye_inner[side] as usize, lm.eye_outer[side] as usize];
    for (i, uv) in mask.uv.iter().enumerate() {
        if corners.contains(&i) {
            continue;
        }
        if let Some((_, d, up)) = lid_delta.iter().find(|(v, _, _)| *v == i) {
            delta[i] = *d;
            if *up {
                bulge_field[i] = DVec3::Z * bulge;
            }
            continue;
        }
        let lower_share = lower_lid_share(*uv, side);
        for (is_upper, share, r) in [
            (true, 1.0 - lower_share, reach[0]),
            (false, lower_share, reach[1]),
        ] {
            if share <= 0.0 {
                continue;
            }
            let (mut sum, mut wsum, mut dmin) = (DVec3::ZERO, 0.0, f64::INFINITY);
            for (v, d, up) in &lid_delta {
                if *up != is_upper {
                    continue;
                }
                let q = mask.uv[*v];
                let dist = ((uv[0] - q[0]).powi(2) + (uv[1] - q[1]).powi(2)).sqrt();
                let w = (-(dist / 0.004).powi(2)).exp() + 1e-12;
                sum += w * *d;
                wsum += w;
                dmin = dmin.min(dist);
            }
            let fade = share * kernel(dmin / r);
            delta[i] += fade * sum / wsum;
            if is_upper {
                bulge_field[i] += fade * DVec3::Z * bulge;
            }
        }
    }
    (delta, bulge_field)
}

impl FaceModel {
    /// Builds a face from the mask's parametrization, `neutral` positions,
    /// the shapes' specifications, a linear map `scale` applied to every
    /// handle displacement (the person's proportions), and the jaw joint.
    pub fn build(
        mask: &FaceMask,
        neutral: Vec<DVec3>,
        specs: &[ShapeSpec],
        scale: DMat3,
        jaw: JawJoint,
    ) -> FaceModel {
        assert_eq!(specs.len(), BLENDSHAPE_COUNT, "one spec per ARKit shape");
        let n = neutral.len();
        let jaw_weights: Vec<f64> = mask.uv.iter().map(|uv| jaw_weight(*uv)).collect();
        let jaw_angle = match specs[Blendshape::JawOpen.index()].special {
            Special::JawRotation { angle } => angle,
            _ => 0.0,
        };
        let jaw_delta: Vec<DVec3> = (0..n)
            .map(|i| jaw_weights[i] * (jaw.open(neutral[i], jaw_angle) - neutral[i]))
            .collect();
        let mut deltas = Vec::with_capacity(BLENDSHAPE_COUNT);
        let mut blink_bulge: [SparseField; 2] = Default::default();
        for spec in specs {
            let mut dense = vec![DVec3::ZERO; n];
            for h in &spec.handles {
                for (d, add) in dense.iter_mut().zip(handle_field(mask, h, DVec3::ONE)) {
                    *d += scale * add;
                }
            }
            match spec.special {
                Special::None => {}
                Special::Blink {
                    side,
                    meet,
                    bulge,
                    upper_reach,
                    lower_reach,
                    gap,
                } => {
                    let (d, b) = blink_field(
                        mask,
                        &neutral,
                        side,
                        meet,
                        bulge,
                        [upper_reach, lower_reach],
                        gap,
                    );
                    dense.iter_mut().zip(d).for_each(|(a, b)| *a += b);
                    blink_bulge[side] = SparseField::from_dense(&b);
                }
                Special::JawRotation { .. } => {
                    dense.iter_mut().zip(&jaw_delta).for_each(|(a, b)| *a += *b);
                }
                Special::JawTranslation { offset } => {
                    for (d, w) in dense.iter_mut().zip(&jaw_weights) {
                        *d += *w * (scale * offset);
                    }
                }
                Special::MouthClose { upper_share } => {
                    mouth_close_field(mask, &jaw_delta, upper_share, &mut dense);
                }
            }
            deltas.push(SparseField::from_dense(&dense));
        }
        FaceModel {
            neutral,
            deltas,
            jaw,
            jaw_angle,
            jaw_weights,
            nonlinear: Some(Nonlinear {
                blink_bulge,
                smile_jaw: Default::default(),
            }),
        }
    }

    /// The linear model `B₀ + Σ aⱼ Bⱼ` (what ARKit's template and the
    /// personalized blendshapes are).
    pub fn linear(&self, activations: &[f64; BLENDSHAPE_COUNT]) -> Vec<DVec3> {
        let mut p = self.neutral.clone();
        for (field, a) in self.deltas.iter().zip(activations) {
            if a.abs() > 1e-9 {
                field.add_to(&mut p, *a);
            }
        }
        p
    }

    /// The face at true muscle activations `a`, with all nonlinear behaviour
    /// (see the module documentation). Equals [`FaceModel::linear`] when the
    /// model has no nonlinear part.
    pub fn evaluate(&self, a: &[f64; BLENDSHAPE_COUNT]) -> Vec<DVec3> {
        let Some(nl) = &self.nonlinear else {
            return self.linear(a);
        };
        use Blendshape as B;
        let jaw = a[B::JawOpen.index()];
        let mut p = self.neutral.clone();
        for (j, (field, aj)) in self.deltas.iter().zip(a).enumerate() {
            let weight = match Blendshape::ALL[j] {
                B::JawOpen => 0.0,
                B::MouthClose => aj * jaw,
                _ => *aj,
            };
            if weight.abs() > 1e-9 {
                field.add_to(&mut p, weight);
            }
        }
        for (side, blink) in [B::EyeBlinkLeft, B::EyeBlinkRight].into_iter().enumerate() {
            let ab = a[blink.index()];
            nl.blink_bulge[side].add_to(&mut p, 4.0 * ab * (1.0 - ab));
        }
        for (side, smile) in [B::MouthSmileLeft, B::MouthSmileRight]
            .into_iter()
            .enumerate()
        {
            nl.smile_jaw[side].add_to(&mut p, a[smile.index()] * jaw);
        }
        if jaw.abs() > 1e-9 {
            let angle = self.jaw_angle * jaw;
            for (q, w) in p.iter_mut().zip(&self.jaw_weights) {
                if *w > 0.0 {
                    *q += *w * (self.jaw.open(*q, angle) - *q);
                }
            }
        }
        p
    }

    /// Absolute positions of shape `j` at weight one, alone (the linear model).
    pub fn shape(&self, j: Blendshape) -> Vec<DVec3> {
        let mut p = self.neutral.clone();
        self.deltas[j.index()].add_to(&mut p, 1.0);
        p
    }

    /// Adds a smile-with-open-jaw corrective handle for `side`.
    pub fn set_smile_jaw(&mut self, mask: &FaceMask, side: usize, h: &Handle) {
        let field = handle_field(mask, h, DVec3::ONE);
        if let Some(nl) = &mut self.nonlinear {
            nl.smile_jaw[side] = SparseField::from_dense(&field);
        }
    }
}

/// mouthClose: below the mouth the lips take back part of the jaw's motion;
/// above it the upper lip comes down to meet them (ARKit's mouthClose is the
/// lip closure *relative to* an open jaw).
fn mouth_close_field(mask: &FaceMask, jaw_delta: &[DVec3], upper_share: f64, dense: &mut [DVec3]) {
    let lm = &mask.landmarks;
    let mouth_y = crate::face_mask::MOUTH_CENTRE[1];
    let lower_row: Vec<u32> = std::iter::once(lm.lip_corners[1])
        .chain(lm.lower_lip.iter().copied())
        .chain(std::iter::once(lm.lip_corners[0]))
        .collect();
    for (i, uv) in mask.uv.iter().enumerate() {
        let row = crate::face_mask::lip_row_offset(uv[0]);
        let lower = region_weight(Region::LowerLip, *uv);
        let below = (mouth_y - row - uv[1]).max(0.0);
        let above = (uv[1] - mouth_y - row).max(0.0);
        let nearest = lower_row
            .iter()
            .min_by(|a, b| {
                let da = (mask.uv[**a as usize][0] - uv[0]).abs();
                let db = (mask.uv[**b as usize][0] - uv[0]).abs();
                da.total_cmp(&db)
            })
            .map(|v| jaw_delta[*v as usize])
            .unwrap_or(DVec3::ZERO);
        dense[i] += -(1.0 - upper_share) * lower * kernel(below / 0.012) * jaw_delta[i];
        dense[i] += upper_share * (1.0 - lower) * kernel(above / 0.010) * nearest;
    }
}
