import Foundation
import UIKit

/// Tells a screen when the app goes away (it resigns active, goes to the
/// background, or the phone locks and protected data becomes unavailable)
/// and when it is back (active again).
@MainActor
final class AppLifecycle {
    private var observers: [Any] = []

    /// Starts listening; `onAway` may be called several times for one
    /// absence (resigning active, then the background), `onBack` once it ends.
    func start(onAway: @escaping @MainActor () -> Void, onBack: @escaping @MainActor () -> Void) {
        stop()
        let center = NotificationCenter.default
        let away = [
            UIApplication.willResignActiveNotification,
            UIApplication.didEnterBackgroundNotification,
            UIApplication.protectedDataWillBecomeUnavailableNotification,
        ]
        for name in away {
            observers.append(center.addObserver(forName: name, object: nil, queue: .main) { _ in
                MainActor.assumeIsolated { onAway() }
            })
        }
        observers.append(center.addObserver(
            forName: UIApplication.didBecomeActiveNotification, object: nil, queue: .main
        ) { _ in
            MainActor.assumeIsolated { onBack() }
        })
    }

    /// Stops listening.
    func stop() {
        for observer in observers {
            NotificationCenter.default.removeObserver(observer)
        }
        observers = []
    }
}
