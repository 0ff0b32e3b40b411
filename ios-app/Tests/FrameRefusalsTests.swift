import LikenessGlue
import XCTest

/// One refused frame is dropped; a run of them stops the capture.
final class FrameRefusalsTests: XCTestCase {
    func testOnlyARunOfRefusalsStops() {
        var refusals = FrameRefusals()
        for _ in 1..<FrameRefusals.stopAfterInARow {
            XCTAssertFalse(refusals.refused())
        }
        XCTAssertTrue(refusals.refused())
        XCTAssertEqual(refusals.total, FrameRefusals.stopAfterInARow)
    }

    func testAnAcceptedFrameEndsTheRun() {
        var refusals = FrameRefusals()
        for _ in 1..<FrameRefusals.stopAfterInARow {
            _ = refusals.refused()
        }
        refusals.accepted()
        XCTAssertEqual(refusals.inARow, 0)
        XCTAssertFalse(refusals.refused())
        XCTAssertEqual(refusals.total, FrameRefusals.stopAfterInARow)
    }
}
