//! The GLB container (glTF 2.0 spec, "GLB File Format Specification") and
//! where a buffer's bytes come from ("Buffers and Buffer Views": the GLB `BIN` chunk, a `data:` URI, or a file beside the
//! `.gltf`).
//!
//! A GLB is a 12-byte header (`magic` = `glTF`, `version` = 2, `length` =
//! the whole file) and chunks, each `chunkLength`, `chunkType` and data
//! padded to 4 bytes: first `JSON` (padded with spaces), then optionally
//! `BIN` (padded with zeros); chunks of other types are skipped. Every
//! length is checked against the bytes actually there before it is used.

use super::GlbError;
use super::read::MAX_GLB_BYTES;
use crate::io::read_bounded;
use std::path::{Path, PathBuf};

const MAGIC: u32 = 0x4654_6C67; // "glTF"
const CHUNK_JSON: u32 = 0x4E4F_534A; // "JSON"
const CHUNK_BIN: u32 = 0x004E_4942; // "BIN\0"

/// The JSON text of a glTF file and its GLB `BIN` chunk, if any.
pub(crate) struct Container<'a> {
    pub json: &'a [u8],
    pub bin: Option<&'a [u8]>,
}

fn u32_at(bytes: &[u8], at: usize) -> Option<u32> {
    let b = bytes.get(at..at.checked_add(4)?)?;
    Some(u32::from_le_bytes([b[0], b[1], b[2], b[3]]))
}

/// Splits a GLB, or takes a `.gltf` file's bytes as JSON.
pub(crate) fn split<'a>(bytes: &'a [u8], file: &Path) -> Result<Container<'a>, GlbError> {
    let truncated = |what: String| GlbError::Truncated {
        file: file.to_path_buf(),
        what,
    };
    let malformed = |what: String| GlbError::Container {
        file: file.to_path_buf(),
        what,
    };
    if !bytes.starts_with(b"glTF") {
        let first = bytes.iter().find(|b| !b.is_ascii_whitespace());
        // A UTF-8 byte order mark may precede the JSON.
        let json = bytes.strip_prefix(b"\xEF\xBB\xBF").unwrap_or(bytes);
        return match first {
            Some(b'{') | Some(0xEF) => Ok(Container { json, bin: None }),
            _ => Err(GlbError::NotGltf {
                file: file.to_path_buf(),
            }),
        };
    }
    let (Some(MAGIC), Some(version), Some(length)) =
        (u32_at(bytes, 0), u32_at(bytes, 4), u32_at(bytes, 8))
    else {
        return Err(truncated(format!("{} bytes, header needs 12", bytes.len())));
    };
    if version != 2 {
        return Err(malformed(format!("version {version}, only 2 is glTF 2.0")));
    }
    let length = length as usize;
    if length > bytes.len() {
        return Err(truncated(format!(
            "header says {length} bytes, file has {}",
            bytes.len()
        )));
    }
    let bytes = &bytes[..length];
    let mut at = 12;
    let mut json = None;
    let mut bin = None;
    while at < bytes.len() {
        let (Some(chunk_len), Some(kind)) = (u32_at(bytes, at), u32_at(bytes, at + 4)) else {
            return Err(truncated(format!("chunk header at byte {at}")));
        };
        let start = at + 8;
        let end = start
            .checked_add(chunk_len as usize)
            .filter(|&e| e <= bytes.len())
            .ok_or_else(|| {
                truncated(format!(
                    "chunk at byte {at} says {chunk_len} bytes, {} left",
                    bytes.len() - start.min(bytes.len())
                ))
            })?;
        let data = &bytes[start..end];
        match kind {
            CHUNK_JSON if json.is_none() && at == 12 => json = Some(data),
            CHUNK_BIN if bin.is_none() && json.is_some() => bin = Some(data),
            CHUNK_JSON | CHUNK_BIN => {
                return Err(malformed(format!("unexpected chunk at byte {at}")));
            }
            _ => {} // unknown chunk types are skipped (as the spec asks)
        }
        at = end.next_multiple_of(4);
    }
    let json = json.ok_or_else(|| malformed("no JSON chunk".to_string()))?;
    Ok(Container { json, bin })
}

/// Builds a GLB from JSON text and the binary buffer.
pub(crate) fn join(json: &[u8], bin: &[u8]) -> Vec<u8> {
    let json_len = json.len().next_multiple_of(4);
    let bin_len = bin.len().next_multiple_of(4);
    let total = 12 + 8 + json_len + if bin.is_empty() { 0 } else { 8 + bin_len };
    let mut out = Vec::with_capacity(total);
    out.extend_from_slice(&MAGIC.to_le_bytes());
    out.extend_from_slice(&2u32.to_le_bytes());
    out.extend_from_slice(&(total as u32).to_le_bytes());
    out.extend_from_slice(&(json_len as u32).to_le_bytes());
    out.extend_from_slice(&CHUNK_JSON.to_le_bytes());
    out.extend_from_slice(json);
    out.resize(20 + json_len, b' ');
    if !bin.is_empty() {
        out.extend_from_slice(&(bin_len as u32).to_le_bytes());
        out.extend_from_slice(&CHUNK_BIN.to_le_bytes());
        out.extend_from_slice(bin);
        out.resize(total, 0);
    }
    out
}

/// The bytes of every buffer of `root` (read before validation, so that
/// Draco-compressed accessors, which have no data of their own, can be
/// decoded first), in order, each at least as long as its `byteLength`; a
/// buffer `skip` marks (a fallback buffer of `EXT_meshopt_compression`,
/// `meshopt.rs`) is not loaded and left empty. A buffer without a URI is
/// the GLB's BIN chunk.
pub(crate) fn load_buffers(
    root: &gltf::json::Root,
    bin: Option<&[u8]>,
    folder: Option<&Path>,
    file: &Path,
    skip: &[bool],
) -> Result<Vec<Vec<u8>>, GlbError> {
    let mut out = Vec::new();
    for (index, buffer) in root.buffers.iter().enumerate() {
        if skip.get(index).copied().unwrap_or(false) {
            out.push(Vec::new());
            continue;
        }
        let err = |what: String| GlbError::Buffer {
            file: file.to_path_buf(),
            buffer: index,
            what,
        };
        let bytes = match buffer.uri.as_deref() {
            None => bin
                .ok_or_else(|| err("refers to the GLB BIN chunk, which is absent".into()))?
                .to_vec(),
            Some(uri) => {
                if let Some(data) = uri.strip_prefix("data:") {
                    let (_, encoded) = data
                        .split_once(";base64,")
                        .ok_or_else(|| err("a data URI that is not base64".into()))?;
                    decode_base64(encoded).ok_or_else(|| err("invalid base64".into()))?
                } else {
                    let path = external_path(uri, folder)
                        .ok_or_else(|| err(format!("cannot resolve URI {uri:?}")))?;
                    read_bounded(&path, MAX_GLB_BYTES, "a glTF buffer")
                        .map_err(|e| err(e.to_string()))?
                }
            }
        };
        let length = buffer.byte_length.0;
        if (bytes.len() as u64) < length {
            return Err(err(format!(
                "byteLength {length} but only {} bytes",
                bytes.len()
            )));
        }
        out.push(bytes);
    }
    Ok(out)
}

/// A relative URI (percent-encoded) as a path in `folder`.
fn external_path(uri: &str, folder: Option<&Path>) -> Option<PathBuf> {
    if uri.contains(':') || uri.starts_with('/') {
        return None; // another scheme, or absolute: not a file beside this one
    }
    let bytes = uri.as_bytes();
    let mut decoded = Vec::with_capacity(bytes.len());
    let mut i = 0;
    while i < bytes.len() {
        if bytes[i] == b'%' {
            let hex = std::str::from_utf8(bytes.get(i + 1..i + 3)?).ok()?;
            decoded.push(u8::from_str_radix(hex, 16).ok()?);
            i += 3;
        } else {
            decoded.push(bytes[i]);
            i += 1;
        }
    }
    Some(folder?.join(String::from_utf8(decoded).ok()?))
}

/// Standard base64 (RFC 4648 §4), padding optional.
fn decode_base64(text: &str) -> Option<Vec<u8>> {
    let text = text.trim_end_matches('=');
    let mut out = Vec::with_capacity(text.len() / 4 * 3 + 3);
    let mut acc = 0u32;
    let mut bits = 0;
    for c in text.bytes() {
        let v = match c {
            b'A'..=b'Z' => c - b'A',
            b'a'..=b'z' => c - b'a' + 26,
            b'0'..=b'9' => c - b'0' + 52,
            b'+' => 62,
            b'/' => 63,
            _ => return None,
        };
        acc = (acc << 6) | u32::from(v);
        bits += 6;
        if bits >= 8 {
            bits -= 8;
            out.push((acc >> bits) as u8);
            acc &= (1 << bits) - 1;
        }
    }
    Some(out)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn base64_decodes_with_and_without_padding() {
        assert_eq!(decode_base64("aGVsbG8=").as_deref(), Some(&b"hello"[..]));
        assert_eq!(decode_base64("aGVsbG8").as_deref(), Some(&b"hello"[..]));
        assert_eq!(
            decode_base64("AAECAw==").as_deref(),
            Some(&[0, 1, 2, 3][..])
        );
        assert!(decode_base64("a$b").is_none());
    }

    #[test]
    fn percent_encoded_uris_resolve_beside_the_file() {
        let p = external_path("my%20body.bin", Some(Path::new("/x"))).unwrap();
        assert_eq!(p, Path::new("/x/my body.bin"));
        assert!(external_path("http://a/b.bin", Some(Path::new("/x"))).is_none());
        assert!(external_path("b.bin", None).is_none());
    }

    #[test]
    fn join_then_split_gives_back_the_chunks() {
        let glb = join(b"{\"a\":1}", &[1, 2, 3, 4, 5]);
        assert_eq!(glb.len() % 4, 0);
        let c = split(&glb, Path::new("t.glb")).unwrap();
        assert_eq!(c.json, b"{\"a\":1} ");
        assert_eq!(c.bin, Some(&[1, 2, 3, 4, 5, 0, 0, 0][..]));
    }

    #[test]
    fn short_and_foreign_files_are_typed_errors() {
        let glb = join(b"{}", &[0; 16]);
        for cut in [5, 20, glb.len() - 1] {
            assert!(matches!(
                split(&glb[..cut], Path::new("t.glb")),
                Err(GlbError::Truncated { .. })
            ));
        }
        assert!(matches!(
            split(b"PK\x03\x04", Path::new("t.glb")),
            Err(GlbError::NotGltf { .. })
        ));
    }
}
