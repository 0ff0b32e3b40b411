import Foundation

/// The one serial queue on which the app calls into the core.
///
/// The core's objects are thread-safe, but a capture is a sequence: frames,
/// skips and retakes must reach it in the order they happened. ARKit delivers
/// its frames on this queue too (`ARSession.delegateQueue`), so a frame is
/// read and handed to the core in one step, off the main thread.
enum CoreQueue {
    /// The queue itself.
    static let queue = DispatchQueue(label: "org.likeness.core", qos: .userInitiated)

    /// Runs `body` on the main actor after everything sent there before it
    /// (`DispatchQueue.main` keeps the order; a `Task` would not promise it).
    static func onMain(_ body: @escaping @MainActor () -> Void) {
        DispatchQueue.main.async {
            MainActor.assumeIsolated(body)
        }
    }
}
