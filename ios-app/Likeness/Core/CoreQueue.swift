import Foundation

/// The one thread on which the app calls into the core.
///
/// Every call into the Rust core runs on a dedicated `Thread` with an 8 MiB
/// stack (`stackSize`): the core's longest calls (personalizing, reading and
/// writing an avatar) go deeper than the 512 KiB a dispatch queue's worker
/// threads have. Jobs reach that thread through one first-in-first-out list,
/// so a capture's frames, skips, retakes and interruptions reach the core in
/// the order they happened, off the main thread. Results go to the screen
/// with `onMain`, in order.
///
/// ARKit cannot deliver on a `Thread` of ours: it delivers on a dispatch
/// queue, where the app reads each frame into plain values and sends them
/// here with `async`.
enum CoreQueue {
    /// The core thread's stack size: 8 MiB.
    static let stackSize = 8 << 20

    private static let worker = CoreThread(name: "org.likeness.core", stackSize: stackSize)

    /// Runs `job` on the core's thread, after every job sent before it.
    static func async(_ job: @escaping () -> Void) {
        worker.enqueue(job)
    }

    /// Runs `body` on the main actor after everything sent there before it
    /// (`DispatchQueue.main` keeps the order; a `Task` would not promise it).
    static func onMain(_ body: @escaping @MainActor () -> Void) {
        DispatchQueue.main.async {
            MainActor.assumeIsolated(body)
        }
    }

    /// Runs `body` on the main actor after `seconds`.
    static func onMain(after seconds: Double, _ body: @escaping @MainActor () -> Void) {
        DispatchQueue.main.asyncAfter(deadline: .now() + seconds) {
            MainActor.assumeIsolated(body)
        }
    }
}

/// A thread that runs the jobs it is given, one at a time, in order, for the
/// life of the app.
final class CoreThread: @unchecked Sendable {
    private let condition = NSCondition()
    private var jobs: [() -> Void] = []

    /// Starts the thread.
    init(name: String, stackSize: Int) {
        let thread = Thread { [self] in run() }
        thread.name = name
        thread.stackSize = stackSize
        thread.qualityOfService = .userInitiated
        thread.start()
    }

    /// Adds `job` to the end of the list. Callable from any thread.
    func enqueue(_ job: @escaping () -> Void) {
        condition.lock()
        jobs.append(job)
        condition.signal()
        condition.unlock()
    }

    private func run() {
        while true {
            condition.lock()
            while jobs.isEmpty {
                condition.wait()
            }
            let batch = jobs
            jobs.removeAll(keepingCapacity: true)
            condition.unlock()
            for job in batch {
                // A thread of our own has no autorelease pool draining
                // between jobs; ARKit and Foundation objects would pile up.
                autoreleasepool { job() }
            }
        }
    }
}
