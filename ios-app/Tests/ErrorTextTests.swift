import ARKit
import LikenessGlue
import XCTest

/// The sentences shown when something goes wrong.
final class ErrorTextTests: XCTestCase {
    func testCoreFailuresEndWithTheCoresMessage() {
        for kind in ErrorText.CoreFailure.allCases where kind != .cancelled {
            let text = ErrorText.text(for: kind, detail: "prompt 7 has no frames")
            XCTAssertTrue(text.hasSuffix(" prompt 7 has no frames"), text)
        }
    }

    func testEveryCoreFailureHasItsOwnLead() {
        let leads = Set(ErrorText.CoreFailure.allCases.map { ErrorText.text(for: $0, detail: nil) })
        XCTAssertEqual(leads.count, ErrorText.CoreFailure.allCases.count)
    }

    func testCancellationIsPlain() {
        XCTAssertEqual(ErrorText.text(for: .cancelled, detail: nil), "Cancelled.")
        XCTAssertEqual(ErrorText.text(for: .file, detail: ""), ErrorText.text(for: .file, detail: nil))
    }

    func testCameraRefusalSaysWhereToAllowIt() {
        let text = ErrorText.text(for: ARError(.cameraUnauthorized))
        XCTAssertTrue(text.contains("Settings"), text)
    }

    func testOtherErrorsDescribeThemselves() {
        let error = NSError(domain: "test", code: 1, userInfo: [NSLocalizedDescriptionKey: "Disk full"])
        XCTAssertEqual(ErrorText.text(forOther: error), "Disk full")
        XCTAssertEqual(ErrorText.text(forOther: ARError(.cameraUnauthorized)), ErrorText.text(for: ARError(.cameraUnauthorized)))
    }
}
