//! How a person performs the app's prompts: true muscle activations over
//! time, at the stream's frame rate.
//!
//! For each prompt the person reacts after a delay, ramps up, overshoots to a
//! peak and settles to a slightly lower hold with tremor (the common pattern
//! of voluntary force production: an initial peak, then a sustained level),
//! and ramps down. Other shapes come along (nobody can wink without the other
//! eye twitching). Sometimes the first attempt is too weak and the person
//! tries again; sometimes the tracker reports a one-frame spike.

use crate::regions::smoothstep;
use likeness::{BLENDSHAPE_COUNT, Blendshape, prompt_order::PROMPT_ORDER};
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;
use rand_distr::{Distribution, LogNormal};
use std::ops::Range;

/// Length of the neutral hold at the start (s).
pub const NEUTRAL_HOLD: f64 = 2.0;
/// When, within the hold, the neutral scan is taken (s).
pub const NEUTRAL_SCAN_AT: f64 = 1.5;
/// Median reaction delay after a prompt appears (s) and its log-normal σ;
/// choice reaction times to a written instruction are 0.4–0.8 s.
pub const REACTION_MEDIAN: (f64, f64) = (0.55, 0.3);
/// Range of the peak activation of a real attempt.
pub const PEAK_RANGE: (f64, f64) = (0.7, 1.0);
/// Range of the peak activation of a failed first attempt.
pub const FAILED_PEAK_RANGE: (f64, f64) = (0.15, 0.35);
/// Probability that a prompt starts with a failed (too weak) attempt.
pub const FAILED_ATTEMPT_PROBABILITY: f64 = 0.15;
/// Probability of a one-frame tracker spike on the prompted weight.
pub const SPIKE_PROBABILITY: f64 = 0.10;
/// Probability of a short tracking loss between two prompts.
pub const TRACKING_LOSS_PROBABILITY: f64 = 0.03;
/// Time the app shows "captured" before the next prompt (s).
pub const ADVANCE_AFTER_PEAK: f64 = 0.35;
/// Amplitude of physiological tremor on a hold (activation units, 8–12 Hz).
pub const TREMOR: f64 = 0.01;

/// One attempt at an expression: an activation envelope over time.
#[derive(Clone, Copy, Debug)]
pub struct Envelope {
    /// Start (s).
    pub start: f64,
    /// Rise time to the peak (s).
    pub rise: f64,
    /// Peak activation.
    pub peak: f64,
    /// Hold level as a fraction of the peak.
    pub hold_ratio: f64,
    /// Time constant of settling from peak to hold (s).
    pub settle: f64,
    /// Hold duration (s).
    pub hold: f64,
    /// Fall time (s).
    pub fall: f64,
    /// Tremor frequency (Hz) and phase (rad).
    pub tremor: (f64, f64),
}

impl Envelope {
    fn draw(rng: &mut ChaCha8Rng, start: f64, peak: f64) -> Envelope {
        Envelope {
            start,
            rise: rng.random_range(0.25..0.5),
            peak,
            hold_ratio: rng.random_range(0.8..0.92),
            settle: rng.random_range(0.08..0.15),
            hold: rng.random_range(0.4..0.9),
            fall: rng.random_range(0.25..0.5),
            tremor: (
                rng.random_range(8.0..12.0),
                rng.random_range(0.0..std::f64::consts::TAU),
            ),
        }
    }

    /// Time of the peak (s).
    pub fn peak_time(&self) -> f64 {
        self.start + self.rise
    }

    /// Time the activation is back to zero (s).
    pub fn end(&self) -> f64 {
        self.start + self.rise + self.hold + self.fall
    }

    /// Activation at time `t`, normalised so the peak is `self.peak`.
    pub fn at(&self, t: f64) -> f64 {
        let t = t - self.start;
        if t <= 0.0 {
            return 0.0;
        }
        if t < self.rise {
            return self.peak * smoothstep(0.0, self.rise, t);
        }
        let level = |s: f64| {
            let hold = self.peak * self.hold_ratio;
            let settle = (-(s / self.settle).powi(2)).exp();
            let tremor = TREMOR
                * (1.0 - settle)
                * (std::f64::consts::TAU * self.tremor.0 * s + self.tremor.1).sin();
            hold + (self.peak - hold) * settle + tremor
        };
        let s = t - self.rise;
        if s < self.hold {
            return level(s);
        }
        level(self.hold) * (1.0 - smoothstep(0.0, self.fall, s - self.hold))
    }
}

/// Shapes that come along with a prompt: `(prompt, other, base amount)`,
/// listed for the left side and mirrored. Each person's amount is the base
/// times a factor in 0.5–1.5. Gaze is conjugate: asked to look down with the
/// left eye, both eyes look down.
pub const COACTIVATION: [(Blendshape, Blendshape, f64); 44] = {
    use Blendshape::*;
    [
        (EyeBlinkLeft, EyeBlinkRight, 0.25),
        (EyeBlinkLeft, CheekSquintLeft, 0.15),
        (EyeBlinkLeft, EyeSquintLeft, 0.2),
        (EyeLookDownLeft, EyeLookDownRight, 0.9),
        (EyeLookUpLeft, EyeLookUpRight, 0.9),
        (EyeLookInLeft, EyeLookOutRight, 0.9),
        (EyeLookOutLeft, EyeLookInRight, 0.9),
        (EyeSquintLeft, EyeSquintRight, 0.3),
        (EyeSquintLeft, CheekSquintLeft, 0.3),
        (EyeWideLeft, EyeWideRight, 0.4),
        (EyeWideLeft, BrowOuterUpLeft, 0.3),
        (EyeWideLeft, BrowInnerUp, 0.2),
        (JawForward, JawOpen, 0.15),
        (JawLeft, MouthLeft, 0.3),
        (JawOpen, MouthFunnel, 0.1),
        (JawOpen, MouthLowerDownLeft, 0.15),
        (JawOpen, MouthLowerDownRight, 0.15),
        (MouthClose, JawOpen, 0.7),
        (MouthFunnel, JawOpen, 0.2),
        (MouthFunnel, MouthPucker, 0.3),
        (MouthPucker, MouthFunnel, 0.2),
        (MouthPucker, MouthRollLower, 0.1),
        (MouthLeft, MouthSmileLeft, 0.1),
        (MouthSmileLeft, MouthSmileRight, 0.2),
        (MouthSmileLeft, CheekSquintLeft, 0.4),
        (MouthSmileLeft, EyeSquintLeft, 0.2),
        (MouthSmileLeft, MouthDimpleLeft, 0.15),
        (MouthFrownLeft, MouthFrownRight, 0.3),
        (MouthFrownLeft, MouthShrugLower, 0.2),
        (MouthDimpleLeft, MouthSmileLeft, 0.2),
        (MouthStretchLeft, MouthStretchRight, 0.3),
        (MouthStretchLeft, MouthLowerDownLeft, 0.2),
        (MouthRollLower, MouthRollUpper, 0.3),
        (MouthRollUpper, MouthRollLower, 0.3),
        (MouthShrugLower, MouthShrugUpper, 0.3),
        (MouthShrugUpper, MouthShrugLower, 0.3),
        (MouthPressLeft, MouthPressRight, 0.4),
        (MouthLowerDownLeft, MouthLowerDownRight, 0.4),
        (MouthUpperUpLeft, MouthUpperUpRight, 0.3),
        (MouthUpperUpLeft, NoseSneerLeft, 0.3),
        (BrowDownLeft, BrowDownRight, 0.4),
        (BrowInnerUp, BrowOuterUpLeft, 0.3),
        (BrowOuterUpLeft, BrowInnerUp, 0.3),
        (NoseSneerLeft, MouthUpperUpLeft, 0.3),
    ]
};

/// One prompt as performed.
#[derive(Clone, Debug)]
pub struct PromptTrack {
    /// The requested shape.
    pub shape: Blendshape,
    /// Frame at which the app showed the prompt.
    pub shown: usize,
    /// Frames of the attempt that counts.
    pub attempt: Range<usize>,
    /// Frame of the true peak of the requested activation.
    pub true_peak: usize,
    /// Frames of a failed first attempt, if any.
    pub failed_attempt: Option<Range<usize>>,
    /// A one-frame tracker spike: frame and reported value.
    pub spike: Option<(usize, f32)>,
}

/// A held-out test expression as performed.
#[derive(Clone, Debug)]
pub struct TestTrack {
    /// Its name, e.g. `smile-squint`.
    pub id: String,
    /// Frame of its true peak.
    pub frame: usize,
}

/// A whole session's true activations, frame by frame.
#[derive(Clone, Debug)]
pub struct Timeline {
    /// Frame rate (Hz).
    pub frame_rate: f64,
    /// True activations per frame.
    pub activations: Vec<[f64; BLENDSHAPE_COUNT]>,
    /// Frame of the neutral scan.
    pub neutral_frame: usize,
    /// The 52 prompts in order.
    pub prompts: Vec<PromptTrack>,
    /// The test expressions in order.
    pub tests: Vec<TestTrack>,
    /// Frames during which tracking is lost.
    pub tracking_lost: Vec<Range<usize>>,
}

struct Builder {
    rng: ChaCha8Rng,
    frame_rate: f64,
    /// (shape, envelope, scale) contributions.
    parts: Vec<(usize, Envelope, f64)>,
}

impl Builder {
    fn frame(&self, t: f64) -> usize {
        (t * self.frame_rate).round() as usize
    }

    fn perform(&mut self, recipe: &[(usize, f64)], env: Envelope) {
        for (shape, amount) in recipe {
            self.parts.push((*shape, env, *amount));
        }
    }
}

fn coactivation(rng: &mut ChaCha8Rng) -> Vec<(usize, usize, f64)> {
    let mut table = Vec::new();
    for (from, to, amount) in COACTIVATION {
        table.push((
            from.index(),
            to.index(),
            amount * rng.random_range(0.5..1.5),
        ));
        if from.mirror() != from || to.mirror() != to {
            table.push((
                from.mirror().index(),
                to.mirror().index(),
                amount * rng.random_range(0.5..1.5),
            ));
        }
    }
    table
}

/// Draws a session's performance: neutral hold, 52 prompts in
/// [`PROMPT_ORDER`], then the test expressions from
/// [`crate::test_expressions`].
pub fn perform_session(seed: u64, frame_rate: f64) -> Timeline {
    let mut rng = ChaCha8Rng::seed_from_u64(seed ^ 0x5045_5246_4f52_4d00); // "PERFORM"
    let coact = coactivation(&mut rng);
    let reaction = LogNormal::new(REACTION_MEDIAN.0.ln(), REACTION_MEDIAN.1).expect("valid");
    let mut b = Builder {
        rng,
        frame_rate,
        parts: Vec::new(),
    };
    // Neutral hold: faint, slow micro-activations of a few shapes.
    let mut neutral_parts = Vec::new();
    for _ in 0..3 {
        let shape = b.rng.random_range(0..BLENDSHAPE_COUNT);
        neutral_parts.push((
            shape,
            b.rng.random_range(0.0..0.03),
            b.rng.random_range(0.0..std::f64::consts::TAU),
        ));
    }
    let mut t = NEUTRAL_HOLD;
    let mut previous_end = 0.0;
    let mut prompts = Vec::new();
    let mut tracking_lost = Vec::new();
    for shape in PROMPT_ORDER {
        let shown = t;
        let mut start =
            (shown + reaction.sample(&mut b.rng).clamp(0.25, 1.5)).max(previous_end + 0.05);
        let mut failed_attempt = None;
        if b.rng.random_bool(FAILED_ATTEMPT_PROBABILITY) {
            let peak = b.rng.random_range(FAILED_PEAK_RANGE.0..FAILED_PEAK_RANGE.1);
            let env = Envelope::draw(&mut b.rng, start, peak);
            b.perform(&[(shape.index(), 1.0)], env);
            failed_attempt = Some(b.frame(env.start)..b.frame(env.end()));
            start = env.end() + b.rng.random_range(0.3..0.7);
        }
        let peak = b.rng.random_range(PEAK_RANGE.0..PEAK_RANGE.1);
        let env = Envelope::draw(&mut b.rng, start, peak);
        let mut recipe = vec![(shape.index(), 1.0)];
        recipe.extend(
            coact
                .iter()
                .filter(|c| c.0 == shape.index())
                .map(|c| (c.1, c.2)),
        );
        if b.rng.random_bool(0.3) {
            recipe.push((
                b.rng.random_range(0..BLENDSHAPE_COUNT),
                b.rng.random_range(0.03..0.1),
            ));
        }
        recipe.retain(|(s, a)| *s != shape.index() || *a == 1.0);
        b.perform(&recipe, env);
        let spike_window = b.frame(shown) + 3..b.frame(start).saturating_sub(3);
        let spike = (b.rng.random_bool(SPIKE_PROBABILITY) && !spike_window.is_empty()).then(|| {
            (
                b.rng.random_range(spike_window),
                b.rng.random_range(0.6..1.0) as f32,
            )
        });
        let attempt = b.frame(env.start)..b.frame(env.end());
        prompts.push(PromptTrack {
            shape,
            shown: b.frame(shown),
            true_peak: b.frame(env.peak_time()),
            attempt,
            failed_attempt,
            spike,
        });
        previous_end = env.end();
        t = env.peak_time() + ADVANCE_AFTER_PEAK;
        if b.rng.random_bool(TRACKING_LOSS_PROBABILITY) {
            let from = b.frame(env.end()) + 1;
            tracking_lost.push(from..from + b.rng.random_range(5..20));
            t = t.max((from + 25) as f64 / frame_rate);
        }
    }
    let tests =
        crate::test_expressions::perform_tests(&mut b.rng, &mut t, frame_rate, &mut b.parts);
    let frames = b.frame(t + 1.0);
    let mut activations = vec![[0.0; BLENDSHAPE_COUNT]; frames];
    for (f, a) in activations.iter_mut().enumerate() {
        let time = f as f64 / frame_rate;
        let fade = 1.0 - smoothstep(NEUTRAL_HOLD, NEUTRAL_HOLD + 0.5, time);
        if fade > 0.0 {
            for (shape, amount, phase) in &neutral_parts {
                a[*shape] += fade * amount * (0.5 + 0.5 * (0.7 * time + phase).sin());
            }
        }
    }
    for (shape, env, scale) in &b.parts {
        let from = b.frame(env.start);
        let to = (b.frame(env.end()) + 1).min(frames);
        for (f, a) in activations.iter_mut().enumerate().take(to).skip(from) {
            a[*shape] += scale * env.at(f as f64 / frame_rate);
        }
    }
    for a in activations.iter_mut() {
        a.iter_mut().for_each(|x| *x = x.clamp(0.0, 1.0));
    }
    // The true peak: the frame of the attempt where the requested activation
    // (with everything else that moved it) is largest.
    for p in prompts.iter_mut() {
        let j = p.shape.index();
        p.true_peak = p
            .attempt
            .clone()
            .max_by(|x, y| activations[*x][j].total_cmp(&activations[*y][j]))
            .unwrap_or(p.true_peak);
    }
    Timeline {
        frame_rate,
        activations,
        neutral_frame: b.frame(NEUTRAL_SCAN_AT),
        prompts,
        tests,
        tracking_lost,
    }
}

/// Draws an envelope (for the test expressions).
pub(crate) fn draw_envelope(rng: &mut ChaCha8Rng, start: f64, peak: f64) -> Envelope {
    Envelope::draw(rng, start, peak)
}
