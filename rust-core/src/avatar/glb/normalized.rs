//! Integer vertex data as floats, by the glTF 2.0 spec's rules
//! ("Animations", the table of normalized integers, which
//! `KHR_mesh_quantization` refers to): unnormalized, `c` itself;
//! normalized, `max(c / 127, −1)` (BYTE), `c / 255` (UNSIGNED_BYTE),
//! `max(c / 32767, −1)` (SHORT), `c / 65535` (UNSIGNED_SHORT).

use gltf::accessor::DataType;

/// One component of `data_type` from its little-endian bytes, as a float
/// (the module's rules).
pub(crate) fn component(data_type: DataType, normalized: bool, b: &[u8]) -> f32 {
    match (data_type, normalized) {
        (DataType::F32, _) => f32::from_le_bytes([b[0], b[1], b[2], b[3]]),
        (DataType::I8, false) => f32::from(b[0] as i8),
        (DataType::I8, true) => (f32::from(b[0] as i8) / 127.0).max(-1.0),
        (DataType::U8, false) => f32::from(b[0]),
        (DataType::U8, true) => f32::from(b[0]) / 255.0,
        (DataType::I16, false) => f32::from(i16::from_le_bytes([b[0], b[1]])),
        (DataType::I16, true) => (f32::from(i16::from_le_bytes([b[0], b[1]])) / 32767.0).max(-1.0),
        (DataType::U16, false) => f32::from(u16::from_le_bytes([b[0], b[1]])),
        (DataType::U16, true) => f32::from(u16::from_le_bytes([b[0], b[1]])) / 65535.0,
        // Not a vertex attribute type in glTF 2.0 (indices only).
        (DataType::U32, _) => u32::from_le_bytes([b[0], b[1], b[2], b[3]]) as f32,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn normalized_integers_follow_the_spec() {
        assert_eq!(component(DataType::I8, true, &[0x81]), -1.0); // -127
        assert_eq!(component(DataType::I8, true, &[0x80]), -1.0); // -128 clamps
        assert_eq!(component(DataType::U8, true, &[255]), 1.0);
        assert_eq!(
            component(DataType::I16, true, &0x7FFFi16.to_le_bytes()),
            1.0
        );
        assert_eq!(
            component(DataType::I16, true, &(-32768i16).to_le_bytes()),
            -1.0
        );
        assert_eq!(
            component(DataType::U16, true, &32768u16.to_le_bytes()),
            32768.0 / 65535.0
        );
        assert_eq!(
            component(DataType::I16, false, &(-300i16).to_le_bytes()),
            -300.0
        );
        assert_eq!(component(DataType::U8, false, &[200]), 200.0);
    }
}
