import simd

/// Per-vertex normals of a triangle mesh given as flat arrays, for shading the
/// meshes the core returns (which carry positions only).
public enum MeshNormals {
    /// One unit normal per vertex (flattened xyz like `vertices`): the sum of
    /// the face normals of the triangles around it, each weighted by the
    /// triangle's area. A vertex in no triangle, or only in degenerate ones,
    /// gets +z (towards the viewer in ARKit's face coordinates).
    ///
    /// Triangles are counter-clockwise seen from the front. Indices past the
    /// end of `vertices` are skipped.
    public static func compute(vertices: [Float], triangles: [UInt32]) -> [Float] {
        let count = vertices.count / 3
        var sums = [SIMD3<Float>](repeating: .zero, count: count)
        func position(_ index: Int) -> SIMD3<Float> {
            SIMD3(vertices[3 * index], vertices[3 * index + 1], vertices[3 * index + 2])
        }
        var corner = 0
        while corner + 2 < triangles.count {
            let a = Int(triangles[corner])
            let b = Int(triangles[corner + 1])
            let c = Int(triangles[corner + 2])
            corner += 3
            guard a < count, b < count, c < count else { continue }
            // The cross product's length is twice the area: area weighting for free.
            let faceNormal = simd_cross(position(b) - position(a), position(c) - position(a))
            sums[a] += faceNormal
            sums[b] += faceNormal
            sums[c] += faceNormal
        }
        var normals: [Float] = []
        normals.reserveCapacity(count * 3)
        for sum in sums {
            let length = simd_length(sum)
            let unit = length > 0 ? sum / length : SIMD3<Float>(0, 0, 1)
            normals.append(unit.x)
            normals.append(unit.y)
            normals.append(unit.z)
        }
        return normals
    }
}
