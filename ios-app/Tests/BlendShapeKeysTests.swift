import ARKit
import LikenessGlue
import XCTest

/// Pairing the core's names with ARKit's dictionary keys.
final class BlendShapeKeysTests: XCTestCase {
    private func key(_ rawValue: String) -> ARFaceAnchor.BlendShapeLocation {
        ARFaceAnchor.BlendShapeLocation(rawValue: rawValue)
    }

    func testSpellingReadsSideSuffixesAndIgnoresCase() {
        XCTAssertEqual(BlendShapeKeys.spelling(of: "fooBar_L"), "foobarleft")
        XCTAssertEqual(BlendShapeKeys.spelling(of: "fooBarRight"), "foobarright")
        XCTAssertEqual(BlendShapeKeys.spelling(of: "foo_bar_R"), "foobarright")
        XCTAssertEqual(BlendShapeKeys.spelling(of: "FooBar"), "foobar")
    }

    func testMatchPairsRawValuesWithNamesInTheCoreOrder() throws {
        let available = [key("eyeBlink_L"), key("jawOpen"), key("mouthLeft")]
        let matched = try BlendShapeKeys.match(names: ["jawOpen", "mouthLeft", "eyeBlinkLeft"], available: available)
        XCTAssertEqual(matched.keys.map(\.rawValue), ["jawOpen", "mouthLeft", "eyeBlink_L"])
    }

    func testARKitsOwnConstantMatchesTheCoreSpelling() throws {
        // The reason the app pairs by spelling: ARKit's raw value is not the name.
        let matched = try BlendShapeKeys.match(names: ["eyeBlinkLeft"], available: [.eyeBlinkLeft])
        XCTAssertEqual(matched.keys, [.eyeBlinkLeft])
    }

    func testMissingNamesAreReportedTogether() {
        XCTAssertThrowsError(
            try BlendShapeKeys.match(names: ["fooBarLeft", "bazQux"], available: [key("jawOpen")])
        ) { error in
            XCTAssertEqual(error as? BlendShapeKeys.MatchError, .missing(["fooBarLeft", "bazQux"]))
        }
    }

    func testTwoKeysSpellingOneNameAreAnError() {
        XCTAssertThrowsError(
            try BlendShapeKeys.match(names: ["fooBarLeft"], available: [key("fooBar_L"), key("fooBarLeft")])
        ) { error in
            XCTAssertEqual(error as? BlendShapeKeys.MatchError, .ambiguous("fooBarLeft"))
        }
    }

    func testErrorsDescribeThemselves() {
        XCTAssertEqual(
            BlendShapeKeys.MatchError.missing(["a", "b"]).errorDescription,
            "ARKit reports no expression named a, b.")
    }
}
