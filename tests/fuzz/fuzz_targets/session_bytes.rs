//! The session file from raw bytes: `file::decode`, and `file::read` on the
//! same bytes written to a file, which must agree; a session that decodes
//! encodes and decodes to itself.
#![no_main]

use libfuzzer_sys::fuzz_target;
use likeness::session::file;
use likeness_fuzz::{check_message, check_session_bytes, scratch_file};

fuzz_target!(|data: &[u8]| {
    check_session_bytes(data);
    let path = scratch_file("session.likeness", data);
    match (file::read(&path), file::decode(data)) {
        (Ok(read), Ok(decoded)) => assert!(read == decoded, "read and decode differ"),
        (Err(e), Err(_)) => {
            check_message(&e);
        }
        (read, decoded) => panic!(
            "read and decode disagree: read {:?}, decode {:?}",
            read.err(),
            decoded.err()
        ),
    }
});
