import Foundation
import LikenessFFI

/// Hears the core's progress during the long steps (personalizing, building
/// the avatar) and tells the core when the person pressed Cancel.
///
/// Implements the core's `ProgressListener` protocol. The core calls it on
/// the thread that made the call (the core's thread, `CoreQueue`) while the
/// person may press Cancel on the main thread, or iOS may end the background
/// time, so the cancel flag sits behind a lock, and progress is handed to
/// `report`, which must hop to the main actor itself.
final class ProgressReporter: ProgressListener, @unchecked Sendable {
    private let lock = NSLock()
    private var cancelled = false
    private let report: @Sendable (_ stage: String, _ fraction: Double) -> Void

    /// - Parameter report: called with the core's stage name and how far it
    ///   is (0…1), on the core's thread.
    init(report: @escaping @Sendable (_ stage: String, _ fraction: Double) -> Void) {
        self.report = report
    }

    /// The person asked to stop: the core sees it at its next check and stops
    /// with `LikenessError.Cancelled`.
    func cancel() {
        lock.withLock { cancelled = true }
    }

    // MARK: ProgressListener

    func onProgress(stage: String, fraction: Double) {
        report(stage, fraction)
    }

    func isCancelled() -> Bool {
        lock.withLock { cancelled }
    }
}
