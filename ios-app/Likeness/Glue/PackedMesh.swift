import Foundation

/// Checks on the packed meshes the core hands out (`PreviewMesh`): vertices
/// and normals as little-endian 32-bit floats, xyz after xyz, triangles as
/// little-endian 32-bit indices. SceneKit reads the bytes as they are (every
/// iPhone is little-endian), so a count that does not fit would draw garbage
/// or read past the end: these say whether the bytes form a mesh before
/// SceneKit sees them.
public enum PackedMesh {
    /// Bytes of one xyz vector of 32-bit floats.
    public static let bytesPerVector = 12
    /// Bytes of one triangle index.
    public static let bytesPerIndex = 4

    /// How many vectors `bytes` holds, or `nil` if it is not a whole number
    /// of them.
    public static func vectorCount(_ bytes: Data) -> Int? {
        bytes.count % bytesPerVector == 0 ? bytes.count / bytesPerVector : nil
    }

    /// How many triangles `bytes` holds, or `nil` unless it is whole
    /// triangles whose every index is below `vertexCount`.
    public static func triangleCount(_ bytes: Data, vertexCount: Int) -> Int? {
        let bytesPerTriangle = 3 * bytesPerIndex
        guard bytes.count % bytesPerTriangle == 0 else { return nil }
        let fits = bytes.withUnsafeBytes { raw -> Bool in
            var offset = 0
            while offset < raw.count {
                let index = UInt32(littleEndian: raw.loadUnaligned(fromByteOffset: offset, as: UInt32.self))
                if Int(index) >= vertexCount {
                    return false
                }
                offset += bytesPerIndex
            }
            return true
        }
        return fits ? bytes.count / bytesPerTriangle : nil
    }

    /// The positions in `targets` (one per ARKit shape, in the core's order)
    /// that hold a full set of `vertexCount` vectors; an empty target (the
    /// avatar lacks that shape) or one of another size is left out.
    public static func presentTargets(_ targets: [Data], vertexCount: Int) -> [Int] {
        targets.indices.filter { vectorCount(targets[$0]) == vertexCount && vertexCount > 0 }
    }
}
