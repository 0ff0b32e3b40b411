import LikenessGlue
import XCTest

/// A recording replayed at its own speed, and over again.
final class ReplayScheduleTests: XCTestCase {
    func testAFrameIsDueAsLongAfterTheStartAsInTheRecording() {
        var schedule = ReplaySchedule(first: 0, second: 0.5, last: 10)
        schedule.start(recordedTime: 2, uptime: 100)
        XCTAssertEqual(schedule.delay(until: 2, now: 100), 0)
        XCTAssertEqual(schedule.delay(until: 3, now: 100), 1)
        XCTAssertEqual(schedule.delay(until: 3, now: 100.25), 0.75)
        XCTAssertLessThan(schedule.delay(until: 3, now: 102), 0, "late: push at once")
    }

    func testLaterPassesMoveTheTimestampsOn() {
        let schedule = ReplaySchedule(first: 0, second: 0.5, last: 10)
        XCTAssertEqual(schedule.loopLength, 10.5)
        XCTAssertEqual(schedule.timestamp(of: 0, pass: 0), 0)
        XCTAssertEqual(schedule.timestamp(of: 0, pass: 1), 10.5, "after the last frame, one interval on")
        XCTAssertEqual(schedule.timestamp(of: 10, pass: 2), 31)
    }

    func testASingleFrameDoesNotRepeat() {
        let schedule = ReplaySchedule(first: 3, second: nil, last: 3)
        XCTAssertNil(schedule.loopLength)
        XCTAssertEqual(schedule.timestamp(of: 3, pass: 0), 3)
        XCTAssertNil(schedule.timestamp(of: 3, pass: 1))
    }
}
