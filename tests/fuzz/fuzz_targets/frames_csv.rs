//! `frames.csv`, read by `read_frames`, seeded and steered (dictionary) toward the
//! plain dialect: `timestamp,<the 52 ARKit names>`. What is accepted is a
//! stream a session takes: finite times, never going back, at most ten
//! minutes, finite weights.
#![no_main]

use libfuzzer_sys::fuzz_target;
use likeness_fuzz::check_frames_csv;

fuzz_target!(|data: &[u8]| {
    check_frames_csv(data);
});
