//! The registration cache: finding the face is done once per avatar
//! topology and kept in a file named after [`super::find_face::cache_key`]
//! (`face-v<rules>-<vertices>-<crc>.bin`), so the avatar command and the app skip it
//! the next time. The file is a magic, a format version and the
//! [`FaceRegistration`] as bincode; anything unreadable is treated as a
//! miss (the registration is then redone and the file rewritten).

use super::face_registration::{FaceRegistration, FoundFace};
use crate::avatar::model::Avatar;
use crate::io::atomic_write::write_atomically;
use std::path::{Path, PathBuf};

/// First bytes of a cache file.
pub const MAGIC: &[u8; 8] = b"LKFACE02";

/// Largest cache file read (bytes): far above a 100k-vertex avatar's map.
pub const MAX_BYTES: u64 = 256 << 20;

/// The cache file for `key` in `dir`.
pub fn cache_path(dir: &Path, key: &str) -> PathBuf {
    dir.join(format!("face-{key}.bin"))
}

fn config() -> bincode::config::Configuration<
    bincode::config::LittleEndian,
    bincode::config::Varint,
    bincode::config::Limit<{ MAX_BYTES as usize }>,
> {
    bincode::config::standard().with_limit()
}

/// The cached registration for `key` in `dir`, if a readable one is there
/// and it fits `avatar` and a mask of `mask_vertices` vertices
/// ([`FaceRegistration::new`]).
pub fn load(
    dir: &Path,
    key: &str,
    avatar: &Avatar,
    mask_vertices: usize,
) -> Option<FaceRegistration> {
    let path = cache_path(dir, key);
    let len = std::fs::metadata(&path).ok()?.len();
    if len > MAX_BYTES {
        return None;
    }
    let bytes = std::fs::read(&path).ok()?;
    let payload = bytes.strip_prefix(MAGIC.as_slice())?;
    let (found, used): (FoundFace, usize) =
        bincode::serde::decode_from_slice(payload, config()).ok()?;
    if used != payload.len() {
        return None;
    }
    FaceRegistration::new(found, avatar, mask_vertices).ok()
}

/// Stores `registration` for `key` in `dir` (created if missing), written
/// atomically.
pub fn store(dir: &Path, key: &str, registration: &FaceRegistration) -> std::io::Result<PathBuf> {
    std::fs::create_dir_all(dir)?;
    let mut bytes = MAGIC.to_vec();
    bytes.extend(
        bincode::serde::encode_to_vec(registration, config())
            .map_err(|e| std::io::Error::other(e.to_string()))?,
    );
    let path = cache_path(dir, key);
    write_atomically(&path, &bytes)?;
    Ok(path)
}
