//! The committed sample sessions are exactly what the simulator makes from
//! their seeds, and they fit the repository's budget.

use likeness::session::file as session_file;
use likeness_sim::{SAMPLE_GEOMETRY_WINDOW, SimulationOptions};
use likeness_tests::committed::{SEEDS, path};

#[test]
fn each_committed_session_regenerates_identically_from_its_seed() {
    for seed in SEEDS {
        let committed = std::fs::read(path(seed)).expect("committed session exists");
        let options = SimulationOptions {
            geometry_window: Some(SAMPLE_GEOMETRY_WINDOW),
            ..SimulationOptions::default()
        };
        let session = likeness_sim::simulate_session_with(seed, options, &mut |_, _| {});
        let regenerated = session_file::encode(&session).expect("encodes");
        assert!(
            committed == regenerated,
            "subject-{seed}.likeness differs from a fresh simulation of seed {seed}; \
             if the simulator changed on purpose, bump SIMULATOR_VERSION and regenerate"
        );
    }
}

#[test]
fn committed_sessions_stay_within_twenty_megabytes() {
    let total: u64 = SEEDS
        .iter()
        .map(|s| std::fs::metadata(path(*s)).expect("exists").len())
        .sum();
    assert!(total <= 20_000_000, "committed sessions take {total} bytes");
}

#[test]
fn committed_sessions_decode_to_complete_captures() {
    for seed in SEEDS {
        let s = likeness_tests::committed::read(seed).expect("decodes");
        assert_eq!(s.captures.len(), 52, "seed {seed}");
        assert!(s.truth.as_ref().is_some_and(|t| t.seed == seed));
        // Geometry is kept around every capture, as the app's ring buffer would.
        for c in &s.captures {
            let f = c.frame.expect("simulated captures name their frame") as usize;
            assert!(
                s.frames[f].vertices.is_some(),
                "seed {seed}: no mesh at capture of {}",
                c.prompt
            );
            assert!(s.frames[f.saturating_sub(20)].vertices.is_some());
        }
    }
}
