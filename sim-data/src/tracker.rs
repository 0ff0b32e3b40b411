//! What an iPhone reports: ARKit's face tracker, simulated.
//!
//! **Mesh.** ARKit's face geometry is the output of a fitted parametric model,
//! so its error is smooth over the face and over time, not independent per
//! vertex. The simulated mesh is the person's true face plus a sum of
//! [`MESH_NOISE_FIELDS`] smooth random fields (Gaussian bumps of radius 2–5 cm,
//! directions favouring depth, the least constrained axis of a frontal
//! camera), whose coefficients follow an Ornstein–Uhlenbeck process with
//! time constant [`MESH_NOISE_TAU`] (ARKit filters its fit over time). The
//! per-vertex RMS error is drawn per person from [`MESH_NOISE_RMS`].
//!
//! **Weights.** ARKit estimates the 52 weights with its own generic model, so
//! they are a distorted view of the true activations: per-shape gain and
//! bias, cross-talk between shapes that move the same skin, white noise,
//! exponential temporal smoothing, and clamping to `[0, 1]`.

use glam::{DVec3, Vec3};
use likeness::{BLENDSHAPE_COUNT, Blendshape, Weights};
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;
use rand_distr::{Distribution, Normal};

/// Number of smooth mesh-noise fields.
pub const MESH_NOISE_FIELDS: usize = 16;
/// Range of a person's per-vertex RMS mesh error (m): 0.1–0.3 mm.
pub const MESH_NOISE_RMS: (f64, f64) = (0.0001, 0.0003);
/// Time constant of the mesh-noise coefficients (s).
pub const MESH_NOISE_TAU: f64 = 0.3;
/// Range of a person's per-shape weight gain.
pub const WEIGHT_GAIN: (f64, f64) = (0.85, 1.05);
/// Mean and standard deviation of a per-shape weight bias.
pub const WEIGHT_BIAS: (f64, f64) = (0.01, 0.01);
/// Standard deviation of the per-frame weight noise before smoothing.
pub const WEIGHT_NOISE_SD: f64 = 0.015;
/// Exponential smoothing factor of the weights per frame (0.5 ≈ one frame
/// of lag at 60 fps).
pub const WEIGHT_SMOOTHING: f64 = 0.5;

/// Tracker cross-talk: `(source, lights up, base amount)`; each person's
/// amount is the base times a factor in 0.5–1.5. Pairs that move the same
/// skin, listed once for the left side and mirrored.
pub const CROSSTALK: [(Blendshape, Blendshape, f64); 12] = {
    use Blendshape::*;
    [
        (EyeBlinkLeft, EyeSquintLeft, 0.10),
        (EyeSquintLeft, CheekSquintLeft, 0.10),
        (CheekSquintLeft, EyeSquintLeft, 0.10),
        (MouthSmileLeft, MouthDimpleLeft, 0.08),
        (MouthSmileLeft, CheekSquintLeft, 0.08),
        (MouthPucker, MouthFunnel, 0.10),
        (MouthFunnel, MouthPucker, 0.10),
        (MouthRollLower, MouthRollUpper, 0.08),
        (MouthLowerDownLeft, JawOpen, 0.08),
        (MouthPressLeft, MouthClose, 0.05),
        (BrowInnerUp, BrowOuterUpLeft, 0.10),
        (NoseSneerLeft, MouthUpperUpLeft, 0.10),
    ]
};

/// The simulated tracker of one person's session (stateful: it smooths).
pub struct Tracker {
    gain: [f64; BLENDSHAPE_COUNT],
    bias: [f64; BLENDSHAPE_COUNT],
    crosstalk: Vec<(usize, usize, f64)>,
    smoothed: Option<[f64; BLENDSHAPE_COUNT]>,
    fields: Vec<Vec<DVec3>>,
    coefficients: Vec<f64>,
    rho: f64,
    rng: ChaCha8Rng,
}

impl Tracker {
    /// A tracker for a face with parameter-plane coordinates `uv`, at
    /// `frame_rate` Hz, drawn from `seed`.
    pub fn new(seed: u64, uv: &[[f64; 2]], frame_rate: f64) -> Tracker {
        let mut rng = ChaCha8Rng::seed_from_u64(seed ^ 0x5452_4143_4b45_5200); // "TRACKER"
        let normal = Normal::new(0.0, 1.0).expect("unit normal");
        let gain = std::array::from_fn(|_| rng.random_range(WEIGHT_GAIN.0..WEIGHT_GAIN.1));
        let bias = std::array::from_fn(|_| WEIGHT_BIAS.0 + WEIGHT_BIAS.1 * normal.sample(&mut rng));
        let mut crosstalk = Vec::new();
        for (from, to, amount) in CROSSTALK {
            let left = amount * rng.random_range(0.5..1.5);
            let right = amount * rng.random_range(0.5..1.5);
            crosstalk.push((from.index(), to.index(), left));
            if from.mirror() != from || to.mirror() != to {
                crosstalk.push((from.mirror().index(), to.mirror().index(), right));
            }
        }
        let rms = rng.random_range(MESH_NOISE_RMS.0..MESH_NOISE_RMS.1);
        let mut fields: Vec<Vec<DVec3>> = (0..MESH_NOISE_FIELDS)
            .map(|_| {
                let c = uv[rng.random_range(0..uv.len())];
                let r = rng.random_range(0.02..0.05);
                let dir = DVec3::new(
                    normal.sample(&mut rng),
                    normal.sample(&mut rng),
                    2.0 * normal.sample(&mut rng),
                )
                .normalize_or(DVec3::Z);
                uv.iter()
                    .map(|p| {
                        let d2 = (p[0] - c[0]).powi(2) + (p[1] - c[1]).powi(2);
                        dir * (-d2 / (r * r)).exp()
                    })
                    .collect()
            })
            .collect();
        // Scale so the mean per-vertex variance of Σ c_k φ_k (c_k ~ N(0,1)) is rms².
        let variance: f64 = fields
            .iter()
            .flatten()
            .map(|d| d.length_squared())
            .sum::<f64>()
            / uv.len() as f64;
        let s = rms / variance.sqrt();
        fields.iter_mut().flatten().for_each(|d| *d *= s);
        let coefficients = (0..MESH_NOISE_FIELDS)
            .map(|_| normal.sample(&mut rng))
            .collect();
        Tracker {
            gain,
            bias,
            crosstalk,
            smoothed: None,
            fields,
            coefficients,
            rho: (-1.0 / (frame_rate * MESH_NOISE_TAU)).exp(),
            rng,
        }
    }

    /// One frame: the reported weights for true activations `a`, and the
    /// reported mesh for the true face.
    pub fn observe(
        &mut self,
        a: &[f64; BLENDSHAPE_COUNT],
        true_face: &[DVec3],
    ) -> (Weights, Vec<Vec3>) {
        let normal = Normal::new(0.0, 1.0).expect("unit normal");
        let mut raw: [f64; BLENDSHAPE_COUNT] =
            std::array::from_fn(|j| self.gain[j] * a[j] + self.bias[j]);
        for (from, to, amount) in &self.crosstalk {
            raw[*to] += amount * a[*from];
        }
        for r in raw.iter_mut() {
            *r += WEIGHT_NOISE_SD * normal.sample(&mut self.rng);
        }
        let smoothed = match self.smoothed {
            None => raw,
            Some(prev) => std::array::from_fn(|j| prev[j] + WEIGHT_SMOOTHING * (raw[j] - prev[j])),
        };
        self.smoothed = Some(smoothed);
        let weights = Weights(smoothed.map(|w| w.clamp(0.0, 1.0) as f32));
        let innovation = (1.0 - self.rho * self.rho).sqrt();
        for c in self.coefficients.iter_mut() {
            *c = self.rho * *c + innovation * normal.sample(&mut self.rng);
        }
        let mesh = true_face
            .iter()
            .enumerate()
            .map(|(i, p)| {
                let noise: DVec3 = self
                    .fields
                    .iter()
                    .zip(&self.coefficients)
                    .map(|(f, c)| f[i] * *c)
                    .sum();
                (*p + noise).as_vec3()
            })
            .collect();
        (weights, mesh)
    }
}
