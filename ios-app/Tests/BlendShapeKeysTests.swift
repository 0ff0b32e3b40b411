import ARKit
import LikenessGlue
import XCTest

/// The core's raw keys as ARKit's dictionary keys.
final class BlendShapeKeysTests: XCTestCase {
    private func key(_ rawValue: String) -> ARFaceAnchor.BlendShapeLocation {
        ARFaceAnchor.BlendShapeLocation(rawValue: rawValue)
    }

    func testRawKeysBecomeKeysInTheCoreOrder() throws {
        let available = [key("eyeBlink_L"), key("jawOpen"), key("mouthLeft")]
        let matched = try BlendShapeKeys.match(
            names: ["jawOpen", "mouthLeft", "eyeBlinkLeft"],
            rawKeys: ["jawOpen", "mouthLeft", "eyeBlink_L"],
            available: available)
        XCTAssertEqual(matched.keys.map(\.rawValue), ["jawOpen", "mouthLeft", "eyeBlink_L"])
    }

    func testARKitsOwnConstantIsTheRawKey() throws {
        // Why the core gives raw keys: ARKit's raw value is not the name.
        let matched = try BlendShapeKeys.match(
            names: ["eyeBlinkLeft"], rawKeys: ["eyeBlink_L"], available: [.eyeBlinkLeft])
        XCTAssertEqual(matched.keys, [.eyeBlinkLeft])
    }

    func testKeysARKitDoesNotReportAreNamedTogether() {
        XCTAssertThrowsError(
            try BlendShapeKeys.match(
                names: ["fooBarLeft", "bazQux"], rawKeys: ["fooBar_L", "bazQux"],
                available: [key("jawOpen")])
        ) { error in
            XCTAssertEqual(error as? BlendShapeKeys.MatchError, .missing(["fooBarLeft", "bazQux"]))
        }
    }

    func testNamesAndKeysOfDifferentLengthsAreAnError() {
        XCTAssertThrowsError(
            try BlendShapeKeys.match(names: ["a", "b"], rawKeys: ["a"], available: [key("a")])
        ) { error in
            XCTAssertEqual(error as? BlendShapeKeys.MatchError, .mismatched(names: 2, keys: 1))
        }
    }

    func testErrorsDescribeThemselves() {
        XCTAssertEqual(
            BlendShapeKeys.MatchError.missing(["a", "b"]).errorDescription,
            "ARKit reports no expression named a, b.")
    }
}
