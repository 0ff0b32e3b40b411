//! Accessor data (glTF 2.0 spec, "Accessors"), read with every length checked
//! first.
//!
//! An accessor's element `i` starts in its buffer at
//! `view.byteOffset + accessor.byteOffset + i · stride`, where `stride` is
//! the view's `byteStride` or else the element's size; without a
//! `bufferView` every element is zero.
//! A sparse accessor ("Sparse Accessors") then overwrites `sparse.count` elements: the
//! element numbers (strictly increasing, unsigned 8/16/32-bit) and their
//! values lie tightly packed in two views of their own.
//!
//! The count in the JSON is never trusted to size an allocation: the bytes
//! it implies are checked against the view and the buffer first, and an
//! accessor without a view must have the count its caller expects.

use super::GlbError;
use super::normalized::component;
use gltf::accessor::{DataType, Dimensions};
use std::path::Path;

/// The component types of vertex data: floats, and the integers of
/// `KHR_mesh_quantization`.
const VERTEX_TYPES: [DataType; 5] = [
    DataType::F32,
    DataType::I8,
    DataType::U8,
    DataType::I16,
    DataType::U16,
];

/// `count` elements of `size` bytes, `stride` apart, all within `data`.
struct Strided<'a> {
    data: &'a [u8],
    stride: usize,
    size: usize,
    count: usize,
}

impl Strided<'_> {
    fn element(&self, i: usize) -> &[u8] {
        &self.data[i * self.stride..i * self.stride + self.size]
    }
}

/// What an accessor read needs: the file name for messages and the
/// buffers' bytes.
pub(crate) struct Source<'a> {
    pub file: &'a Path,
    pub buffers: &'a [Vec<u8>],
}

impl Source<'_> {
    fn error(&self, accessor: usize, what: String) -> GlbError {
        GlbError::Accessor {
            file: self.file.to_path_buf(),
            accessor,
            what,
        }
    }

    /// `count` elements of `size` bytes starting `offset` bytes into `view`.
    fn strided<'b>(
        &'b self,
        accessor: usize,
        view: &gltf::buffer::View,
        offset: usize,
        count: usize,
        size: usize,
        stride: Option<usize>,
    ) -> Result<Strided<'b>, GlbError> {
        let stride = stride.unwrap_or(size);
        let buffer = &self.buffers[view.buffer().index()];
        let view_end = view.offset().checked_add(view.length());
        let needed = (count as u64)
            .saturating_sub(1)
            .saturating_mul(stride as u64)
            .saturating_add(if count == 0 { 0 } else { size as u64 })
            .saturating_add(offset as u64);
        match view_end {
            Some(end) if end <= buffer.len() && needed <= view.length() as u64 && stride >= size => {
                let data = &buffer[view.offset() + offset..end];
                Ok(Strided {
                    data,
                    stride,
                    size,
                    count,
                })
            }
            _ => Err(self.error(
                accessor,
                format!(
                    "{count} elements of {size} bytes (stride {stride}) from byte {offset} need {needed} bytes; buffer view {} has {} (buffer {} holds {} bytes)",
                    view.index(),
                    view.length(),
                    view.buffer().index(),
                    buffer.len()
                ),
            )),
        }
    }

    /// Every element of `accessor` as raw little-endian bytes, sparse
    /// substitution applied: `out(i, bytes)` is called for each element.
    /// `expected_count`, if given, must equal the accessor's count.
    fn elements(
        &self,
        accessor: &gltf::Accessor,
        size: usize,
        expected_count: Option<usize>,
        out: &mut dyn FnMut(usize, &[u8]),
    ) -> Result<usize, GlbError> {
        let a = accessor.index();
        let count = accessor.count();
        if let Some(expected) = expected_count.filter(|&e| e != count) {
            return Err(self.error(a, format!("count {count}, its primitive has {expected}")));
        }
        match accessor.view() {
            Some(view) => {
                let s = self.strided(a, &view, accessor.offset(), count, size, view.stride())?;
                for i in 0..s.count {
                    out(i, s.element(i));
                }
            }
            None if expected_count.is_none() => {
                return Err(self.error(a, "no buffer view, and no count to check".into()));
            }
            None => {
                let zero = vec![0u8; size];
                for i in 0..count {
                    out(i, &zero);
                }
            }
        }
        if let Some(sparse) = accessor.sparse() {
            let n = sparse.count();
            if n > count {
                return Err(self.error(a, format!("sparse count {n} > count {count}")));
            }
            let (ix, vals) = (sparse.indices(), sparse.values());
            let isize = match ix.index_type() {
                gltf::accessor::sparse::IndexType::U8 => 1,
                gltf::accessor::sparse::IndexType::U16 => 2,
                gltf::accessor::sparse::IndexType::U32 => 4,
            };
            let ix = self.strided(a, &ix.view(), ix.offset(), n, isize, None)?;
            let vals = self.strided(a, &vals.view(), vals.offset(), n, size, None)?;
            let mut last = None;
            for k in 0..n {
                let i = le_uint(ix.element(k)) as usize;
                if i >= count || last.is_some_and(|l| i <= l) {
                    return Err(self.error(
                        a,
                        format!("sparse index {i} (entry {k}) out of range or not increasing"),
                    ));
                }
                last = Some(i);
                out(i, vals.element(k));
            }
        }
        Ok(count)
    }

    fn check_type(
        &self,
        accessor: &gltf::Accessor,
        dims: Dimensions,
        types: &[DataType],
    ) -> Result<(), GlbError> {
        if accessor.dimensions() != dims || !types.contains(&accessor.data_type()) {
            return Err(self.error(
                accessor.index(),
                format!(
                    "{:?} of {:?}; expected {dims:?} of {types:?}",
                    accessor.dimensions(),
                    accessor.data_type()
                ),
            ));
        }
        Ok(())
    }

    /// A `VEC3` of 32-bit floats, or of 8- or 16-bit integers, normalized
    /// or not (`KHR_mesh_quantization`), as floats by the rules of
    /// [`component`] (positions, target displacements).
    pub fn vec3(
        &self,
        accessor: &gltf::Accessor,
        expected_count: Option<usize>,
    ) -> Result<Vec<glam::Vec3>, GlbError> {
        self.check_type(accessor, Dimensions::Vec3, &VERTEX_TYPES)?;
        let (dt, normalized) = (accessor.data_type(), accessor.normalized());
        let c = dt.size();
        let mut out = vec![glam::Vec3::ZERO; expected_count.unwrap_or(0)];
        self.elements(accessor, 3 * c, expected_count, &mut |i, b| {
            let f = |k: usize| component(dt, normalized, &b[k * c..]);
            let v = glam::Vec3::new(f(0), f(1), f(2));
            match out.get_mut(i) {
                Some(slot) => *slot = v,
                None => out.push(v),
            }
        })?;
        Ok(out)
    }

    /// Every component of a `SCALAR` or `VEC2`…`VEC4` accessor of floats or
    /// 8- or 16-bit integers, as floats ([`component`]), element after
    /// element, sparse substitution applied.
    pub fn floats(&self, accessor: &gltf::Accessor) -> Result<Vec<f32>, GlbError> {
        let dims = accessor.dimensions();
        let width = match dims {
            Dimensions::Scalar | Dimensions::Vec2 | Dimensions::Vec3 | Dimensions::Vec4 => {
                dims.multiplicity()
            }
            _ => {
                return Err(self.error(
                    accessor.index(),
                    format!("{dims:?}: not a vertex attribute"),
                ));
            }
        };
        self.check_type(accessor, dims, &VERTEX_TYPES)?;
        let (dt, normalized) = (accessor.data_type(), accessor.normalized());
        let c = dt.size();
        // Dense data (the common case, and every decoded meshopt view):
        // one pass over the view, without a call per element.
        if let (Some(view), None) = (accessor.view(), accessor.sparse()) {
            let s = self.strided(
                accessor.index(),
                &view,
                accessor.offset(),
                accessor.count(),
                width * c,
                view.stride(),
            )?;
            let mut out = Vec::with_capacity(s.count * width);
            for i in 0..s.count {
                let e = s.element(i);
                out.extend((0..width).map(|k| component(dt, normalized, &e[k * c..])));
            }
            return Ok(out);
        }
        // The count is checked against the view before any element is
        // read; capacity is reserved only up to what the buffers could hold.
        let held: usize = self.buffers.iter().map(Vec::len).sum();
        let mut out = Vec::with_capacity(accessor.count().min(held) * width);
        self.elements(accessor, width * c, None, &mut |i, b| {
            let at = i * width;
            if out.len() == at {
                out.extend((0..width).map(|k| component(dt, normalized, &b[k * c..])));
                return;
            }
            if out.len() < at + width {
                out.resize(at + width, 0.0);
            }
            for k in 0..width {
                out[at + k] = component(dt, normalized, &b[k * c..]);
            }
        })?;
        Ok(out)
    }

    /// A `SCALAR` of unsigned 8, 16 or 32-bit integers (triangle indices).
    pub fn indices(&self, accessor: &gltf::Accessor) -> Result<Vec<u32>, GlbError> {
        self.check_type(
            accessor,
            Dimensions::Scalar,
            &[DataType::U8, DataType::U16, DataType::U32],
        )?;
        let size = accessor.data_type().size();
        let mut out = Vec::new();
        self.elements(accessor, size, None, &mut |i, b| {
            let v = le_uint(b) as u32;
            match out.get_mut(i) {
                Some(slot) => *slot = v,
                None => out.push(v),
            }
        })?;
        Ok(out)
    }

    /// A `MAT4` of 32-bit floats, column-major (inverse bind matrices).
    pub fn mat4(&self, accessor: &gltf::Accessor) -> Result<Vec<glam::Mat4>, GlbError> {
        self.check_type(accessor, Dimensions::Mat4, &[DataType::F32])?;
        let mut out = Vec::new();
        self.elements(accessor, 64, None, &mut |i, b| {
            let cols: [f32; 16] = std::array::from_fn(|k| {
                f32::from_le_bytes([b[4 * k], b[4 * k + 1], b[4 * k + 2], b[4 * k + 3]])
            });
            let m = glam::Mat4::from_cols_array(&cols);
            match out.get_mut(i) {
                Some(slot) => *slot = m,
                None => out.push(m),
            }
        })?;
        Ok(out)
    }
}

/// An unsigned little-endian integer of 1, 2 or 4 bytes.
fn le_uint(b: &[u8]) -> u64 {
    b.iter().rev().fold(0, |acc, &x| (acc << 8) | u64::from(x))
}
