//! How a person performs the app's prompts: true muscle activations over
//! time, at the stream's frame rate.
//!
//! After a neutral hold, for each prompt the person reacts after a delay and
//! makes an attempt (an [`Envelope`]: a ramp up, an overshoot to a peak, a
//! slightly lower hold with tremor, a ramp down). Other shapes come along
//! (nobody can wink without the other eye twitching). Sometimes the first
//! attempt is too weak and the person tries again; sometimes the tracker
//! reports a one-frame spike or loses the face. The test expressions of
//! [`crate::test_expressions`] follow the prompts.

use crate::envelope::{Envelope, Score};
use crate::regions::smoothstep;
use crate::test_expressions::perform_tests;
use crate::timeline::{PromptTrack, TestTrack, Timeline, frame_at};
use likeness::capture::prompt_order::PROMPT_ORDER;
use likeness::{BLENDSHAPE_COUNT, Blendshape};
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

/// Draws a session's performance: neutral hold, 52 prompts in
/// [`PROMPT_ORDER`], then the test expressions from
/// [`crate::test_expressions`].
pub fn perform_session(seed: u64, frame_rate: f64) -> Timeline {
    let rng = ChaCha8Rng::seed_from_u64(seed ^ 0x5045_5246_4f52_4d00); // "PERFORM"
    let mut performer = Performer::new(rng, frame_rate);
    let neutral = NeutralHold::draw(&mut performer.rng);
    let (mut prompts, tracking_lost) = performer.perform_prompts();
    let tests = performer.perform_tests();
    let activations = true_activations(&neutral, &performer.score, performer.clock, frame_rate);
    locate_true_peaks(&mut prompts, &activations);
    Timeline {
        frame_rate,
        activations,
        neutral_frame: frame_at(NEUTRAL_SCAN_AT, frame_rate),
        prompts,
        tests,
        tracking_lost,
    }
}

/// Draws each person's co-activation table from [`COACTIVATION`]:
/// `(prompted shape, other shape, amount)`, mirrored pairs included.
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

/// The faint, slow micro-activations of a few shapes during the neutral
/// hold: `(shape, amount below 0.03, phase)`.
struct NeutralHold(Vec<(usize, f64, f64)>);

impl NeutralHold {
    /// Draws three micro-activations.
    fn draw(rng: &mut ChaCha8Rng) -> NeutralHold {
        let mut parts = Vec::new();
        for _ in 0..3 {
            let shape = rng.random_range(0..BLENDSHAPE_COUNT);
            parts.push((
                shape,
                rng.random_range(0.0..0.03),
                rng.random_range(0.0..std::f64::consts::TAU),
            ));
        }
        NeutralHold(parts)
    }

    /// Adds the micro-activations to every frame, fading them out over the
    /// half second after the hold.
    fn add_to(&self, activations: &mut [[f64; BLENDSHAPE_COUNT]], frame_rate: f64) {
        for (f, a) in activations.iter_mut().enumerate() {
            let time = f as f64 / frame_rate;
            let fade = 1.0 - smoothstep(NEUTRAL_HOLD, NEUTRAL_HOLD + 0.5, time);
            if fade > 0.0 {
                for (shape, amount, phase) in &self.0 {
                    a[*shape] += fade * amount * (0.5 + 0.5 * (0.7 * time + phase).sin());
                }
            }
        }
    }
}

/// The person going through the prompts: their random draws, their
/// co-activation table and reaction delays, the score performed so far and
/// the session's clock.
struct Performer {
    rng: ChaCha8Rng,
    frame_rate: f64,
    /// This person's co-activation table (see [`coactivation`]).
    coactivation: Vec<(usize, usize, f64)>,
    /// Distribution of the reaction delay (s).
    reaction: LogNormal<f64>,
    /// Everything performed so far.
    score: Score,
    /// When the app shows the next prompt (s).
    clock: f64,
    /// When the previous attempt ended (s).
    previous_end: f64,
}

impl Performer {
    /// A person at the end of the neutral hold, with their co-activation
    /// table drawn from `rng`.
    fn new(mut rng: ChaCha8Rng, frame_rate: f64) -> Performer {
        let coactivation = coactivation(&mut rng);
        let reaction = LogNormal::new(REACTION_MEDIAN.0.ln(), REACTION_MEDIAN.1).expect("valid");
        Performer {
            rng,
            frame_rate,
            coactivation,
            reaction,
            score: Score::default(),
            clock: NEUTRAL_HOLD,
            previous_end: 0.0,
        }
    }

    /// The frame nearest to time `t` (s).
    fn frame(&self, t: f64) -> usize {
        frame_at(t, self.frame_rate)
    }

    /// Draws the prompt attempts, one prompt after another in
    /// [`PROMPT_ORDER`]; returns the prompts and the frames where tracking
    /// is lost.
    fn perform_prompts(&mut self) -> (Vec<PromptTrack>, Vec<Range<usize>>) {
        let mut prompts = Vec::new();
        let mut tracking_lost = Vec::new();
        for shape in PROMPT_ORDER {
            let (prompt, lost) = self.perform_prompt(shape);
            prompts.push(prompt);
            tracking_lost.extend(lost);
        }
        (prompts, tracking_lost)
    }

    /// Performs one prompt shown now: an optional failed attempt, the
    /// attempt that counts, an optional tracker spike before it, then the
    /// app advances (after an optional tracking loss).
    fn perform_prompt(&mut self, shape: Blendshape) -> (PromptTrack, Option<Range<usize>>) {
        let shown = self.clock;
        let start = self.reaction_start(shown);
        let (failed_attempt, start) = self.failed_attempt(shape, start);
        let env = self.counted_attempt(shape, start);
        let spike = self.spike(shown, start);
        let prompt = PromptTrack {
            shape,
            shown: self.frame(shown),
            true_peak: self.frame(env.peak_time()),
            attempt: self.frame(env.start)..self.frame(env.end()),
            failed_attempt,
            spike,
        };
        self.previous_end = env.end();
        self.clock = env.peak_time() + ADVANCE_AFTER_PEAK;
        let lost = self.tracking_loss(&env);
        (prompt, lost)
    }

    /// When the person starts on a prompt shown at `shown`: after their
    /// reaction delay, and after the previous attempt has ended.
    fn reaction_start(&mut self, shown: f64) -> f64 {
        (shown + self.reaction.sample(&mut self.rng).clamp(0.25, 1.5)).max(self.previous_end + 0.05)
    }

    /// With probability [`FAILED_ATTEMPT_PROBABILITY`], a too-weak first
    /// attempt at `shape` from `start`; returns its frames and when the real
    /// attempt starts (after a pause), or `None` and `start`.
    fn failed_attempt(&mut self, shape: Blendshape, start: f64) -> (Option<Range<usize>>, f64) {
        if !self.rng.random_bool(FAILED_ATTEMPT_PROBABILITY) {
            return (None, start);
        }
        let peak = self
            .rng
            .random_range(FAILED_PEAK_RANGE.0..FAILED_PEAK_RANGE.1);
        let env = Envelope::draw(&mut self.rng, start, peak);
        self.score.perform(&[(shape.index(), 1.0)], env);
        let frames = self.frame(env.start)..self.frame(env.end());
        (Some(frames), env.end() + self.rng.random_range(0.3..0.7))
    }

    /// The attempt at `shape` that counts, from `start`, with the shapes
    /// that come along.
    fn counted_attempt(&mut self, shape: Blendshape, start: f64) -> Envelope {
        let peak = self.rng.random_range(PEAK_RANGE.0..PEAK_RANGE.1);
        let env = Envelope::draw(&mut self.rng, start, peak);
        let recipe = self.recipe(shape);
        self.score.perform(&recipe, env);
        env
    }

    /// What an attempt at `shape` moves: the shape itself at full amount,
    /// the person's co-activations and, 30% of the time, one random shape at
    /// 0.03–0.1.
    fn recipe(&mut self, shape: Blendshape) -> Vec<(usize, f64)> {
        let mut recipe = vec![(shape.index(), 1.0)];
        recipe.extend(
            self.coactivation
                .iter()
                .filter(|c| c.0 == shape.index())
                .map(|c| (c.1, c.2)),
        );
        if self.rng.random_bool(0.3) {
            recipe.push((
                self.rng.random_range(0..BLENDSHAPE_COUNT),
                self.rng.random_range(0.03..0.1),
            ));
        }
        recipe.retain(|(s, a)| *s != shape.index() || *a == 1.0);
        recipe
    }

    /// With probability [`SPIKE_PROBABILITY`], a one-frame tracker spike
    /// between the prompt being shown and the attempt's `start`: its frame
    /// and reported value.
    fn spike(&mut self, shown: f64, start: f64) -> Option<(usize, f32)> {
        let window = self.frame(shown) + 3..self.frame(start).saturating_sub(3);
        (self.rng.random_bool(SPIKE_PROBABILITY) && !window.is_empty()).then(|| {
            (
                self.rng.random_range(window),
                self.rng.random_range(0.6..1.0) as f32,
            )
        })
    }

    /// With probability [`TRACKING_LOSS_PROBABILITY`], 5–20 untracked frames
    /// just after the attempt `env`; the next prompt then waits until the
    /// face has been tracked again for a while.
    fn tracking_loss(&mut self, env: &Envelope) -> Option<Range<usize>> {
        if !self.rng.random_bool(TRACKING_LOSS_PROBABILITY) {
            return None;
        }
        let from = self.frame(env.end()) + 1;
        let lost = from..from + self.rng.random_range(5..20);
        self.clock = self.clock.max((from + 25) as f64 / self.frame_rate);
        Some(lost)
    }

    /// Places the test expressions after the prompts.
    fn perform_tests(&mut self) -> Vec<TestTrack> {
        perform_tests(
            &mut self.rng,
            &mut self.clock,
            self.frame_rate,
            &mut self.score,
        )
    }
}

/// The true activations of every frame up to a second after `end` (s): the
/// neutral hold's micro-activations plus the score, clamped to `[0, 1]`.
fn true_activations(
    neutral: &NeutralHold,
    score: &Score,
    end: f64,
    frame_rate: f64,
) -> Vec<[f64; BLENDSHAPE_COUNT]> {
    let frames = frame_at(end + 1.0, frame_rate);
    let mut activations = vec![[0.0; BLENDSHAPE_COUNT]; frames];
    neutral.add_to(&mut activations, frame_rate);
    score.add_to(&mut activations, frame_rate);
    for a in activations.iter_mut() {
        a.iter_mut().for_each(|x| *x = x.clamp(0.0, 1.0));
    }
    activations
}

/// Moves each prompt's true peak to the frame of its attempt where the
/// requested activation (with everything else that moved it) is largest.
fn locate_true_peaks(prompts: &mut [PromptTrack], activations: &[[f64; BLENDSHAPE_COUNT]]) {
    for p in prompts.iter_mut() {
        let j = p.shape.index();
        p.true_peak = p
            .attempt
            .clone()
            .max_by(|x, y| activations[*x][j].total_cmp(&activations[*y][j]))
            .unwrap_or(p.true_peak);
    }
}
