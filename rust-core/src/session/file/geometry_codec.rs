//! Quantization and residual coding of positions and weights.
//!
//! Every position and weight is stored as an integer number of
//! [`QUANTUM`]s (10 µm, or 1e-5 of a weight): `q = round(x · 1e5)`. Decoding
//! gives `(q as f64 · 1e-5) as f32`, so the stored value is within ±5 µm of
//! the original (plus f32 rounding of the decoded value, at most 0.06 µm for
//! |x| < 1 m), and quantizing a decoded value gives back the same `q`
//! ([`quantize`]`(`[`dequantize`]`(q)) == q` for every `|q| ≤` [`MAX_Q`]):
//! re-encoding a decoded session reproduces the same bytes.
//!
//! Integers are written as residuals from a prediction, zigzag-mapped and
//! written as LEB128 varints, so small residuals take one byte and the
//! compressor behind this sees long runs of a few symbols. Single meshes
//! ([`encode_mesh`]) are residuals against a reference mesh, optionally
//! differenced once more along a breadth-first [`Traversal`] of the mesh
//! (each vertex against its neighbours, `traversal.rs`); time series are in
//! `series.rs`.
//! Meshes are laid out planar: all x, then all y, then all z.
//!
//! Indexing: a planar mesh of `n` vertices has `3n` values, and the coders
//! index it with `c · n + i` (`c < 3`, `i < n`) or with value indices from
//! a [`Traversal`] of its topology; a reference mesh has the same length (it
//! is decoded with the same traversal). Bytes from the file are only read
//! through [`Reader`], which checks every position.

use super::error::SessionFileError;
use super::traversal::Traversal;
use crate::arkit::{Blendshape, Weights};
use glam::Vec3;

/// One stored unit: 10 µm for positions in metres, 1e-5 for weights.
pub const QUANTUM: f64 = 1e-5;

/// Largest stored magnitude in quanta (100 m, or a weight of 100). Up to
/// there an f32 holds `q · 1e-5` to better than half a quantum, which is what
/// makes decode → encode reproduce the same integers.
pub const MAX_Q: i32 = 10_000_000;

/// `round(x · 1e5)`, or `None` if `x` is not finite or beyond ±[`MAX_Q`].
pub fn quantize(x: f32) -> Option<i32> {
    let q = (x as f64 * 1e5).round();
    // NaN fails the comparison, so it is rejected too.
    (q.abs() <= MAX_Q as f64).then_some(q as i32)
}

/// The value a stored integer stands for: `(q as f64 · 1e-5) as f32`.
pub fn dequantize(q: i32) -> f32 {
    (q as f64 * QUANTUM) as f32
}

fn out_of_range(field: String, value: f32) -> SessionFileError {
    SessionFileError::OutOfRange {
        field,
        value: value as f64,
        limit: MAX_Q as f64 * QUANTUM,
    }
}

/// Quantizes a mesh into planar order (all x, all y, all z).
pub fn quantize_mesh(field: &str, mesh: &[Vec3]) -> Result<Vec<i32>, SessionFileError> {
    let n = mesh.len();
    let mut q = vec![0; 3 * n];
    for (i, p) in mesh.iter().enumerate() {
        for (c, x) in p.to_array().into_iter().enumerate() {
            q[c * n + i] = quantize(x).ok_or_else(|| out_of_range(format!("{field}[{i}]"), x))?;
        }
    }
    Ok(q)
}

/// Inverse of [`quantize_mesh`]; `q.len()` is a multiple of 3.
pub fn dequantize_mesh(q: &[i32]) -> Vec<Vec3> {
    let n = q.len() / 3;
    (0..n)
        .map(|i| {
            Vec3::new(
                dequantize(q[i]),
                dequantize(q[n + i]),
                dequantize(q[2 * n + i]),
            )
        })
        .collect()
}

/// Quantizes the 52 weights.
pub fn quantize_weights(field: &str, w: &Weights) -> Result<Vec<i32>, SessionFileError> {
    w.iter()
        .map(|(shape, x)| quantize(x).ok_or_else(|| out_of_range(format!("{field}[{shape}]"), x)))
        .collect()
}

/// Inverse of [`quantize_weights`]; `q` has
/// [`BLENDSHAPE_COUNT`](crate::BLENDSHAPE_COUNT) values.
pub fn dequantize_weights(q: &[i32]) -> Weights {
    let mut w = Weights::ZERO;
    for (shape, &v) in Blendshape::ALL.iter().zip(q) {
        w.set(*shape, dequantize(v));
    }
    w
}

/// Appends `v` zigzag-mapped as an LEB128 varint (1 to 10 bytes).
pub fn put_varint(out: &mut Vec<u8>, v: i64) {
    let mut u = ((v << 1) ^ (v >> 63)) as u64;
    while u >= 0x80 {
        out.push(u as u8 | 0x80);
        u >>= 7;
    }
    out.push(u as u8);
}

/// Cost estimate of a residual: bits of its zigzag value.
pub(super) fn cost(v: i64) -> u64 {
    (64 - (((v << 1) ^ (v >> 63)) as u64).leading_zeros()) as u64
}

/// A cursor over a blob of varints that never reads out of bounds.
#[derive(Clone, Debug)]
pub struct Reader<'a> {
    bytes: &'a [u8],
    pos: usize,
}

impl<'a> Reader<'a> {
    /// Reads `bytes` from the start.
    pub fn new(bytes: &'a [u8]) -> Self {
        Reader { bytes, pos: 0 }
    }

    /// Bytes not yet read.
    pub fn remaining(&self) -> usize {
        self.bytes.len() - self.pos
    }

    /// The next byte.
    pub fn byte(&mut self) -> Result<u8, &'static str> {
        let b = *self.bytes.get(self.pos).ok_or("ends early")?;
        self.pos += 1;
        Ok(b)
    }

    /// The next zigzag LEB128 varint; rejects overlong and non-minimal forms.
    #[inline]
    pub fn varint(&mut self) -> Result<i64, &'static str> {
        let mut u = 0u64;
        let mut shift = 0;
        loop {
            let b = self.byte()?;
            if shift == 63 && b > 1 {
                return Err("varint overflows 64 bits");
            }
            u |= ((b & 0x7f) as u64) << shift;
            if b & 0x80 == 0 {
                if b == 0 && shift > 0 {
                    return Err("varint is not in minimal form");
                }
                return Ok((u >> 1) as i64 ^ -((u & 1) as i64));
            }
            shift += 7;
        }
    }

    /// An error unless every byte was read.
    pub fn finish(&self) -> Result<(), String> {
        match self.remaining() {
            0 => Ok(()),
            n => Err(format!("{n} unexpected bytes after the data")),
        }
    }
}

/// `pred + residual`, if it is within ±[`MAX_Q`].
#[inline]
pub(super) fn reconstruct(pred: i64, residual: i64) -> Result<i32, &'static str> {
    match pred.checked_add(residual) {
        Some(q) if q.abs() <= MAX_Q as i64 => Ok(q as i32),
        _ => Err("value outside the storable range"),
    }
}

/// Codes a weight vector (or any short vector) as plain varints.
pub fn encode_values(q: &[i32]) -> Vec<u8> {
    let mut out = Vec::with_capacity(q.len());
    for &v in q {
        put_varint(&mut out, v as i64);
    }
    out
}

/// Decodes a blob written by [`encode_values`] holding exactly `n` values.
pub fn decode_values(field: &str, blob: &[u8], n: usize) -> Result<Vec<i32>, SessionFileError> {
    let corrupt = |reason: String| SessionFileError::corrupt(field, reason);
    if blob.len() < n {
        return Err(corrupt(format!(
            "{} bytes cannot hold {n} values",
            blob.len()
        )));
    }
    let mut reader = Reader::new(blob);
    let mut q = Vec::with_capacity(n);
    for j in 0..n {
        let v = reader
            .varint()
            .and_then(|r| reconstruct(0, r))
            .map_err(|e| corrupt(format!("value {j}: {e}")))?;
        q.push(v);
    }
    reader.finish().map_err(corrupt)?;
    Ok(q)
}

/// Codes one mesh (planar, `q.len() == traversal.len()`): the differences
/// `d = q − reference` (the reference is zero for an absolute mesh), after a
/// flag byte: `0` = `d` as it is, `1` = `d` minus its [`Traversal`]
/// prediction from neighbouring vertices, whichever is smaller.
pub fn encode_mesh(q: &[i32], reference: Option<&[i32]>, traversal: &Traversal) -> Vec<u8> {
    let d: Vec<i64> = match reference {
        Some(r) => q
            .iter()
            .zip(r)
            .map(|(a, b)| *a as i64 - *b as i64)
            .collect(),
        None => q.iter().map(|a| *a as i64).collect(),
    };
    let spatial = |j: usize| d[j] - traversal.predict(j, &d);
    let plain_cost: u64 = d.iter().map(|v| cost(*v)).sum();
    let spatial_cost: u64 = (0..d.len()).map(|j| cost(spatial(j))).sum();
    let use_spatial = spatial_cost < plain_cost;
    let mut out = Vec::with_capacity(1 + d.len());
    out.push(use_spatial as u8);
    for &j in traversal.order() {
        let j = j as usize;
        put_varint(&mut out, if use_spatial { spatial(j) } else { d[j] });
    }
    out
}

/// Decodes a blob written by [`encode_mesh`]. The blob must hold at least a
/// byte per value before anything is allocated.
pub fn decode_mesh(
    field: &str,
    blob: &[u8],
    reference: Option<&[i32]>,
    traversal: &Traversal,
) -> Result<Vec<i32>, SessionFileError> {
    let corrupt = |reason: String| SessionFileError::corrupt(field, reason);
    let n = traversal.len();
    if blob.len() < n + 1 {
        return Err(corrupt(format!(
            "{} bytes cannot hold {n} values",
            blob.len()
        )));
    }
    let mut reader = Reader::new(blob);
    let use_spatial = match reader.byte() {
        Ok(0) => false,
        Ok(1) => true,
        Ok(b) => return Err(corrupt(format!("unknown mesh coding {b}"))),
        Err(e) => return Err(corrupt(e.to_string())),
    };
    let mut d = vec![0i64; n];
    let mut q = vec![0i32; n];
    for &j in traversal.order() {
        let j = j as usize;
        let value = |e: &str| corrupt(format!("{}: {e}", describe(j, n)));
        let mut dj = reader.varint().map_err(value)?;
        if use_spatial {
            dj = dj
                .checked_add(traversal.predict(j, &d))
                .ok_or_else(|| value("overflow"))?;
        }
        let base = reference.map_or(0, |r| r[j] as i64);
        q[j] = reconstruct(base, dj).map_err(value)?;
        d[j] = dj;
    }
    reader.finish().map_err(corrupt)?;
    Ok(q)
}

/// Names planar value `j` of an `n`-value mesh: `vertex 12 y`.
fn describe(j: usize, n: usize) -> String {
    let v = (n / 3).max(1);
    format!("vertex {} {}", j % v, ["x", "y", "z"][(j / v).min(2)])
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::session::file::traversal::tests::strip;

    #[test]
    fn quantization_round_trips_every_integer() {
        // Exhaustive over the whole storable range: decode then encode gives
        // the same integer, which makes re-encoding byte-identical.
        for q in -MAX_Q..=MAX_Q {
            assert_eq!(quantize(dequantize(q)), Some(q), "{q}");
        }
    }

    #[test]
    fn quantization_keeps_five_micrometres() {
        for &x in &[
            0.0f32,
            1e-6,
            4.9e-6,
            5.1e-6,
            0.123_456_7,
            -0.087_654_3,
            0.999_999,
            -1.5,
        ] {
            let y = dequantize(quantize(x).unwrap());
            assert!((y as f64 - x as f64).abs() <= 5e-6 + 1e-7, "{x} -> {y}");
        }
        assert_eq!(quantize(f32::NAN), None);
        assert_eq!(quantize(f32::INFINITY), None);
        assert_eq!(quantize(100.0), Some(MAX_Q));
        assert_eq!(quantize(100.001), None);
    }

    #[test]
    fn varints_round_trip_and_reject_malformed_input() {
        let values = [
            0i64,
            1,
            -1,
            63,
            -64,
            64,
            1 << 20,
            -(1 << 40),
            i64::MAX,
            i64::MIN,
        ];
        let mut out = Vec::new();
        for v in values {
            put_varint(&mut out, v);
        }
        assert_eq!(out[..3], [0, 2, 1]);
        let mut r = Reader::new(&out);
        for v in values {
            assert_eq!(r.varint(), Ok(v));
        }
        assert!(r.finish().is_ok());
        assert_eq!(Reader::new(&[0x80]).varint(), Err("ends early"));
        assert_eq!(
            Reader::new(&[0x80, 0x00]).varint(),
            Err("varint is not in minimal form")
        );
        let mut too_long = [0xffu8; 10];
        too_long[9] = 0x02;
        assert_eq!(
            Reader::new(&too_long).varint(),
            Err("varint overflows 64 bits")
        );
    }

    #[test]
    fn values_round_trip() {
        let q = [6, -7, 90, -3];
        let blob = encode_values(&q);
        assert_eq!(blob, [12, 13, 180, 1, 5]);
        assert_eq!(decode_values("x", &blob, 4).unwrap(), q);
        assert!(decode_values("x", &blob, 5).is_err());
        assert!(decode_values("x", &blob, 3).is_err());
    }

    #[test]
    fn meshes_round_trip_with_and_without_spatial_prediction() {
        let traversal = Traversal::for_mesh(&strip());
        let reference: Vec<i32> = (0..24).map(|j| j * 1000).collect();
        // A smooth offset: spatial prediction wins.
        let smooth: Vec<i32> = reference.iter().map(|r| r + 5000).collect();
        // Independent noise: it does not.
        let noisy: Vec<i32> = reference
            .iter()
            .zip([3, -2, 4, 1, -3, 2])
            .map(|(r, e)| r + e)
            .collect();
        let noisy: Vec<i32> = noisy
            .into_iter()
            .chain(reference[6..].iter().copied())
            .collect();
        for (q, spatial) in [(&smooth, 1), (&noisy, 0)] {
            let blob = encode_mesh(q, Some(&reference), &traversal);
            assert_eq!(blob[0], spatial);
            assert_eq!(
                &decode_mesh("m", &blob, Some(&reference), &traversal).unwrap(),
                q
            );
            assert!(
                decode_mesh("m", &blob[..blob.len() - 1], Some(&reference), &traversal).is_err()
            );
        }
        let blob = encode_mesh(&reference, None, &traversal);
        assert_eq!(
            decode_mesh("m", &blob, None, &traversal).unwrap(),
            reference
        );
        let mut bad = blob.clone();
        bad[0] = 7;
        assert!(decode_mesh("m", &bad, None, &traversal).is_err());
    }
}
