//! One attempt at an expression over time, and the score a session's true
//! activations are summed from.
//!
//! An [`Envelope`] rises smoothly to a peak, settles to a slightly lower hold
//! with tremor (the common pattern of voluntary force production: an initial
//! peak, then a sustained level) and falls back to zero. A [`Score`] lists
//! every shape each attempt drives, and by how much: the prompts and the
//! test expressions are both written into one, and summed frame by frame
//! into the session's true activations.

use crate::regions::smoothstep;
use crate::timeline::frame_at;
use likeness::BLENDSHAPE_COUNT;
use rand::Rng;
use rand_chacha::ChaCha8Rng;

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
    /// Draws an attempt starting at `start` and peaking at `peak`: rise and
    /// fall 0.25–0.5 s, a hold at 80–92% of the peak for 0.4–0.9 s after
    /// settling with a time constant of 0.08–0.15 s, tremor at 8–12 Hz.
    pub fn draw(rng: &mut ChaCha8Rng, start: f64, peak: f64) -> Envelope {
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

/// One shape driven by one attempt: `amount` times the envelope.
#[derive(Clone, Copy, Debug)]
pub struct Contribution {
    /// Index of the shape (Apple's order).
    pub shape: usize,
    /// The attempt.
    pub envelope: Envelope,
    /// How much of the envelope the shape follows.
    pub amount: f64,
}

/// Every contribution of a session's performance, in the order performed.
#[derive(Clone, Debug, Default)]
pub struct Score {
    /// The contributions.
    pub contributions: Vec<Contribution>,
}

impl Score {
    /// Performs `recipe`, a list of `(shape, amount)`, with one envelope.
    pub fn perform(&mut self, recipe: &[(usize, f64)], envelope: Envelope) {
        for &(shape, amount) in recipe {
            self.contributions.push(Contribution {
                shape,
                envelope,
                amount,
            });
        }
    }

    /// Adds every contribution, in order, to the activations of the frames
    /// it spans (frame `f` is at time `f / frame_rate`).
    pub fn add_to(&self, activations: &mut [[f64; BLENDSHAPE_COUNT]], frame_rate: f64) {
        let frames = activations.len();
        for c in &self.contributions {
            let env = &c.envelope;
            let from = frame_at(env.start, frame_rate);
            let to = (frame_at(env.end(), frame_rate) + 1).min(frames);
            for (f, a) in activations.iter_mut().enumerate().take(to).skip(from) {
                a[c.shape] += c.amount * env.at(f as f64 / frame_rate);
            }
        }
    }
}
