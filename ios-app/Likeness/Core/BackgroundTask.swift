import UIKit

/// Asks iOS for time to finish a long step after the person leaves the app
/// (`UIApplication.beginBackgroundTask`), and gives it back when the step
/// ends (`endBackgroundTask`).
@MainActor
final class BackgroundTask {
    private var identifier: UIBackgroundTaskIdentifier = .invalid

    /// Begins the task; if iOS runs out of time for it, `onExpiry` is called
    /// (on the main thread) to stop the step, and the task ends.
    func begin(name: String, onExpiry: @escaping @MainActor () -> Void) {
        end()
        identifier = UIApplication.shared.beginBackgroundTask(withName: name) { [weak self] in
            MainActor.assumeIsolated {
                onExpiry()
                self?.end()
            }
        }
    }

    /// Ends the task, if one is under way.
    func end() {
        guard identifier != .invalid else { return }
        UIApplication.shared.endBackgroundTask(identifier)
        identifier = .invalid
    }
}
