import ARKit
import LikenessGlue

/// Reads an `ARFaceAnchor` into what the core takes: the 52 weights in the
/// core's order and the face mesh's vertices, packed.
///
/// Takes ARKit's keys from the core (`arkitKeys()`), checks them against the
/// first anchor it reads, and keeps them. Used on one serial queue only (the
/// camera feed's or the mirror's ARKit delegate queue).
final class FaceFrameReader {
    /// The core's blendshape names, in its order.
    let names: [String]
    /// ARKit's raw key for each name, in the same order.
    private let rawKeys: [String]
    private var keys: BlendShapeKeys?

    /// - Parameters:
    ///   - names: `arkitNames()`.
    ///   - rawKeys: `arkitKeys()`.
    init(names: [String], rawKeys: [String]) {
        self.names = names
        self.rawKeys = rawKeys
    }

    /// ARKit's key for each name, checked on the first anchor.
    func blendShapeKeys(for anchor: ARFaceAnchor) throws -> BlendShapeKeys {
        if let keys {
            return keys
        }
        let matched = try BlendShapeKeys.match(
            names: names, rawKeys: rawKeys, available: Array(anchor.blendShapes.keys))
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

    /// The anchor's face mesh, packed as `CaptureSession.pushFramePacked`
    /// takes it, in face-anchor coordinates.
    func packedVertices(of anchor: ARFaceAnchor) -> Data {
        ARKitGlue.packed(anchor.geometry.vertices)
    }
}
