//! The weight-table CSV reader (`expressions/weights.csv`,
//! `test/weights.csv`): `read_weight_table` on the bytes as a file and
//! `parse_weight_table` on them as text; the two agree, and every weight
//! accepted is finite.
#![no_main]

use libfuzzer_sys::fuzz_target;
use likeness::session::interchange::weights_csv::{parse_weight_table, read_weight_table};
use likeness_fuzz::{check_message, scratch_file};

/// Every key column a table may have.
const KEYS: [&str; 4] = ["prompt", "id", "timestamp", "timecode"];

fuzz_target!(|data: &[u8]| {
    let path = scratch_file("weights.csv", data);
    let from_file = read_weight_table(&path, &KEYS);
    if let Err(e) = &from_file {
        check_message(e);
    }
    if let Ok(text) = std::str::from_utf8(data) {
        match (&from_file, parse_weight_table(&path, text, &KEYS)) {
            (Ok(a), Ok(b)) => assert!(*a == b, "read and parse differ"),
            (Err(_), Err(e)) => {
                check_message(&e);
            }
            _ => panic!("read_weight_table and parse_weight_table disagree"),
        }
    }
    if let Ok(table) = from_file {
        for row in &table.rows {
            assert!(
                row.weights.0.iter().all(|w| w.is_finite()),
                "line {}",
                row.line
            );
        }
    }
});
