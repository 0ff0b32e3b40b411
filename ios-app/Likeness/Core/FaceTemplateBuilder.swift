import ARKit
import LikenessFFI
import LikenessGlue

/// Builds the generic face the core personalizes, from ARKit's own face model:
/// its mesh at rest and at each of the 52 shapes at full weight.
///
/// `ARFaceGeometry(blendShapes:)` needs a phone that tracks faces; it makes
/// the same topology ARKit tracks, so the template, the frames and the core's
/// meshes all share one vertex numbering.
enum FaceTemplateBuilder {
    /// ARKit could not make its face model (a device without TrueDepth).
    struct Unavailable: LocalizedError {
        /// Which mesh failed.
        let shape: String
        var errorDescription: String? {
            "ARKit could not make its face model for \(shape)."
        }
    }

    /// The template: the neutral mesh (no weights), each of `names` at weight
    /// one in the core's order, and the triangles.
    static func build(names: [String], keys: BlendShapeKeys) throws -> FaceTemplate {
        guard let neutral = ARFaceGeometry(blendShapes: [:]) else {
            throw Unavailable(shape: "the neutral face")
        }
        var shapes: [[Float]] = []
        shapes.reserveCapacity(names.count)
        for (name, key) in zip(names, keys.keys) {
            guard let geometry = ARFaceGeometry(blendShapes: [key: NSNumber(value: Float(1))]) else {
                throw Unavailable(shape: name)
            }
            shapes.append(ARKitGlue.flatten(geometry.vertices))
        }
        return FaceTemplate(
            triangles: ARKitGlue.triangleIndices(neutral.triangleIndices),
            neutral: ARKitGlue.flatten(neutral.vertices),
            shapes: shapes)
    }
}
