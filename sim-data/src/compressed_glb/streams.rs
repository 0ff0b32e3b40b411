//! Compressed buffer views as `EXT_meshopt_compression` lays them out
//! (<https://github.com/KhronosGroup/glTF/blob/main/extensions/2.0/Vendor/EXT_meshopt_compression/README.md>):
//! the compressed stream in buffer 0 (the GLB `BIN` chunk), the view itself
//! pointing into the fallback buffer (buffer 1, which holds no data).
//!
//! Vertex streams use meshoptimizer's vertex codec version 0, the one the
//! extension specifies (version 1 belongs to `KHR_meshopt_compression`);
//! index streams its index buffer codec (mode `TRIANGLES`).

use serde_json::{Value, json};

/// The file's binary data and views as they are being written.
#[derive(Default)]
pub struct Streams {
    /// Buffer 0: compressed streams and the views copied as they were.
    pub bin: Vec<u8>,
    /// Length of buffer 1, the fallback buffer.
    pub fallback: usize,
    /// The new `bufferViews`.
    pub views: Vec<Value>,
}

/// One vertex of `N` bytes.
fn encode_n<const N: usize>(data: &[u8]) -> Result<Vec<u8>, String> {
    let vertices: Vec<[u8; N]> = data
        .chunks_exact(N)
        .map(|c| c.try_into().unwrap_or([0; N]))
        .collect();
    meshopt::encoding::encode_vertex_buffer_level(&vertices, 2, Some(0)).map_err(|e| e.to_string())
}

macro_rules! by_stride {
    ($stride:expr, $data:expr; $($n:literal)*) => {
        match $stride {
            $($n => encode_n::<$n>($data),)*
            other => Err(format!("byteStride {other} not handled by the test encoder")),
        }
    };
}

impl Streams {
    /// Appends `bytes` to buffer 0, 4-byte aligned; their offset.
    fn push(&mut self, bytes: &[u8]) -> usize {
        self.bin.resize(self.bin.len().next_multiple_of(4), 0);
        let at = self.bin.len();
        self.bin.extend_from_slice(bytes);
        at
    }

    /// A plain view of `bytes` in buffer 0 (data that is not geometry);
    /// its index.
    pub fn plain(&mut self, mut view: Value, bytes: &[u8]) -> usize {
        let at = self.push(bytes);
        view["buffer"] = json!(0);
        view["byteOffset"] = json!(at);
        view["byteLength"] = json!(bytes.len());
        self.views.push(view);
        self.views.len() - 1
    }

    fn compressed(
        &mut self,
        encoded: &[u8],
        count: usize,
        stride: usize,
        mode: &str,
        filter: &str,
        target: u32,
    ) -> usize {
        let at = self.push(encoded);
        self.fallback = self.fallback.next_multiple_of(4);
        let mut ext = json!({
            "buffer": 0, "byteOffset": at, "byteLength": encoded.len(),
            "byteStride": stride, "count": count, "mode": mode
        });
        if filter != "NONE" {
            ext["filter"] = json!(filter);
        }
        let mut view = json!({
            "buffer": 1, "byteOffset": self.fallback, "byteLength": count * stride,
            "target": target,
            "extensions": { "EXT_meshopt_compression": ext }
        });
        if mode == "ATTRIBUTES" {
            view["byteStride"] = json!(stride);
        }
        self.fallback += count * stride;
        self.views.push(view);
        self.views.len() - 1
    }

    /// A compressed view of vertex data, `stride` bytes a vertex (a
    /// multiple of 4 up to 64), with `filter` already applied; its index.
    pub fn vertices(&mut self, data: &[u8], stride: usize, filter: &str) -> Result<usize, String> {
        let encoded = by_stride!(stride, data; 4 8 12 16 20 24 28 32 36 40 44 48 52 56 60 64)?;
        Ok(self.compressed(
            &encoded,
            data.len() / stride,
            stride,
            "ATTRIBUTES",
            filter,
            34962,
        ))
    }

    /// A compressed view of triangle indices (`u16` if every index fits,
    /// else `u32`); its index and the glTF component type.
    pub fn triangles(&mut self, indices: &[u32], vertices: usize) -> Result<(usize, u32), String> {
        if !indices.len().is_multiple_of(3) {
            return Err(format!("{} indices, not triangles", indices.len()));
        }
        let encoded =
            meshopt::encoding::encode_index_buffer(indices, vertices).map_err(|e| e.to_string())?;
        let (stride, component) = if vertices <= 0xFFFF {
            (2, 5123)
        } else {
            (4, 5125)
        };
        let view = self.compressed(&encoded, indices.len(), stride, "TRIANGLES", "NONE", 34963);
        Ok((view, component))
    }
}
