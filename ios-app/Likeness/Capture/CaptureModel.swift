import ARKit
import LikenessFFI
import Observation
import SceneKit

/// What the capture and review screens show, kept up to date from the core's
/// answers, and the person's choices sent back to it.
@MainActor @Observable
final class CaptureModel {
    /// Where the capture stands.
    enum Stage: Equatable {
        /// The camera runs (the demo loads its recording); no face yet.
        case lookingForFace
        /// A face was found; the core is being set up.
        case preparing
        /// The core is asking for expressions.
        case capturing
        /// No step is left: the person checks the captures.
        case reviewing
        /// The person confirmed; the session is being made and saved.
        case saving
        /// The capture stopped, with the reason in words.
        case failed(String)
    }

    private(set) var stage: Stage = .lookingForFace
    /// The prompt the person is asked to make now.
    private(set) var prompt: Prompt? = nil
    /// Captured / skipped / total, as the core counts them.
    private(set) var progress: CaptureProgress? = nil
    /// The most recently captured prompt (what "Retake last" takes again).
    private(set) var lastCaptured: Prompt? = nil
    /// The core's quality warnings about the last capture.
    private(set) var captureWarnings: [String] = []
    /// A one-off message: a skipped prompt, a refused retake, an interruption.
    private(set) var notice: String? = nil
    /// A frame the core refused and the app dropped, shown for a moment.
    private(set) var frameNotice: String? = nil
    /// Tracking is lost: the core waits until the face is back.
    private(set) var isPaused: Bool = false
    /// Whether `previewNode` shows the current prompt's expression.
    private(set) var hasPreview: Bool = false
    /// The captures to review, once no step is left.
    private(set) var review: CaptureReview? = nil
    /// Why the session could not be made or saved, or a retake was refused,
    /// shown on the review.
    private(set) var reviewProblem: String? = nil
    /// Whether this is the demo (a recorded capture replayed).
    let isDemo: Bool

    /// The picture of the current expression; its geometry changes per prompt.
    let previewNode = SCNNode()
    @ObservationIgnored private var triangles: [UInt32] = []
    @ObservationIgnored private var runner: CaptureRunner?
    @ObservationIgnored private var feed: FrameFeed?
    @ObservationIgnored private var demo: DemoFeed?
    private let lifecycle = AppLifecycle()
    @ObservationIgnored private var started = false
    @ObservationIgnored private var frameNoticeCount = 0
    private let onSaved: (SavedSession) -> Void

    /// - Parameters:
    ///   - demo: replay the bundled recording instead of using the camera.
    ///   - onSaved: called once the confirmed capture is saved.
    init(demo: Bool, onSaved: @escaping (SavedSession) -> Void) {
        isDemo = demo
        self.onSaved = onSaved
        let runner = CaptureRunner { [weak self] update in
            self?.apply(update)
        }
        self.runner = runner
        if demo {
            let replay = DemoFeed(runner: runner)
            self.demo = replay
            feed = replay
        } else {
            feed = CameraFeed(runner: runner)
        }
    }

    /// The ARKit session for the camera view (`nil` in the demo).
    var arSession: ARSession? { feed?.arSession }

    /// Starts the camera (or the replay), once.
    func start() {
        guard !started else { return }
        started = true
        lifecycle.start(
            onAway: { [weak self] in self?.wentAway() },
            onBack: { [weak self] in self?.cameBack() })
        feed?.start()
    }

    /// Stops everything (leaving the screen).
    func stop() {
        lifecycle.stop()
        feed?.stop()
        send { $0.stop() }
    }

    /// Skips the current prompt.
    func skip() {
        notice = nil
        send { $0.skip() }
    }

    /// Asks for the last captured prompt again.
    func retakeLast() {
        guard let lastCaptured else { return }
        retake(index: lastCaptured.index)
    }

    /// Asks for the step at `index` again (from the capture or the review).
    func retake(index: UInt32) {
        notice = nil
        reviewProblem = nil
        captureWarnings = []
        send { $0.retake(index: index) }
    }

    /// The person confirmed the review: make and save the session, then
    /// process it.
    func confirm() {
        reviewProblem = nil
        if let saved = review?.saved {
            onSaved(saved)
            return
        }
        stage = .saving
        send { $0.confirm() }
    }

    private func send(_ call: @escaping (CaptureRunner) -> Void) {
        guard let runner else { return }
        CoreQueue.async { call(runner) }
    }

    // MARK: The app going away and coming back

    private var isTakingFrames: Bool {
        switch stage {
        case .lookingForFace, .preparing, .capturing:
            return true
        case .reviewing, .saving, .failed:
            return false
        }
    }

    private func wentAway() {
        guard isTakingFrames else { return }
        feed?.pause()
        send { $0.interrupt() }
    }

    private func cameBack() {
        guard isTakingFrames else { return }
        feed?.resume()
    }

    // MARK: The core's answers

    private func apply(_ update: CaptureUpdate) {
        switch update {
        case .preparing:
            stage = .preparing
        case .started(let triangles):
            self.triangles = triangles
            stage = .capturing
        case .events(let events, let progress):
            self.progress = progress
            for event in events {
                handle(event)
            }
        case .preview(let promptIndex, let vertices):
            guard prompt?.index == promptIndex else { return }
            previewNode.geometry = vertices.flatMap { MeshGeometry.make(vertices: $0, triangles: triangles) }
            hasPreview = previewNode.geometry != nil
        case .interrupted:
            notice = "The capture was interrupted; this expression starts again."
        case .refused(let message):
            if stage == .reviewing {
                reviewProblem = message
            } else {
                notice = message
            }
        case .frameRefused(let message):
            showFrameNotice(message)
        case .review(let review):
            self.review = review
            isPaused = false
            stage = .reviewing
            feed?.pause()
        case .retaking:
            review = nil
            stage = .capturing
            feed?.resume()
        case .saved(let saved):
            onSaved(saved)
        case .saveRefused(let message):
            reviewProblem = message
            stage = .reviewing
        case .failed(let message):
            isPaused = false
            stage = .failed(message)
            feed?.stop()
        }
    }

    private func handle(_ event: CaptureEvent) {
        switch event {
        case .promptStarted(let prompt):
            self.prompt = prompt
            hasPreview = false
            previewNode.geometry = nil
        case .captured(let prompt, let warnings):
            lastCaptured = prompt
            captureWarnings = warnings
        case .skipped(let prompt, let reason):
            notice = "Skipped “\(prompt.instruction)”: \(reason)"
        case .trackingLost:
            isPaused = true
        case .trackingResumed:
            isPaused = false
        case .limitReached(_, let message):
            notice = message
        case .finished:
            isPaused = false
        }
    }

    /// Shows `message` for a moment; a newer one replaces it and restarts
    /// the moment.
    private func showFrameNotice(_ message: String) {
        frameNoticeCount += 1
        let shown = frameNoticeCount
        frameNotice = message
        CoreQueue.onMain(after: Theme.noticeSeconds) { [weak self] in
            guard let self, self.frameNoticeCount == shown else { return }
            self.frameNotice = nil
        }
    }
}
