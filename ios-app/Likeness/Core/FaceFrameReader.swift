import ARKit
import LikenessGlue

/// Reads an `ARFaceAnchor` into what the core takes: the 52 weights in the
/// core's order and the face mesh's vertices, flattened.
///
/// Pairs ARKit's dictionary keys with the core's names (`arkitNames()`) on the
/// first anchor it reads, and keeps the pairing. Used on `CoreQueue` only.
final class FaceFrameReader {
    /// The core's blendshape names, in its order.
    let names: [String]
    private var keys: BlendShapeKeys?

    /// - Parameter names: `arkitNames()`.
    init(names: [String]) {
        self.names = names
    }

    /// ARKit's key for each name, paired on the first anchor.
    func blendShapeKeys(for anchor: ARFaceAnchor) throws -> BlendShapeKeys {
        if let keys {
            return keys
        }
        let matched = try BlendShapeKeys.match(names: names, available: Array(anchor.blendShapes.keys))
        keys = matched
        return matched
    }

    /// The anchor's weights in the core's order.
    func weights(of anchor: ARFaceAnchor) throws -> [Float] {
        let keys = try blendShapeKeys(for: anchor)
        if let weights = ARKitGlue.weights(from: anchor.blendShapes, keys: keys.keys) {
            return weights
        }
        var missing: [String] = []
        for (name, key) in zip(names, keys.keys) where anchor.blendShapes[key] == nil {
            missing.append(name)
        }
        throw BlendShapeKeys.MatchError.missing(missing)
    }

    /// The anchor's face mesh, xyz flattened, in face-anchor coordinates.
    func vertices(of anchor: ARFaceAnchor) -> [Float] {
        ARKitGlue.flatten(anchor.geometry.vertices)
    }
}
