import LikenessGlue
import XCTest

/// Live values handed on: at most one update in flight, the latest applied.
final class CoalescerTests: XCTestCase {
    /// A consumer queue run by hand: jobs wait until `runNext`.
    private final class ManualQueue {
        var jobs: [() -> Void] = []
        func schedule(_ job: @escaping () -> Void) { jobs.append(job) }
        func runNext() { jobs.removeFirst()() }
    }

    func testManyOffersBeforeTheConsumerRunsApplyOnlyTheLatest() {
        let queue = ManualQueue()
        var applied: [[Float]] = []
        let coalescer = Coalescer(schedule: queue.schedule) { applied.append($0) }
        coalescer.offer([1])
        coalescer.offer([2])
        coalescer.offer([3])
        XCTAssertEqual(queue.jobs.count, 1, "one update in flight, not three")
        queue.runNext()
        XCTAssertEqual(applied, [[3]])
        XCTAssertTrue(queue.jobs.isEmpty)
        XCTAssertFalse(coalescer.isInFlight)
    }

    func testAValueOfferedWhileApplyingIsAppliedNext() {
        let queue = ManualQueue()
        var applied: [[Float]] = []
        var coalescer: Coalescer?
        coalescer = Coalescer(schedule: queue.schedule) { value in
            applied.append(value)
            if value == [1] {
                // A newer value arrives while the first is being applied.
                coalescer?.offer([2])
                coalescer?.offer([4])
            }
        }
        coalescer?.offer([1])
        queue.runNext()
        XCTAssertEqual(queue.jobs.count, 1)
        queue.runNext()
        XCTAssertEqual(applied, [[1], [4]])
        XCTAssertEqual(coalescer?.isInFlight, false)
    }

    func testAnOfferAfterTheUpdateSchedulesAgain() {
        let queue = ManualQueue()
        var applied: [[Float]] = []
        let coalescer = Coalescer(schedule: queue.schedule) { applied.append($0) }
        coalescer.offer([1])
        queue.runNext()
        coalescer.offer([2])
        queue.runNext()
        XCTAssertEqual(applied, [[1], [2]])
    }
}
