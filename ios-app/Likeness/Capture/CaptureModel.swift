import ARKit
import LikenessFFI
import Observation
import SceneKit

/// What the capture screen shows, kept up to date from the core's events.
@MainActor @Observable
final class CaptureModel {
    /// Where the capture stands.
    enum Stage: Equatable {
        /// The camera runs; no face yet.
        case lookingForFace
        /// A face was found; the core is being set up.
        case preparing
        /// The core is asking for expressions.
        case capturing
        /// All prompts done; the session is being saved.
        case finishing
        /// The capture stopped, with the reason in words.
        case failed(String)
    }

    private(set) var stage: Stage = .lookingForFace
    /// The prompt the person is asked to make now.
    private(set) var prompt: Prompt? = nil
    /// Captured / skipped / total, as the core counts them.
    private(set) var progress: CaptureProgress? = nil
    /// The most recently captured prompt (what "Retake" takes again).
    private(set) var lastCaptured: Prompt? = nil
    /// The core's quality warnings about the last capture.
    private(set) var captureWarnings: [String] = []
    /// A one-off message: a skipped prompt, a refused retake.
    private(set) var notice: String? = nil
    /// Tracking is lost: the core waits until the face is back.
    private(set) var isPaused: Bool = false
    /// Whether `previewNode` shows the current prompt's expression.
    private(set) var hasPreview: Bool = false

    /// The picture of the current expression; its geometry changes per prompt.
    let previewNode = SCNNode()
    @ObservationIgnored private var triangles: [UInt32] = []
    @ObservationIgnored private var driver: CaptureDriver?
    private let onSaved: (SavedSession) -> Void

    /// - Parameter onSaved: called once the finished capture is saved.
    init(onSaved: @escaping (SavedSession) -> Void) {
        self.onSaved = onSaved
        driver = CaptureDriver { [weak self] update in
            self?.apply(update)
        }
    }

    /// The ARKit session for the camera view.
    var arSession: ARSession? { driver?.arSession }

    /// Starts the camera.
    func start() {
        driver?.run()
    }

    /// Stops the camera (leaving the screen).
    func stop() {
        driver?.stop()
    }

    /// Skips the current prompt.
    func skip() {
        notice = nil
        driver?.skip()
    }

    /// Asks for the last captured prompt again.
    func retakeLast() {
        guard let lastCaptured else { return }
        notice = nil
        captureWarnings = []
        driver?.retake(promptIndex: lastCaptured.index)
    }

    private func apply(_ update: CaptureDriver.Update) {
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
        case .refused(let message):
            notice = message
        case .saved(let saved):
            onSaved(saved)
        case .failed(let message):
            isPaused = false
            stage = .failed(message)
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
        case .finished:
            isPaused = false
            stage = .finishing
        }
    }
}
