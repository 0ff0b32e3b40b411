import ARKit

/// Conversions from ARKit's face types to the flat arrays the core takes.
///
/// Pure functions with no camera and no core, so they are unit-tested on a
/// simulator (`Tests/ARKitGlueTests.swift`).
public enum ARKitGlue {
    /// The weights of `blendShapes` in the order of `keys` (the core's order,
    /// from `BlendShapeKeys`), or `nil` if the dictionary lacks one of them:
    /// a weight is never made up.
    public static func weights(
        from blendShapes: [ARFaceAnchor.BlendShapeLocation: NSNumber],
        keys: [ARFaceAnchor.BlendShapeLocation]
    ) -> [Float]? {
        var weights: [Float] = []
        weights.reserveCapacity(keys.count)
        for key in keys {
            guard let value = blendShapes[key] else { return nil }
            weights.append(value.floatValue)
        }
        return weights
    }

    /// Vertex positions as `x0, y0, z0, x1, y1, z1, …`.
    public static func flatten(_ vertices: [SIMD3<Float>]) -> [Float] {
        var flat: [Float] = []
        flat.reserveCapacity(vertices.count * 3)
        for vertex in vertices {
            flat.append(vertex.x)
            flat.append(vertex.y)
            flat.append(vertex.z)
        }
        return flat
    }

    /// Vertex positions as little-endian 32-bit floats, xyz after xyz (12
    /// bytes a vertex): what `CaptureSession.pushFramePacked` takes, one
    /// copy across the FFI instead of one write per float.
    public static func packed(_ vertices: [SIMD3<Float>]) -> Data {
        var bytes: [UInt8] = []
        bytes.reserveCapacity(vertices.count * 12)
        func append(_ value: Float) {
            withUnsafeBytes(of: value.bitPattern.littleEndian) { bytes.append(contentsOf: $0) }
        }
        for vertex in vertices {
            append(vertex.x)
            append(vertex.y)
            append(vertex.z)
        }
        return Data(bytes)
    }

    /// Flattened xyz values (`x0, y0, z0, x1, …`, as a recorded frame holds
    /// them) packed the same way as `packed(_:)`.
    public static func packed(flat values: [Float]) -> Data {
        var bytes: [UInt8] = []
        bytes.reserveCapacity(values.count * 4)
        for value in values {
            withUnsafeBytes(of: value.bitPattern.littleEndian) { bytes.append(contentsOf: $0) }
        }
        return Data(bytes)
    }

    /// `ARFaceGeometry.triangleIndices` (16-bit, signed by ARKit's declaration
    /// but indices all the same) as the core's 32-bit unsigned indices.
    public static func triangleIndices(_ indices: [Int16]) -> [UInt32] {
        indices.map { UInt32(UInt16(bitPattern: $0)) }
    }
}
