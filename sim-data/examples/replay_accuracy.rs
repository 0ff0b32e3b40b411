//! How close the guided capture comes to the true peaks on simulated
//! subjects that are *not* committed (so not the ones the tests guard):
//! `cargo run --release -p likeness-sim --example replay_accuracy -- FIRST LAST`
//! simulates seeds FIRST..=LAST (default 5..=24), replays each session
//! through the state machine with default parameters, and prints the
//! histogram of capture − true peak (frames) for prompts and for tests, the
//! steps skipped and the quality flags raised.

use likeness::capture::guided_capture::{GuidedCaptureConfig, Step};
use likeness::capture::replay::replay_session;
use likeness_sim::capture_session::{SimulationOptions, simulate_session_with};
use std::collections::BTreeMap;

fn main() {
    let arg = |i: usize, default: u64| {
        std::env::args()
            .nth(i)
            .map(|a| a.parse().expect("a seed number"))
            .unwrap_or(default)
    };
    let (first, last) = (arg(1, 5), arg(2, 24));
    let mut prompts: BTreeMap<i64, usize> = BTreeMap::new();
    let mut tests: BTreeMap<i64, usize> = BTreeMap::new();
    let (mut steps, mut captured) = (0, 0);
    for seed in first..=last {
        // Meshes are not needed to find the peaks; skip storing them.
        let options = SimulationOptions {
            geometry_window: Some(0.0),
            ..SimulationOptions::default()
        };
        let session = simulate_session_with(seed, options, &mut |_, _| {});
        let report = replay_session(session, GuidedCaptureConfig::default()).expect("replays");
        steps += report.steps.len();
        captured += report.captured();
        for s in &report.steps {
            if s.frame.is_none() {
                println!("seed {seed}: {} skipped", s.name);
            }
            if !s.quality.is_clean() {
                println!("seed {seed}: {} flagged {:?}", s.name, s.quality);
            }
            let histogram = match s.step {
                Step::Expression(_) => &mut prompts,
                Step::Test(_) => &mut tests,
                Step::Neutral => continue,
            };
            if let Some(e) = s.frame_error() {
                *histogram.entry(e).or_default() += 1;
            }
        }
    }
    let describe = |h: &BTreeMap<i64, usize>| {
        let n: usize = h.values().sum();
        let within: usize = h.iter().filter(|(e, _)| e.abs() <= 2).map(|(_, c)| c).sum();
        let mean = h.iter().map(|(e, c)| *e as f64 * *c as f64).sum::<f64>() / n.max(1) as f64;
        format!("{n} captures, {within} within ±2 frames, mean {mean:+.2}, histogram {h:?}")
    };
    println!("seeds {first}..={last}: {captured} of {steps} steps captured");
    println!("prompts: {}", describe(&prompts));
    println!("tests:   {}", describe(&tests));
}
