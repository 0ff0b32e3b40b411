//! Time series of quantized frames (the stream's meshes and weights).
//!
//! A series is cut into blocks of [`BLOCK`] frames. Each block starts with a
//! mode byte choosing, for the whole block, whichever of four predictors
//! gives the smallest residuals:
//!
//! | mode | temporal prediction | then |
//! |-----:|---------------------|------|
//! | 1 | first order, `t = q[f] − q[f−1]` | — |
//! | 2 | second order, `t = q[f] − (2q[f−1] − q[f−2])` | — |
//! | 3 | first order | minus the [`Traversal`] prediction of `t` from neighbours |
//! | 4 | second order | minus the prediction of `t` from neighbours |
//!
//! The spatial prediction is the rounded mean of `t` over the value's
//! neighbouring vertices that were already coded in this frame. Before the
//! first frame the history is the reference (the neutral scan for meshes,
//! zeros for weights). Modes 3 and 4 exploit that tracking error is smooth
//! over the face: neighbouring vertices move alike, so the difference of
//! their temporal residuals is small even when the motion is not smooth in
//! time. Within a block the residuals are written value by value in traversal
//! order, all frames of one value together, as zigzag varints; a vertex that
//! does not move is a run of zero bytes.
//!
//! Indexing: a series' frames have `n = traversal.len()` values (the
//! reference and every pushed frame; the two callers pass meshes quantized
//! over the traversal's topology, or 52 weights with
//! [`Traversal::identity`]); value indices come from the traversal, and a
//! block's offsets `f · n + j` stay below `frames · n`, the length its
//! buffers are sized to. What the blob declares is only ever read through
//! the bounds-checked [`Reader`].

use super::geometry_codec::{Reader, cost, put_varint, reconstruct};
use super::traversal::Traversal;

/// Frames per block; each block chooses its own predictor.
pub const BLOCK: usize = 64;

/// Codes a series: push frames with [`SeriesEncoder::push`], then
/// [`SeriesEncoder::finish`].
#[derive(Debug)]
pub struct SeriesEncoder<'t> {
    traversal: &'t Traversal,
    prev1: Vec<i32>,
    prev2: Vec<i32>,
    block: Vec<i32>,
    frames: usize,
    t1: Vec<i64>,
    t2: Vec<i64>,
    out: Vec<u8>,
}

impl<'t> SeriesEncoder<'t> {
    /// A series of frames of `traversal.len()` values whose history starts
    /// at `reference`.
    pub fn new(reference: Vec<i32>, traversal: &'t Traversal) -> Self {
        debug_assert_eq!(reference.len(), traversal.len());
        SeriesEncoder {
            traversal,
            prev1: reference.clone(),
            prev2: reference,
            block: Vec::new(),
            frames: 0,
            t1: Vec::new(),
            t2: Vec::new(),
            out: Vec::new(),
        }
    }

    /// Appends one frame.
    pub fn push(&mut self, frame: &[i32]) {
        debug_assert_eq!(frame.len(), self.prev1.len());
        self.block.extend_from_slice(frame);
        self.frames += 1;
        if self.frames == BLOCK {
            self.flush();
        }
    }

    /// The coded series.
    pub fn finish(mut self) -> Vec<u8> {
        self.flush();
        self.out
    }

    fn flush(&mut self) {
        let (n, frames) = (self.prev1.len(), self.frames);
        if frames == 0 {
            return;
        }
        self.t1.resize(frames * n, 0);
        self.t2.resize(frames * n, 0);
        for j in 0..n {
            let (mut p1, mut p2) = (self.prev1[j] as i64, self.prev2[j] as i64);
            for f in 0..frames {
                let q = self.block[f * n + j] as i64;
                self.t1[f * n + j] = q - p1;
                self.t2[f * n + j] = q - (2 * p1 - p2);
                (p2, p1) = (p1, q);
            }
            (self.prev1[j], self.prev2[j]) = (p1 as i32, p2 as i32);
        }
        let mut costs = [0u64; 4];
        for f in 0..frames {
            let (t1, t2) = (&self.t1[f * n..(f + 1) * n], &self.t2[f * n..(f + 1) * n]);
            for j in 0..n {
                costs[0] += cost(t1[j]);
                costs[1] += cost(t2[j]);
                costs[2] += cost(t1[j] - self.traversal.predict(j, t1));
                costs[3] += cost(t2[j] - self.traversal.predict(j, t2));
            }
        }
        // The first of the cheapest modes, so ties keep the simpler one.
        let mode = (0..4).fold(0, |best, m| if costs[m] < costs[best] { m } else { best });
        self.out.push(mode as u8 + 1);
        self.out.reserve(frames * n);
        let t = if mode % 2 == 1 { &self.t2 } else { &self.t1 };
        for &j in self.traversal.order() {
            let j = j as usize;
            for f in 0..frames {
                let frame = &t[f * n..(f + 1) * n];
                let spatial = if mode >= 2 {
                    self.traversal.predict(j, frame)
                } else {
                    0
                };
                put_varint(&mut self.out, frame[j] - spatial);
            }
        }
        self.block.clear();
        self.frames = 0;
    }
}

/// Where decoding a series failed.
#[derive(Debug, PartialEq, Eq)]
pub struct SeriesError {
    /// Index of the frame within the series.
    pub frame: usize,
    /// What is wrong.
    pub reason: String,
}

/// Decodes a series written by [`SeriesEncoder`], one block at a time.
#[derive(Debug)]
pub struct SeriesDecoder<'a, 't> {
    reader: Reader<'a>,
    traversal: &'t Traversal,
    prev1: Vec<i32>,
    prev2: Vec<i32>,
    block: Vec<i32>,
    t: Vec<i64>,
    decoded: usize,
}

impl<'a, 't> SeriesDecoder<'a, 't> {
    /// Reads `blob`, whose history starts at `reference`.
    pub fn new(blob: &'a [u8], reference: Vec<i32>, traversal: &'t Traversal) -> Self {
        debug_assert_eq!(reference.len(), traversal.len());
        SeriesDecoder {
            reader: Reader::new(blob),
            traversal,
            prev1: reference.clone(),
            prev2: reference,
            block: Vec::new(),
            t: Vec::new(),
            decoded: 0,
        }
    }

    /// Decodes the next block of `frames` frames (at most [`BLOCK`]); frame
    /// `f`'s values are `block[f * n..(f + 1) * n]`. Nothing is allocated
    /// before the blob is known to hold at least one byte per value.
    pub fn next_block(&mut self, frames: usize) -> Result<&[i32], SeriesError> {
        let n = self.prev1.len();
        let first = self.decoded;
        let err = |frame: usize, reason: String| SeriesError { frame, reason };
        let needed = frames.saturating_mul(n).saturating_add(1);
        if frames == 0 || frames > BLOCK || self.reader.remaining() < needed {
            let remaining = self.reader.remaining();
            let reason = format!(
                "a block of {frames} frames needs at least {needed} bytes, {remaining} remain"
            );
            return Err(err(first, reason));
        }
        let mode = match self.reader.byte() {
            Ok(m @ 1..=4) => m - 1,
            Ok(m) => return Err(err(first, format!("unknown predictor {m}"))),
            Err(e) => return Err(err(first, e.to_string())),
        };
        let (second, spatial) = (mode % 2 == 1, mode >= 2);
        self.block.clear();
        self.block.resize(frames * n, 0);
        self.t.clear();
        self.t.resize(frames * n, 0);
        // `t` is kept value by value (value `j` of frame `f` at
        // `j * frames + f`): a value's prediction reads its neighbours'
        // runs of `frames` adjacent numbers, not one number per frame
        // `n` apart.
        for &j in self.traversal.order() {
            let j = j as usize;
            let (mut p1, mut p2) = (self.prev1[j] as i64, self.prev2[j] as i64);
            for f in 0..frames {
                let at = |e: &str| err(first + f, format!("value {j}: {e}"));
                let mut t = self.reader.varint().map_err(at)?;
                if spatial {
                    let prediction = self.traversal.predict_from(j, |p| self.t[p * frames + f]);
                    t = t.checked_add(prediction).ok_or_else(|| at("overflow"))?;
                }
                let pred = if second { 2 * p1 - p2 } else { p1 };
                let q = reconstruct(pred, t).map_err(at)?;
                self.t[j * frames + f] = t;
                self.block[f * n + j] = q;
                (p2, p1) = (p1, q as i64);
            }
            (self.prev1[j], self.prev2[j]) = (p1 as i32, p2 as i32);
        }
        self.decoded += frames;
        Ok(&self.block)
    }

    /// An error unless the whole blob was read.
    pub fn finish(&self) -> Result<(), SeriesError> {
        self.reader.finish().map_err(|reason| SeriesError {
            frame: self.decoded.saturating_sub(1),
            reason,
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geometry::topology::Topology;

    fn round_trip(frames: &[Vec<i32>], reference: Vec<i32>, traversal: &Traversal) -> Vec<u8> {
        let n = reference.len();
        let mut enc = SeriesEncoder::new(reference.clone(), traversal);
        frames.iter().for_each(|f| enc.push(f));
        let blob = enc.finish();
        let mut dec = SeriesDecoder::new(&blob, reference, traversal);
        let mut decoded = Vec::new();
        for chunk in frames.chunks(BLOCK) {
            let block = dec.next_block(chunk.len()).unwrap();
            decoded.extend(block.chunks(n).map(<[i32]>::to_vec));
        }
        dec.finish().unwrap();
        assert_eq!(decoded, frames);
        blob
    }

    #[test]
    fn a_ramp_picks_second_order() {
        let n = 5;
        let frames: Vec<Vec<i32>> = (1..=150i32)
            .map(|f| (0..n as i32).map(|j| j + f * (j - 2) * 3).collect())
            .collect();
        let blob = round_trip(&frames, (0..n as i32).collect(), &Traversal::identity(n));
        assert_eq!(blob[0], 2);
    }

    #[test]
    fn a_shared_random_walk_picks_spatial_prediction() {
        // Four vertices in a strip that all move by the same random step.
        let topo = Topology::new(4, vec![[0, 1, 2], [1, 3, 2]]).unwrap();
        let traversal = Traversal::for_mesh(&topo);
        let mut walk = 0i32;
        let mut seed = 12345u32;
        let frames: Vec<Vec<i32>> = (0..100)
            .map(|_| {
                seed = seed.wrapping_mul(1_103_515_245).wrapping_add(12345);
                walk += (seed >> 16) as i32 % 200 - 100;
                (0..12).map(|j| j * 1000 + walk).collect()
            })
            .collect();
        let blob = round_trip(&frames, vec![0; 12], &traversal);
        assert_eq!(blob[0], 3);
    }

    #[test]
    fn errors_name_the_frame() {
        let traversal = Traversal::identity(3);
        let mut enc = SeriesEncoder::new(vec![0; 3], &traversal);
        for f in 0..10 {
            enc.push(&[f, 2 * f, 3 * f]);
        }
        let mut blob = enc.finish();
        // The last byte is value 2 of frame 9: make it a dangling continuation.
        let last = blob.len() - 1;
        blob[last] = 0x80;
        let mut dec = SeriesDecoder::new(&blob, vec![0; 3], &traversal);
        let err = dec.next_block(10).unwrap_err();
        assert_eq!(err.frame, 9);
        assert!(err.reason.contains("ends early"), "{}", err.reason);
        let mut dec = SeriesDecoder::new(&blob[..20], vec![0; 3], &traversal);
        assert_eq!(dec.next_block(10).unwrap_err().frame, 0);
        let mut dec = SeriesDecoder::new(&blob, vec![0; 3], &traversal);
        assert!(dec.next_block(BLOCK + 1).is_err());
    }
}
