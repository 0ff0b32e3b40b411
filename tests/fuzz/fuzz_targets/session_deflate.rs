//! The session file's compressed payload (inflating with a declared
//! length): the first four bytes are the declared payload length (u32 LE),
//! the rest the raw DEFLATE stream, behind a valid header and CRC-32.
#![no_main]

use libfuzzer_sys::fuzz_target;
use likeness_fuzz::{check_session_bytes, seal_compressed};

fuzz_target!(|data: &[u8]| {
    if data.len() < 4 {
        return;
    }
    let declared = u32::from_le_bytes([data[0], data[1], data[2], data[3]]);
    check_session_bytes(&seal_compressed(&data[4..], u64::from(declared)));
});
