//! GLB (and `.gltf` with `data:` buffers) import: `read_avatar_bytes`, then
//! `check_avatar`; an avatar that reads is written back (unchanged targets)
//! and as a new GLB, and both read again.
#![no_main]

use libfuzzer_sys::fuzz_target;
use likeness::avatar::glb::{
    NewGlbOptions, NewShapes, TargetEncoding, check_avatar, new_avatar_glb, read_avatar_bytes,
    written_back_glb,
};
use likeness_fuzz::check_message;
use std::path::Path;

fuzz_target!(|data: &[u8]| {
    let avatar = match read_avatar_bytes(data, "fuzz.glb") {
        Ok(avatar) => avatar,
        Err(e) => {
            check_message(&e);
            return;
        }
    };
    if let Err(e) = check_avatar(&avatar) {
        check_message(&e);
    }
    let file = Path::new("out.glb");
    match written_back_glb(&avatar, &NewShapes::new(), TargetEncoding::Smallest, file) {
        Ok(bytes) => {
            read_avatar_bytes(&bytes, "written-back.glb").expect("a written-back GLB reads");
        }
        Err(e) => {
            check_message(&e);
        }
    }
    match new_avatar_glb(&avatar.avatar, &NewGlbOptions::default(), file) {
        Ok(bytes) => {
            read_avatar_bytes(&bytes, "new.glb").expect("a new GLB reads");
        }
        Err(e) => {
            check_message(&e);
        }
    }
});
