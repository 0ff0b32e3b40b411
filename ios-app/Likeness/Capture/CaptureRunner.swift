import Foundation
import LikenessFFI
import LikenessGlue

/// The capture on the core's side: one `CaptureSession`, and everything the
/// camera (or the demo's recording) and the person send it, in order.
///
/// Every method runs on `CoreQueue`'s thread. A `FrameFeed` sends frames; the
/// capture screen sends skips, retakes, interruptions and the confirmation.
/// The core's answers go to the screen as `CaptureUpdate`s. Which prompt
/// comes next, when a face counts, what is wrong with a capture: all the
/// core's. The runner only carries, and keeps the order: timestamps pushed
/// strictly increase, no frame is pushed while the person reviews, and a
/// capture that reaches its length limit is saved at once.
final class CaptureRunner: @unchecked Sendable {
    private enum Phase {
        case waiting, capturing, reviewing, ended
    }

    private var phase = Phase.waiting
    private var core: CaptureSession?
    /// The session once `finish` made it (kept if saving it failed).
    private var finished: SessionHandle?
    private var lastWeights: [Float]?
    private var lastTimestamp = -TimeInterval.infinity
    private var interrupted = false
    private var refusals = FrameRefusals()
    private let deliver: @MainActor (CaptureUpdate) -> Void

    /// - Parameter deliver: receives every update, on the main actor, in order.
    init(deliver: @escaping @MainActor (CaptureUpdate) -> Void) {
        self.deliver = deliver
    }

    /// Sets the core up with the template `makeTemplate` gives (ARKit's face
    /// model, or the recording's) and starts the neutral scan.
    func begin(device: String, template makeTemplate: () throws -> FaceTemplate) {
        guard phase == .waiting else { return }
        send(.preparing)
        do {
            let template = try makeTemplate()
            let session = try CaptureSession(template: template, device: device)
            core = session
            phase = .capturing
            send(.started(triangles: template.triangles))
            try answer(try session.start(), from: session)
        } catch {
            fail(error)
        }
    }

    /// Pushes one frame. A frame without a tracked face goes as untracked,
    /// with the last weights pushed (zeros before any), so the core pauses.
    /// A refused frame is dropped with a passing notice; a run of them
    /// (`FrameRefusals`) ends the capture with the core's message.
    func push(_ frame: CaptureFrame) {
        guard phase == .capturing, let core, frame.timestamp > lastTimestamp else { return }
        lastTimestamp = frame.timestamp
        interrupted = false
        let weights = frame.weights ?? lastWeights ?? [Float](repeating: 0, count: arkitNames().count)
        let events: [CaptureEvent]
        do {
            events = try core.pushFramePacked(
                timestamp: frame.timestamp, weights: weights, vertices: frame.vertices, tracked: frame.tracked)
        } catch {
            let message = CoreErrors.message(for: error)
            if refusals.refused() {
                fail(message: message)
            } else {
                send(.frameRefused(message))
            }
            return
        }
        refusals.accepted()
        lastWeights = weights
        answerOrFail(events, from: core)
    }

    /// Skips the prompt under way; a refusal is only reported.
    func skip() {
        guard phase == .capturing, let core else { return }
        let events: [CaptureEvent]
        do {
            events = try core.skip()
        } catch {
            send(.refused(CoreErrors.message(for: error)))
            return
        }
        answerOrFail(events, from: core)
    }

    /// Asks for the step at `index` (`Prompt.index`) again, during the
    /// capture or from the review; a refusal is only reported.
    func retake(index: UInt32) {
        guard phase == .capturing || phase == .reviewing, let core else { return }
        let events: [CaptureEvent]
        do {
            events = try core.retake(index: index)
        } catch {
            send(.refused(CoreErrors.message(for: error)))
            return
        }
        if phase == .reviewing {
            phase = .capturing
            interrupted = false
            send(.retaking)
        }
        answerOrFail(events, from: core)
    }

    /// The capture was interrupted (the camera, the app, the phone went
    /// away): the core starts the step under way again. Told once per
    /// interruption, however many notices announce it.
    func interrupt() {
        guard phase == .capturing, let core, !interrupted else { return }
        interrupted = true
        let events: [CaptureEvent]
        do {
            events = try core.interrupt()
        } catch {
            fail(error)
            return
        }
        send(.interrupted)
        answerOrFail(events, from: core)
    }

    /// The person confirmed the review: the session is made and saved.
    func confirm() {
        guard phase == .reviewing, let core else { return }
        do {
            let saved = try save(core)
            phase = .ended
            send(.saved(saved))
        } catch {
            send(.saveRefused(CoreErrors.message(for: error)))
        }
    }

    /// Ends the capture with `error` in words.
    func fail(_ error: Error) {
        fail(message: CoreErrors.message(for: error))
    }

    /// Ends the capture with `message`.
    func fail(message: String) {
        guard phase != .ended else { return }
        phase = .ended
        send(.failed(message))
    }

    /// Ignores everything from now on (the person left the capture).
    func stop() {
        phase = .ended
    }

    // MARK: Answers

    private func answerOrFail(_ events: [CaptureEvent], from core: CaptureSession) {
        do {
            try answer(events, from: core)
        } catch {
            fail(error)
        }
    }

    /// Sends `events` with the progress after them, a picture for each new
    /// prompt, and the review once the core says no step is left.
    private func answer(_ events: [CaptureEvent], from core: CaptureSession) throws {
        guard !events.isEmpty else { return }
        let progress = try core.progress()
        send(.events(events, progress))
        var limitMessage: String?
        for event in events {
            switch event {
            case .promptStarted(let prompt):
                // A prompt without a picture is still asked for.
                let picture = try? core.promptPreview(index: prompt.index)
                send(.preview(promptIndex: prompt.index, vertices: picture))
            case .limitReached(_, let message):
                limitMessage = message
            default:
                break
            }
        }
        if phase == .capturing, try core.isFinished() {
            try review(core, progress: progress, limitMessage: limitMessage)
        }
    }

    private func review(_ core: CaptureSession, progress: CaptureProgress, limitMessage: String?) throws {
        phase = .reviewing
        let captures = try core.captures()
        var saved: SavedSession?
        if progress.endedAtLimit {
            // No retake is possible after the limit: keep what there is now.
            saved = try save(core)
        }
        send(.review(CaptureReview(captures: captures, progress: progress, limitMessage: limitMessage, saved: saved)))
    }

    private func save(_ core: CaptureSession) throws -> SavedSession {
        let handle = try finished ?? core.finish()
        finished = handle
        return try SavedSession.saveUnprocessed(handle)
    }

    private func send(_ update: CaptureUpdate) {
        let deliver = self.deliver
        CoreQueue.onMain { deliver(update) }
    }
}
