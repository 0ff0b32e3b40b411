import ARKit

/// ARKit's dictionary key for each of the core's blendshapes, without the app
/// spelling a single name.
///
/// The core names the 52 shapes as Apple's Swift constants do (`eyeBlinkLeft`,
/// `arkitNames()`) and gives ARKit's raw values for them in the same order
/// (`eyeBlink_L`, `arkitKeys()`): the keys of `ARFaceAnchor.blendShapes` and of
/// `ARFaceGeometry(blendShapes:)`. The app turns the raw values into keys and
/// checks them against what a real anchor reports, so a key ARKit does not
/// know fails loudly instead of reading as a weight of zero.
public struct BlendShapeKeys: Equatable {
    /// ARKit's key for each of the core's names, in the core's order.
    public let keys: [ARFaceAnchor.BlendShapeLocation]

    /// Why the core's keys and ARKit's did not agree.
    public enum MatchError: Error, Equatable, LocalizedError {
        /// Names whose key ARKit does not report.
        case missing([String])
        /// The core gave a different number of names and keys.
        case mismatched(names: Int, keys: Int)

        public var errorDescription: String? {
            switch self {
            case .missing(let names):
                return "ARKit reports no expression named \(names.joined(separator: ", "))."
            case .mismatched(let names, let keys):
                return "The core named \(names) expressions but gave \(keys) ARKit keys."
            }
        }
    }

    /// The keys of `rawKeys`, checked against `available`.
    ///
    /// - Parameters:
    ///   - names: the core's names, in its order (`arkitNames()`), for messages.
    ///   - rawKeys: ARKit's raw values in the same order (`arkitKeys()`).
    ///   - available: ARKit's keys, e.g. `Array(anchor.blendShapes.keys)`.
    /// - Throws: `MatchError` when the lists differ in length or ARKit lacks a key.
    public static func match(
        names: [String],
        rawKeys: [String],
        available: [ARFaceAnchor.BlendShapeLocation]
    ) throws -> BlendShapeKeys {
        guard names.count == rawKeys.count else {
            throw MatchError.mismatched(names: names.count, keys: rawKeys.count)
        }
        let keys = rawKeys.map { ARFaceAnchor.BlendShapeLocation(rawValue: $0) }
        let reported = Set(available)
        var missing: [String] = []
        for (name, key) in zip(names, keys) where !reported.contains(key) {
            missing.append(name)
        }
        if !missing.isEmpty {
            throw MatchError.missing(missing)
        }
        return BlendShapeKeys(keys: keys)
    }
}
