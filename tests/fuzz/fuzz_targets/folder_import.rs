//! Whole-folder import (`import_folder`): the input is a folder packed as
//! text (`likeness_fuzz::folder`: files, directories and links by name),
//! unpacked into a scratch folder each run. An imported session can be
//! written as a session file and read back.
#![no_main]

use libfuzzer_sys::fuzz_target;
use likeness::session::interchange::import_folder;
use likeness_fuzz::{check_message, check_writable, folder, scratch};

fuzz_target!(|data: &[u8]| {
    let dir = scratch().join("folder");
    folder::write(&dir, &folder::unpack(data));
    match import_folder(&dir) {
        Ok((session, warnings)) => {
            check_writable(&session);
            assert!(warnings.len() <= 3 * folder::MAX_ENTRIES + 52, "warnings");
        }
        Err(e) => {
            check_message(&e);
        }
    }
});
