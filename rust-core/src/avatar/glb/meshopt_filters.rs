//! The filters of `EXT_meshopt_compression` (spec, "Filters":
//! <https://github.com/KhronosGroup/glTF/blob/main/extensions/2.0/Vendor/EXT_meshopt_compression/README.md#filters>),
//! applied in place to decoded `ATTRIBUTES` data by meshoptimizer's own
//! decoders (`meshopt::encoding::decode_filter_*`):
//!
//! | filter | `byteStride` | each element becomes |
//! |---|---|---|
//! | `NONE` | any | itself |
//! | `OCTAHEDRAL` | 4 (8-bit) or 8 (16-bit) | a unit vector from octahedral `x, y` (`z` holds the scale one); `w` kept |
//! | `QUATERNION` | 8 | a unit quaternion from three 16-bit components and the index of the fourth |
//! | `EXPONENTIAL` | a multiple of 4 | each 32-bit word `e << 24 \| m` becomes the float `2^e · m` (`e`, `m` signed) |
//!
//! The strides are checked here ([`Filter::parse`]) before the C++ code,
//! which asserts on them, sees any data.

/// A filter of the extension.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum Filter {
    None,
    Octahedral,
    Quaternion,
    Exponential,
}

impl Filter {
    /// The filter named `name` for elements of `stride` bytes, or why it
    /// cannot apply.
    pub fn parse(name: &str, stride: usize) -> Result<Filter, String> {
        let (filter, ok) = match name {
            "NONE" => (Filter::None, true),
            "OCTAHEDRAL" => (Filter::Octahedral, stride == 4 || stride == 8),
            "QUATERNION" => (Filter::Quaternion, stride == 8),
            "EXPONENTIAL" => (Filter::Exponential, stride.is_multiple_of(4) && stride > 0),
            _ => return Err("unknown".into()),
        };
        if ok {
            Ok(filter)
        } else {
            Err(format!("not allowed with byteStride {stride}"))
        }
    }
}

/// Applies `filter` to `bytes`, elements of `stride` bytes that
/// [`Filter::parse`] accepted (a trailing partial element is left alone).
pub(crate) fn apply_filter(filter: Filter, bytes: &mut [u8], stride: usize) {
    use meshopt::encoding::{decode_filter_exp, decode_filter_oct, decode_filter_quat};
    match (filter, stride) {
        (Filter::None, _) => {}
        (Filter::Octahedral, 4) => {
            let mut v: Vec<[i8; 4]> = bytes
                .chunks_exact(4)
                .map(|c| [c[0] as i8, c[1] as i8, c[2] as i8, c[3] as i8])
                .collect();
            decode_filter_oct(&mut v);
            for (c, e) in bytes.chunks_exact_mut(4).zip(&v) {
                c.copy_from_slice(&e.map(|x| x as u8));
            }
        }
        (Filter::Octahedral, _) | (Filter::Quaternion, _) => {
            let mut v: Vec<[i16; 4]> = bytes
                .chunks_exact(8)
                .map(|c| std::array::from_fn(|k| i16::from_le_bytes([c[2 * k], c[2 * k + 1]])))
                .collect();
            if filter == Filter::Octahedral {
                decode_filter_oct(&mut v);
            } else {
                decode_filter_quat(&mut v);
            }
            for (c, e) in bytes.chunks_exact_mut(8).zip(&v) {
                for k in 0..4 {
                    c[2 * k..2 * k + 2].copy_from_slice(&e[k].to_le_bytes());
                }
            }
        }
        (Filter::Exponential, _) => {
            // Each 32-bit word is decoded on its own (spec), whatever the stride.
            let mut v: Vec<[u32; 1]> = bytes
                .chunks_exact(4)
                .map(|c| [u32::from_le_bytes([c[0], c[1], c[2], c[3]])])
                .collect();
            decode_filter_exp(&mut v);
            for (c, e) in bytes.chunks_exact_mut(4).zip(&v) {
                c.copy_from_slice(&e[0].to_le_bytes());
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn exponential_words_become_floats() {
        // e = -2, m = 3: 0.75; e = 0, m = -5: -5.
        let words = [(-2i32 as u32) << 24 | 3, (-5i32 as u32) & 0x00FF_FFFF];
        let mut bytes: Vec<u8> = words.iter().flat_map(|w| w.to_le_bytes()).collect();
        apply_filter(Filter::Exponential, &mut bytes, 8);
        let f = |k: usize| f32::from_le_bytes(bytes[4 * k..4 * k + 4].try_into().unwrap());
        assert_eq!((f(0), f(1)), (0.75, -5.0));
    }

    #[test]
    fn octahedral_gives_unit_vectors() {
        // x = y = 0 with z holding 127: straight up +z.
        let mut bytes = vec![0, 0, 127, 9];
        apply_filter(Filter::Octahedral, &mut bytes, 4);
        assert_eq!(bytes, [0, 0, 127, 9]);
        let mut bytes = vec![64, 0, 127, 0]; // half way to +x
        apply_filter(Filter::Octahedral, &mut bytes, 4);
        let v = bytes[..3].iter().map(|&b| f32::from(b as i8) / 127.0);
        let len: f32 = v.map(|x| x * x).sum::<f32>().sqrt();
        assert!((len - 1.0).abs() < 0.02, "{bytes:?}");
    }

    #[test]
    fn strides_are_checked() {
        assert!(Filter::parse("OCTAHEDRAL", 12).is_err());
        assert!(Filter::parse("QUATERNION", 4).is_err());
        assert!(Filter::parse("EXPONENTIAL", 12).is_ok());
        assert!(Filter::parse("ZSTD", 4).is_err());
    }
}
