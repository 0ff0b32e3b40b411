import ARKit

/// Pairs the core's blendshape names with the keys ARKit uses in
/// `ARFaceAnchor.blendShapes`, without the app spelling a single name.
///
/// The core names the 52 shapes as Apple's Swift constants do
/// (`eyeBlinkLeft`), and `arkitNames()` gives them in the core's order. ARKit's
/// dictionary keys, though, carry Objective-C raw values that abbreviate the
/// side (`ARFaceAnchor.BlendShapeLocation.eyeBlinkLeft.rawValue` is
/// `"eyeBlink_L"`), so `BlendShapeLocation(rawValue: name)` alone would find
/// nothing for most shapes. A key matches a name when both spell the same
/// words: compared without case and underscores, with a trailing `_L` / `_R`
/// read as `Left` / `Right` (the same reading the core's own name parser
/// applies). The keys come from a real anchor, so whatever ARKit calls them,
/// the app follows.
public struct BlendShapeKeys: Equatable {
    /// ARKit's key for each of the core's names, in the core's order.
    public let keys: [ARFaceAnchor.BlendShapeLocation]

    /// Why the names and ARKit's keys could not be paired one to one.
    public enum MatchError: Error, Equatable, LocalizedError {
        /// Names for which ARKit offers no key.
        case missing([String])
        /// A name that more than one of ARKit's keys spell.
        case ambiguous(String)

        public var errorDescription: String? {
            switch self {
            case .missing(let names):
                return "ARKit reports no expression named \(names.joined(separator: ", "))."
            case .ambiguous(let name):
                return "ARKit reports more than one expression named \(name)."
            }
        }
    }

    /// Pairs each of `names` with the one key in `available` that spells it.
    ///
    /// - Parameters:
    ///   - names: the core's names, in its order (`arkitNames()`).
    ///   - available: ARKit's keys, e.g. `Array(anchor.blendShapes.keys)`.
    /// - Throws: `MatchError` when a name has no key or more than one.
    public static func match(
        names: [String],
        available: [ARFaceAnchor.BlendShapeLocation]
    ) throws -> BlendShapeKeys {
        var bySpelling: [String: [ARFaceAnchor.BlendShapeLocation]] = [:]
        for key in available {
            bySpelling[spelling(of: key.rawValue), default: []].append(key)
        }
        var keys: [ARFaceAnchor.BlendShapeLocation] = []
        var missing: [String] = []
        for name in names {
            let candidates = bySpelling[spelling(of: name)] ?? []
            if candidates.count > 1 {
                throw MatchError.ambiguous(name)
            }
            if let key = candidates.first {
                keys.append(key)
            } else {
                missing.append(name)
            }
        }
        if !missing.isEmpty {
            throw MatchError.missing(missing)
        }
        return BlendShapeKeys(keys: keys)
    }

    /// The words a name spells: lower case, without underscores, with a
    /// trailing `_l` / `_r` written out as `left` / `right`.
    public static func spelling(of text: String) -> String {
        var lowered = text.lowercased()
        if lowered.hasSuffix("_l") {
            lowered = String(lowered.dropLast(2)) + "left"
        } else if lowered.hasSuffix("_r") {
            lowered = String(lowered.dropLast(2)) + "right"
        }
        return lowered.replacingOccurrences(of: "_", with: "")
    }
}
