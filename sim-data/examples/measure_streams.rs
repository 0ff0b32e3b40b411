//! The statistics of `likeness_sim::stream_statistics` on real Live Link Face
//! takes and on simulated streams, side by side:
//! `cargo run --release -p likeness-sim --example measure_streams -- TAKE.csv… [--sim SEED…]`.
//! Each stream gets one line per statistic; the rest levels and zero shares
//! are printed for the channels that are not at zero.

use likeness::session::interchange::read_frames;
use likeness_sim::capture_session::{SimulationOptions, simulate_session_with};
use likeness_sim::stream_statistics::{StreamStatistics, stream_statistics};
use std::path::Path;

fn print(name: &str, s: &StreamStatistics) {
    println!(
        "{name}: {} frames, {} moving channels",
        s.frames,
        s.moving.len()
    );
    println!("  jitter {:.3e}", s.jitter);
    println!(
        "  lag-1 autocorrelation of Δw {:.3}",
        s.lag1_autocorrelation
    );
    println!(
        "  band shares of Δw: <2 Hz {:.3}, 2-6 {:.3}, 6-15 {:.3}, >15 {:.3}",
        s.band_shares[0], s.band_shares[1], s.band_shares[2], s.band_shares[3]
    );
    println!(
        "  frames: median interval {:.5} s, {} long, {} short",
        s.median_interval, s.long_intervals, s.short_intervals
    );
    println!("  quantum {:.3e}", s.quantum);
    println!("  mirror correlation of Δw {:.3}", s.mirror_correlation);
    println!(
        "  rest: {} quiet windows, noise {:.2e}, jitter {:.2e}, lag-1 autocorrelation {:.3}",
        s.quiet_windows, s.rest_noise, s.rest_jitter, s.rest_lag1_autocorrelation
    );
    println!(
        "  fastest blink rise 10-90%: {:?} frames",
        s.fastest_blink_rise
    );
    let at_zero = s.rest_levels.iter().filter(|r| **r == 0.0).count();
    let mut zero_shares = s.zero_shares.to_vec();
    zero_shares.sort_by(f64::total_cmp);
    println!(
        "  channels resting at 0: {at_zero} of 52; median zero share {:.2}",
        zero_shares[26]
    );
    let rest: Vec<String> = likeness::Blendshape::ALL
        .iter()
        .filter(|b| s.rest_levels[b.index()] > 0.0 || s.zero_shares[b.index()] < 0.5)
        .map(|b| {
            format!(
                "{}={:.3}/{:.2}",
                b.name(),
                s.rest_levels[b.index()],
                s.zero_shares[b.index()]
            )
        })
        .collect();
    println!("  rest level / zero share: {}", rest.join(" "));
}

fn main() {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let split = args.iter().position(|a| a == "--sim").unwrap_or(args.len());
    for path in &args[..split] {
        let frames = read_frames(Path::new(path)).expect("a readable take");
        print(path, &stream_statistics(&frames));
    }
    for seed in args.iter().skip(split + 1) {
        let seed: u64 = seed.parse().expect("a seed number");
        let options = SimulationOptions {
            geometry_window: Some(0.0),
            ..SimulationOptions::default()
        };
        let session = simulate_session_with(seed, options, &mut |_, _| {});
        print(
            &format!("simulated subject {seed}"),
            &stream_statistics(&session.frames),
        );
    }
}
