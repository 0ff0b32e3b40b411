import LikenessFFI
import LikenessGlue
import SceneKit

/// The avatar as SceneKit plays it: one geometry built once from the core's
/// `PreviewMesh`, with an `SCNMorpher` in additive mode whose targets are the
/// avatar's ARKit shapes. A live frame then sets only the shapes' weights
/// (`apply(weights:)`); no mesh is copied or rebuilt.
///
/// The core's bytes go to SceneKit as they are: vertices and normals as
/// little-endian 32-bit floats (every iPhone is little-endian), triangles as
/// 32-bit indices, each target the displacement of every vertex at weight
/// one, which is what additive morphing adds up (`base + Σ wᵢ·targetᵢ`).
struct AvatarMorph {
    /// The avatar at rest, with `morpher` to be set on the same node.
    let geometry: SCNGeometry
    /// Plays the shapes.
    let morpher: SCNMorpher
    /// For each morph target, the index of its ARKit shape in the core's
    /// order (the avatar may lack some shapes; those have no target).
    let shapeOfTarget: [Int]

    /// The avatar of `mesh`, or `nil` if its bytes do not form a mesh.
    init?(mesh: PreviewMesh) {
        guard let vertexCount = PackedMesh.vectorCount(mesh.positions), vertexCount > 0,
              let triangleCount = PackedMesh.triangleCount(mesh.triangles, vertexCount: vertexCount)
        else { return nil }
        let hasNormals = PackedMesh.vectorCount(mesh.normals) == vertexCount
        var sources = [Self.source(mesh.positions, semantic: .vertex, count: vertexCount)]
        if hasNormals {
            sources.append(Self.source(mesh.normals, semantic: .normal, count: vertexCount))
        }
        let element = SCNGeometryElement(
            data: mesh.triangles, primitiveType: .triangles, primitiveCount: triangleCount,
            bytesPerIndex: PackedMesh.bytesPerIndex)
        let rest = SCNGeometry(sources: sources, elements: [element])
        rest.materials = [MeshGeometry.skin()]

        let positionTargets: [Data] = mesh.positionTargets
        let normalTargets: [Data] = mesh.normalTargets
        let shapes = PackedMesh.presentTargets(positionTargets, vertexCount: vertexCount)
        var targets: [SCNGeometry] = []
        targets.reserveCapacity(shapes.count)
        for shape in shapes {
            var targetSources = [Self.source(positionTargets[shape], semantic: .vertex, count: vertexCount)]
            if hasNormals, shape < normalTargets.count, PackedMesh.vectorCount(normalTargets[shape]) == vertexCount {
                targetSources.append(Self.source(normalTargets[shape], semantic: .normal, count: vertexCount))
            }
            targets.append(SCNGeometry(sources: targetSources, elements: nil))
        }
        let player = SCNMorpher()
        player.calculationMode = .additive
        player.targets = targets

        geometry = rest
        morpher = player
        shapeOfTarget = shapes
    }

    /// Sets each target's weight from `weights` (52, in the core's order).
    /// On the main thread.
    func apply(weights: [Float]) {
        for (target, shape) in shapeOfTarget.enumerated() where shape < weights.count {
            morpher.setWeight(CGFloat(weights[shape]), forTargetAt: target)
        }
    }

    private static func source(_ data: Data, semantic: SCNGeometrySource.Semantic, count: Int) -> SCNGeometrySource {
        SCNGeometrySource(
            data: data,
            semantic: semantic,
            vectorCount: count,
            usesFloatComponents: true,
            componentsPerVector: 3,
            bytesPerComponent: MemoryLayout<Float>.size,
            dataOffset: 0,
            dataStride: PackedMesh.bytesPerVector)
    }
}
