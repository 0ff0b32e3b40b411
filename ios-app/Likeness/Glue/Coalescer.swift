import Foundation

/// Hands a stream of float arrays (live weights, posed vertices) to a slower
/// consumer, keeping only the latest.
///
/// ARKit delivers 60 weight arrays a second; drawing or posing one may take
/// longer. `offer` stores the value under a lock and, if no update is in
/// flight, schedules one (on the main queue, on the core's thread, wherever
/// `schedule` sends it). That update applies whatever is latest when it runs,
/// and schedules one more if a newer value came meanwhile: at most one update
/// is in flight, none queues up behind it, and the latest value is always
/// applied.
public final class Coalescer: @unchecked Sendable {
    /// Runs a job later on the consumer's queue or thread.
    public typealias Schedule = (@escaping () -> Void) -> Void

    private let lock = NSLock()
    private var latest: [Float]?
    private var inFlight = false
    private let schedule: Schedule
    private let apply: ([Float]) -> Void

    /// - Parameters:
    ///   - schedule: runs a job on the consumer's queue or thread.
    ///   - apply: consumes one value, there.
    public init(schedule: @escaping Schedule, apply: @escaping ([Float]) -> Void) {
        self.schedule = schedule
        self.apply = apply
    }

    /// Keeps `value` as the latest, replacing any not yet applied, and
    /// schedules an update unless one is in flight. Callable from any thread.
    public func offer(_ value: [Float]) {
        let startsUpdate: Bool = lock.withLock {
            latest = value
            if inFlight {
                return false
            }
            inFlight = true
            return true
        }
        if startsUpdate {
            schedule { self.drain() }
        }
    }

    /// Whether an update is scheduled or running (for tests).
    public var isInFlight: Bool {
        lock.withLock { inFlight }
    }

    private func drain() {
        let value: [Float]? = lock.withLock {
            let value = latest
            latest = nil
            return value
        }
        if let value {
            apply(value)
        }
        let again: Bool = lock.withLock {
            if latest == nil {
                inFlight = false
                return false
            }
            return true
        }
        if again {
            schedule { self.drain() }
        }
    }
}
