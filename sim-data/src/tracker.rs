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
//! bias, cross-talk between shapes that move the same skin, sensor noise,
//! light temporal smoothing, and clamping to `[0, 1]`. The noise and the
//! smoothing are measured on real Live Link Face takes (sim-data/README.md,
//! "The tracker"): at rest real weights wander slowly and smoothly (the
//! first differences are strongly correlated from one frame to the next),
//! yet a blink rises from 10% to 90% within two frames. So ARKit filters
//! small changes heavily and follows large ones at once, as an adaptive
//! filter does (the 1€ filter of Casiez, Roussel & Vogel 2012 behaves so).
//! The simulation separates the two: the noise is white noise through two
//! cascaded exponential filters ([`WEIGHT_NOISE_FILTER`]), slow and smooth;
//! the signal passes one light exponential filter ([`WEIGHT_SMOOTHING`]).

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
/// Mean and standard deviation of a per-shape weight bias. Below zero the
/// clamp holds the weight at 0 at rest: with noise, about 70% of the
/// channels rest at exactly 0, as 34–41 of 52 do in the real takes.
pub const WEIGHT_BIAS: (f64, f64) = (-0.005, 0.03);
/// Standard deviation of the weight noise (stationary, after its filter).
/// With [`WEIGHT_NOISE_FILTER`] it reproduces the real takes' noise at
/// rest: residual σ 7–9 × 10⁻⁴ after a quadratic fit over half a second,
/// σ of second differences 2.4–3.2 × 10⁻⁴.
pub const WEIGHT_NOISE_SD: f64 = 0.0065;
/// Coefficient of each of the two cascaded exponential filters that make
/// the noise smooth: the real takes' first differences at rest have a lag-1
/// autocorrelation of 0.78–0.80; white noise through two filters of 0.08
/// gives about 0.76 (a single filter cannot make it positive).
pub const WEIGHT_NOISE_FILTER: f64 = 0.08;
/// Exponential smoothing factor of the signal per frame: a step rises from
/// 10% to 90% within one frame (the real takes' fastest blinks take two,
/// the lid's own closing included), a group delay of (1 − 0.7)/0.7 ≈ 0.4
/// frame.
pub const WEIGHT_SMOOTHING: f64 = 0.7;

/// Frames the noise filters run before the first frame, so the noise is
/// stationary from the start (ten time constants of the filters).
const NOISE_WARM_UP: usize = 250;

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

/// Shapes on which some people's relaxed faces rest high, as groups of a
/// shape and its mirror: the shapes that rest highest in the real takes
/// (eyeSquint, browInnerUp, mouthSmile, cheekSquint, browDown, mouthRollLower
/// and mouthShrugLower rest at 0.04–0.16 even after Live Link Face's
/// neutral-pose calibration), and mouthFrown and mouthPress, which a
/// downturned or pressed resting mouth shows.
pub const HIGH_REST_CANDIDATES: [Blendshape; 9] = {
    use Blendshape::*;
    [
        BrowDownLeft,
        BrowInnerUp,
        EyeSquintLeft,
        CheekSquintLeft,
        MouthSmileLeft,
        MouthFrownLeft,
        MouthShrugLower,
        MouthRollLower,
        MouthPressLeft,
    ]
};

/// Range of a high resting level (the issue of real users: some shapes rest
/// at 0.3–0.5).
pub const HIGH_REST_LEVEL: (f64, f64) = (0.3, 0.5);

/// Resting offsets of the weights of a person whose face rests high on
/// `groups` of [`HIGH_REST_CANDIDATES`] (a shape and its mirror, each side
/// within ±0.03 of the group's level), drawn from `seed`; all zero for
/// `groups == 0`. Drawn apart from the tracker's own randomness, so a
/// session without them is unchanged.
pub fn high_rest_offsets(seed: u64, groups: usize) -> [f64; BLENDSHAPE_COUNT] {
    let mut offsets = [0.0; BLENDSHAPE_COUNT];
    if groups == 0 {
        return offsets;
    }
    let mut rng = ChaCha8Rng::seed_from_u64(seed ^ 0x5245_5354_4849_4748); // "RESTHIGH"
    let mut candidates = HIGH_REST_CANDIDATES.to_vec();
    for _ in 0..groups.min(candidates.len()) {
        let shape = candidates.swap_remove(rng.random_range(0..candidates.len()));
        let level = rng.random_range(HIGH_REST_LEVEL.0..HIGH_REST_LEVEL.1);
        for side in [shape, shape.mirror()] {
            offsets[side.index()] = level + rng.random_range(-0.03..0.03);
        }
    }
    offsets
}

/// The simulated tracker of one person's session (stateful: it smooths).
pub struct Tracker {
    gain: [f64; BLENDSHAPE_COUNT],
    bias: [f64; BLENDSHAPE_COUNT],
    crosstalk: Vec<(usize, usize, f64)>,
    smoothed: Option<[f64; BLENDSHAPE_COUNT]>,
    /// The two stages of each channel's noise filter.
    noise: [[f64; 2]; BLENDSHAPE_COUNT],
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
        Tracker {
            gain,
            bias,
            crosstalk,
            smoothed: None,
            noise: [[0.0; 2]; BLENDSHAPE_COUNT],
            fields,
            coefficients: Vec::new(),
            rho: (-1.0 / (frame_rate * MESH_NOISE_TAU)).exp(),
            rng: rng.clone(),
        }
        .with_noise_from(rng)
    }

    /// The tracker's noise started from `rng`: the mesh noise's initial
    /// coefficients drawn, and the weight noise's filters run into their
    /// stationary state.
    fn with_noise_from(mut self, rng: ChaCha8Rng) -> Tracker {
        self.rng = rng;
        let normal = Normal::new(0.0, 1.0).expect("unit normal");
        self.coefficients = (0..MESH_NOISE_FIELDS)
            .map(|_| normal.sample(&mut self.rng))
            .collect();
        for _ in 0..NOISE_WARM_UP {
            self.next_noise();
        }
        self
    }

    /// The same tracker reporting each weight raised by `offsets` at rest
    /// (see [`high_rest_offsets`]); the clamp at 1 still holds.
    pub fn with_rest_offsets(mut self, offsets: [f64; BLENDSHAPE_COUNT]) -> Tracker {
        for (b, o) in self.bias.iter_mut().zip(offsets) {
            *b += o;
        }
        self
    }

    /// The same tracker (the person's distortion and noise fields) on
    /// another sitting: its noise drawn afresh from `seed`.
    pub fn with_noise_seed(self, seed: u64) -> Tracker {
        self.with_noise_from(ChaCha8Rng::seed_from_u64(seed ^ 0x4e4f_4953_4500_0000)) // "NOISE"
    }

    /// The next frame's noise of every channel: white noise through two
    /// cascaded exponential filters of coefficient `β`
    /// ([`WEIGHT_NOISE_FILTER`]). Their impulse response is
    /// `β² (k + 1) (1 − β)^k`, so the stationary variance is
    /// `β⁴ (1 + ρ²) / (1 − ρ²)³` times the input's, `ρ = 1 − β`; the input
    /// is scaled so the output's σ is [`WEIGHT_NOISE_SD`].
    fn next_noise(&mut self) -> [f64; BLENDSHAPE_COUNT] {
        let beta = WEIGHT_NOISE_FILTER;
        let rho2 = (1.0 - beta) * (1.0 - beta);
        let gain = beta.powi(4) * (1.0 + rho2) / (1.0 - rho2).powi(3);
        let input_sd = WEIGHT_NOISE_SD / gain.sqrt();
        let normal = Normal::new(0.0, 1.0).expect("unit normal");
        let mut out = [0.0; BLENDSHAPE_COUNT];
        for (stages, o) in self.noise.iter_mut().zip(out.iter_mut()) {
            let e = input_sd * normal.sample(&mut self.rng);
            stages[0] += beta * (e - stages[0]);
            stages[1] += beta * (stages[0] - stages[1]);
            *o = stages[1];
        }
        out
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
        let smoothed = match self.smoothed {
            None => raw,
            Some(prev) => std::array::from_fn(|j| prev[j] + WEIGHT_SMOOTHING * (raw[j] - prev[j])),
        };
        self.smoothed = Some(smoothed);
        let noise = self.next_noise();
        let weights = Weights(std::array::from_fn(|j| {
            (smoothed[j] + noise[j]).clamp(0.0, 1.0) as f32
        }));
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
