//! The most a session file may hold, each limit with its reason, checked
//! from the header and the counts in the payload before anything is
//! allocated for what they declare.
//!
//! A two-minute capture is about 7,200 frames of ARKit's 1,220-vertex face
//! mesh at 60 fps: a 27.6–32.8 MB payload (measured, see the [module
//! docs](super)) that decodes to about 110 MB of meshes. The limits allow
//! ten minutes, five times that, and nothing larger: reading any file the
//! limits admit needs at most the compressed payload, the payload
//! ([`MAX_PAYLOAD_BYTES`]) and the decoded meshes ([`MAX_DECODED_VERTICES`]
//! × 12 bytes) at once, under 1.1 GB.

use std::fmt;

/// Longest session, from first to last frame, in seconds: ten minutes,
/// five times a two-minute capture.
pub const MAX_DURATION_SECONDS: f64 = 600.0;

/// Most frames: ten minutes at ARKit's 60 fps face tracking.
pub const MAX_FRAMES: usize = 36_000;

/// Most vertices in a session's meshes: 13 times ARKit's 1,220, room for a
/// denser face mesh.
pub const MAX_VERTICES: usize = 16_384;

/// Most vertices of every mesh of a session together (the stream's, the
/// template's, the neutral scan, the captures', the tests' and the ground
/// truth's): ten minutes of 1,220-vertex frames plus a thousand meshes more,
/// 542 MB of decoded positions. This is what bounds a decompression bomb
/// whose payload stays under [`MAX_PAYLOAD_BYTES`].
pub const MAX_DECODED_VERTICES: usize = (MAX_FRAMES + 1_000) * 1_220;

/// Largest uncompressed payload (256 MiB): ten minutes of the measured
/// 32.8 MB per 8,461 frames is 140 MB.
pub const MAX_PAYLOAD_BYTES: usize = 1 << 28;

/// Largest compressed payload: an incompressible payload stored raw, plus
/// DEFLATE's 5 bytes per stored block of up to 64 KiB (rounded up to one
/// 8192th) and 1 KiB. Real payloads compress about 4:1.
pub const MAX_COMPRESSED_BYTES: usize = MAX_PAYLOAD_BYTES + MAX_PAYLOAD_BYTES / 8192 + 1024;

/// One of the limits above, as an error names it.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Limit {
    /// [`MAX_DURATION_SECONDS`].
    Duration,
    /// [`MAX_FRAMES`].
    Frames,
    /// [`MAX_VERTICES`].
    Vertices,
    /// [`MAX_DECODED_VERTICES`].
    DecodedVertices,
    /// [`MAX_PAYLOAD_BYTES`].
    PayloadBytes,
    /// [`MAX_COMPRESSED_BYTES`].
    CompressedBytes,
}

impl Limit {
    /// The largest value allowed.
    pub fn max(self) -> u64 {
        match self {
            Limit::Duration => MAX_DURATION_SECONDS as u64,
            Limit::Frames => MAX_FRAMES as u64,
            Limit::Vertices => MAX_VERTICES as u64,
            Limit::DecodedVertices => MAX_DECODED_VERTICES as u64,
            Limit::PayloadBytes => MAX_PAYLOAD_BYTES as u64,
            Limit::CompressedBytes => MAX_COMPRESSED_BYTES as u64,
        }
    }

    /// The unit of the value and the limit.
    pub fn unit(self) -> &'static str {
        match self {
            Limit::Duration => "s",
            Limit::Frames => "frames",
            Limit::Vertices | Limit::DecodedVertices => "vertices",
            Limit::PayloadBytes | Limit::CompressedBytes => "bytes",
        }
    }

    /// The constant's name and the reason for its value.
    fn describe(self) -> (&'static str, &'static str) {
        match self {
            Limit::Duration => ("MAX_DURATION_SECONDS", "ten minutes"),
            Limit::Frames => ("MAX_FRAMES", "ten minutes at 60 fps"),
            Limit::Vertices => ("MAX_VERTICES", "13 times ARKit's face mesh"),
            Limit::DecodedVertices => (
                "MAX_DECODED_VERTICES",
                "ten minutes of ARKit face meshes, 542 MB",
            ),
            Limit::PayloadBytes => ("MAX_PAYLOAD_BYTES", "256 MiB"),
            Limit::CompressedBytes => ("MAX_COMPRESSED_BYTES", "the payload limit, stored raw"),
        }
    }
}

impl fmt::Display for Limit {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let (name, reason) = self.describe();
        write!(f, "{name} = {} {} ({reason})", self.max(), self.unit())
    }
}

/// The sizes of a session that the limits bound.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(super) struct Extent {
    /// Vertices per mesh.
    pub vertices: usize,
    /// Frames in the stream.
    pub frames: usize,
    /// Meshes in the whole session.
    pub meshes: usize,
}

/// `Err((limit, value))` for the first limit `extent` passes.
pub(super) fn check_extent(extent: Extent) -> Result<(), (Limit, u64)> {
    if extent.vertices > MAX_VERTICES {
        return Err((Limit::Vertices, extent.vertices as u64));
    }
    if extent.frames > MAX_FRAMES {
        return Err((Limit::Frames, extent.frames as u64));
    }
    let decoded = extent.vertices.saturating_mul(extent.meshes);
    if decoded > MAX_DECODED_VERTICES {
        return Err((Limit::DecodedVertices, decoded as u64));
    }
    Ok(())
}

/// `Err((limit, whole seconds))` if the stream spans more than
/// [`MAX_DURATION_SECONDS`] (a span that is not a number is left to the
/// session's own checks).
pub(super) fn check_duration(first: f64, last: f64) -> Result<(), (Limit, u64)> {
    let span = last - first;
    if span > MAX_DURATION_SECONDS {
        return Err((Limit::Duration, span.ceil().min(u64::MAX as f64) as u64));
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn limits_name_themselves_with_their_reason() {
        assert_eq!(
            Limit::Frames.to_string(),
            "MAX_FRAMES = 36000 frames (ten minutes at 60 fps)"
        );
        let two_minutes = Extent {
            vertices: 1_220,
            frames: 7_200,
            meshes: 7_200 + 53 + 1 + 52 + 10,
        };
        assert_eq!(check_extent(two_minutes), Ok(()));
        let dense = Extent {
            vertices: MAX_VERTICES,
            frames: 4_000,
            meshes: 4_000,
        };
        assert_eq!(
            check_extent(dense),
            Err((Limit::DecodedVertices, 4_000 * MAX_VERTICES as u64))
        );
        let long = Extent {
            frames: MAX_FRAMES + 1,
            ..two_minutes
        };
        assert_eq!(check_extent(long).unwrap_err().0, Limit::Frames);
        assert_eq!(check_duration(1.0, 601.0), Ok(()));
        assert_eq!(check_duration(1.0, 601.5), Err((Limit::Duration, 601)));
        assert_eq!(check_duration(0.0, f64::NAN), Ok(()));
    }
}
