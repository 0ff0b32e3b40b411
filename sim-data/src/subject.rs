//! Simulated people: an identity and a personal way of making each
//! expression, drawn from a seed.
//!
//! - **Identity**: the generic neutral face scaled per axis (width, height and
//!   depth vary by about 5%, 5% and 8% between adults; Farkas 1994 reports
//!   coefficients of variation of 4–7% for facial breadths and heights) and
//!   reshaped by eight smooth bumps (radius 1.5–4 cm, a few millimetres:
//!   fuller cheeks, a longer nose, a stronger chin).
//! - **Style**: per shape a gain (log-normal, σ = 0.25: one person's smile is
//!   a quarter wider than another's), per handle a turned direction (σ = 15°),
//!   a shifted centre (σ = 2.5 mm) and a changed extent (σ = 12%); left and
//!   right of a pair differ by a further asymmetry (σ = 10%); and each shape
//!   gets one idiosyncratic extra handle of 15–35% of its largest motion, so
//!   a person's shape is not a deformation of the template's.
//! - **Beyond a linear model**: the jaw rotates, mouthClose multiplies the jaw
//!   opening, a smile with an open jaw carries a corrective, and a closing
//!   lid bulges (see [`crate::face_model`]).

use crate::face_basis::FaceBasis;
use crate::face_model::FaceModel;
use crate::regions::{Region, kernel};
use crate::shape_spec::{Handle, JawJoint, ShapeSpec, Special, generic_specs};
use glam::{DMat3, DQuat, DVec3};
use likeness::{BLENDSHAPE_COUNT, Blendshape};
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;
use rand_distr::{Distribution, LogNormal, Normal};

/// Standard deviation of the per-axis face scale (width, height, depth).
pub const IDENTITY_SCALE_SD: [f64; 3] = [0.05, 0.05, 0.08];
/// Number of smooth identity bumps.
pub const IDENTITY_BUMPS: usize = 8;
/// Standard deviation of a bump's displacement per axis (m).
pub const IDENTITY_BUMP_SD: [f64; 3] = [0.0015, 0.0015, 0.0025];
/// Log-normal σ of a shape's overall gain.
pub const STYLE_GAIN_SIGMA: f64 = 0.25;
/// Standard deviation of the left/right asymmetry of a mirrored pair.
pub const STYLE_ASYMMETRY_SD: f64 = 0.10;
/// Standard deviation of a handle's direction change (rad, 15°).
pub const STYLE_TURN_SD: f64 = 15.0 * std::f64::consts::PI / 180.0;
/// Standard deviation of a handle's centre shift (m).
pub const STYLE_SHIFT_SD: f64 = 0.0025;
/// Log-normal σ of a handle's extent and of its own gain.
pub const STYLE_EXTENT_SIGMA: f64 = 0.12;
/// Range of the idiosyncratic handle's size relative to the shape's largest.
pub const IDIOSYNCRATIC_RANGE: (f64, f64) = (0.15, 0.35);

/// Log-normal σ of a person's jaw opening relative to the template's.
pub const JAW_ANGLE_SIGMA: f64 = 0.15;
/// Bounds of that factor: with the template's 4 cm it keeps the chin travel
/// within the 3–5 cm of a comfortable full opening.
pub const JAW_ANGLE_RANGE: (f64, f64) = (0.8, 1.2);

/// A simulated person.
#[derive(Clone, Debug)]
pub struct Subject {
    /// The seed the person was drawn from.
    pub seed: u64,
    /// The person's face, nonlinear.
    pub model: FaceModel,
}

fn normal(rng: &mut ChaCha8Rng, sd: f64) -> f64 {
    Normal::new(0.0, sd).expect("positive sd").sample(rng)
}

fn log_normal(rng: &mut ChaCha8Rng, sigma: f64) -> f64 {
    LogNormal::new(0.0, sigma)
        .expect("positive sigma")
        .sample(rng)
}

fn random_turn(rng: &mut ChaCha8Rng, sd: f64) -> DQuat {
    let axis =
        DVec3::new(normal(rng, 1.0), normal(rng, 1.0), normal(rng, 1.0)).normalize_or(DVec3::Z);
    DQuat::from_axis_angle(axis, normal(rng, sd))
}

fn style_handle(rng: &mut ChaCha8Rng, h: &Handle, gain: f64) -> Handle {
    let turn = random_turn(rng, STYLE_TURN_SD);
    Handle {
        centre: [
            h.centre[0] + normal(rng, STYLE_SHIFT_SD),
            h.centre[1] + normal(rng, STYLE_SHIFT_SD),
        ],
        radius: h.radius.map(|r| r * log_normal(rng, STYLE_EXTENT_SIGMA)),
        displacement: turn * h.displacement * gain * log_normal(rng, STYLE_EXTENT_SIGMA),
        region: h.region,
    }
}

/// A person's version of one shape.
fn style_shape(rng: &mut ChaCha8Rng, spec: &ShapeSpec, gain: f64) -> ShapeSpec {
    let mut handles: Vec<Handle> = spec
        .handles
        .iter()
        .map(|h| style_handle(rng, h, gain))
        .collect();
    let special = match spec.special {
        Special::None => Special::None,
        Special::Blink { side, .. } => Special::Blink {
            side,
            meet: rng.random_range(0.15..0.35),
            bulge: rng.random_range(0.0005..0.002),
            upper_reach: 0.013 * log_normal(rng, STYLE_EXTENT_SIGMA),
            lower_reach: 0.007 * log_normal(rng, STYLE_EXTENT_SIGMA),
            gap: 0.0,
        },
        Special::JawRotation { angle } => Special::JawRotation {
            angle: angle
                * log_normal(rng, JAW_ANGLE_SIGMA).clamp(JAW_ANGLE_RANGE.0, JAW_ANGLE_RANGE.1),
        },
        Special::JawTranslation { offset } => Special::JawTranslation {
            offset: random_turn(rng, STYLE_TURN_SD) * offset * gain,
        },
        Special::MouthClose { .. } => Special::MouthClose {
            upper_share: rng.random_range(0.15..0.4),
        },
    };
    // The idiosyncratic extra handle, near the shape's strongest handle (or
    // the jaw for the jaw motions). A blink gets none: whatever the person,
    // the lids meet; its style is where they meet and how the skin follows.
    let anchor = spec
        .handles
        .iter()
        .max_by(|a, b| a.displacement.length().total_cmp(&b.displacement.length()))
        .copied();
    let (centre, region, size) = match (anchor, spec.special) {
        (_, Special::Blink { .. }) => return ShapeSpec { handles, special },
        (Some(h), _) => (h.centre, h.region, h.displacement.length() * gain),
        (None, _) => ([0.0, -0.06], Region::LowerLip, 0.01 * gain),
    };
    let direction =
        DVec3::new(normal(rng, 1.0), normal(rng, 1.0), normal(rng, 1.0)).normalize_or(DVec3::Y);
    let r = rng.random_range(0.008..0.018);
    handles.push(Handle {
        centre: [
            centre[0] + normal(rng, 0.008),
            centre[1] + normal(rng, 0.008),
        ],
        radius: [r, r],
        displacement: direction
            * size
            * rng.random_range(IDIOSYNCRATIC_RANGE.0..IDIOSYNCRATIC_RANGE.1),
        region,
    });
    ShapeSpec { handles, special }
}

impl Subject {
    /// Draws a person from `seed` on the simulator's mask; the same seed
    /// always gives the same person.
    pub fn from_seed(seed: u64) -> Subject {
        Subject::on(FaceBasis::Simulator, seed)
    }

    /// Draws a person from `seed` on `basis`: the same draws on every
    /// basis, so seed 5 on ARKit's mesh has seed 5's proportions and style
    /// ([`crate::face_basis`]).
    pub fn on(basis: FaceBasis, seed: u64) -> Subject {
        let mut rng = ChaCha8Rng::seed_from_u64(seed ^ 0x5355_424a_4543_5400); // "SUBJECT"
        let mask = basis.mask();
        let placed = basis.jaw();
        let scale = DMat3::from_diagonal(DVec3::from_array(
            IDENTITY_SCALE_SD.map(|sd| 1.0 + normal(&mut rng, sd)),
        ));
        let bumps: Vec<(DVec3, [f64; 2], f64)> = (0..IDENTITY_BUMPS)
            .map(|_| {
                let c = [rng.random_range(-0.06..0.06), rng.random_range(-0.09..0.07)];
                let d = DVec3::from_array(IDENTITY_BUMP_SD.map(|sd| normal(&mut rng, sd)));
                (d, c, rng.random_range(0.015..0.04))
            })
            .collect();
        let neutral: Vec<DVec3> = mask
            .neutral
            .iter()
            .zip(&mask.uv)
            .map(|(p, uv)| {
                let bump: DVec3 = bumps
                    .iter()
                    .map(|(d, c, r)| {
                        let t = ((uv[0] - c[0]).powi(2) + (uv[1] - c[1]).powi(2)).sqrt() / r;
                        *d * kernel(t)
                    })
                    .sum();
                scale * (p.as_dvec3() + bump)
            })
            .collect();
        let jaw = JawJoint {
            hinge: scale
                * (placed.hinge
                    + DVec3::new(0.0, normal(&mut rng, 0.004), normal(&mut rng, 0.004))),
            glide: scale * placed.glide,
        };
        let generic = generic_specs();
        let mut gains = [0.0; BLENDSHAPE_COUNT];
        for shape in Blendshape::ALL {
            if shape.mirror() == shape || shape < shape.mirror() {
                let g = log_normal(&mut rng, STYLE_GAIN_SIGMA);
                let asym = normal(&mut rng, STYLE_ASYMMETRY_SD);
                gains[shape.index()] = g * (1.0 + asym);
                gains[shape.mirror().index()] = g * (1.0 - asym);
                if shape.mirror() == shape {
                    gains[shape.index()] = g;
                }
            }
        }
        let specs: Vec<ShapeSpec> = Blendshape::ALL
            .iter()
            .map(|s| style_shape(&mut rng, &generic[s.index()], gains[s.index()]))
            .collect();
        let mut model = FaceModel::build(mask, neutral, &specs, scale, jaw);
        if let Some(offsets) = basis.offsets() {
            for (delta, offset) in model.deltas.iter_mut().zip(offsets) {
                delta.add_scaled(offset, scale);
            }
        }
        for (side, sign) in [(0, 1.0), (1, -1.0)] {
            let corrective = Handle {
                centre: [sign * 0.025, -0.047],
                radius: [0.015, 0.015],
                displacement: DVec3::new(-sign * 0.001, -0.003, 0.0) * rng.random_range(0.5..1.5),
                region: Region::Any,
            };
            model.set_smile_jaw(mask, side, &corrective);
        }
        Subject { seed, model }
    }
}
