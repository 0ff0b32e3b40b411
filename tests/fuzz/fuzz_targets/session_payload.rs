//! The session file's payload (bincode fields, the geometry blobs, the
//! session's checks): the fuzzer's bytes are the uncompressed payload,
//! compressed as the writer does and put behind a valid header with the
//! right lengths and CRC-32, so nothing stops them before decoding.
#![no_main]

use libfuzzer_sys::fuzz_target;
use likeness_fuzz::{check_session_bytes, seal_payload};

fuzz_target!(|data: &[u8]| {
    check_session_bytes(&seal_payload(data));
});
