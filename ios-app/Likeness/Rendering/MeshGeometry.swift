import LikenessGlue
import SceneKit
import UIKit

/// SceneKit geometry for the small meshes the core hands out as flat arrays,
/// made anew each time: the template at a prompt's expression, and the
/// person's own face in the mirror (1,220 vertices). The avatar, which may be
/// far larger, is built once and morphed instead (`AvatarMorph`).
enum MeshGeometry {
    /// A shaded triangle mesh from `vertices` (xyz flattened, metres) and
    /// `triangles` (three indices each), or `nil` if the arrays do not form
    /// a mesh (no vertices, a ragged count, or an index past the end).
    static func make(vertices: [Float], triangles: [UInt32]) -> SCNGeometry? {
        let vertexCount = vertices.count / 3
        guard vertexCount > 0, vertices.count % 3 == 0, triangles.count % 3 == 0,
              triangles.allSatisfy({ Int($0) < vertexCount })
        else { return nil }
        let normals = MeshNormals.compute(vertices: vertices, triangles: triangles)
        let geometry = SCNGeometry(
            sources: [source(vertices, semantic: .vertex), source(normals, semantic: .normal)],
            elements: [SCNGeometryElement(indices: triangles, primitiveType: .triangles)])
        geometry.materials = [skin()]
        return geometry
    }

    /// Three floats per vector, copied as they are.
    private static func source(_ values: [Float], semantic: SCNGeometrySource.Semantic) -> SCNGeometrySource {
        let data = values.withUnsafeBufferPointer { Data(buffer: $0) }
        return SCNGeometrySource(
            data: data,
            semantic: semantic,
            vectorCount: values.count / 3,
            usesFloatComponents: true,
            componentsPerVector: 3,
            bytesPerComponent: MemoryLayout<Float>.size,
            dataOffset: 0,
            dataStride: MemoryLayout<Float>.size * 3)
    }

    /// A plain clay look, lit from both sides (the meshes are shown mirrored,
    /// which turns their triangles around).
    static func skin() -> SCNMaterial {
        let material = SCNMaterial()
        material.lightingModel = .blinn
        material.diffuse.contents = UIColor(white: 0.82, alpha: 1)
        material.specular.contents = UIColor(white: 0.15, alpha: 1)
        material.isDoubleSided = true
        return material
    }
}
