import ARKit
import LikenessFFI
import LikenessGlue

/// Drives the core's guided capture from ARKit, one frame at a time.
///
/// ARKit delivers its frames on `CoreQueue`; each one is read into weights and
/// vertices and pushed to the core's `CaptureSession`, and the core's events
/// go to the screen. The first face ARKit finds sets the core up: ARKit's
/// blendshape keys are paired with the core's names and ARKit's face model
/// becomes the core's template. Every decision (what to ask, when a face
/// counts, what is wrong with it) is the core's; this class only carries.
final class CaptureDriver: NSObject, ARSessionDelegate, @unchecked Sendable {
    /// What the driver tells the capture screen, on the main actor.
    enum Update {
        /// A face was found; the core is being set up.
        case preparing
        /// The core is ready; `triangles` are its template's, for pictures.
        case started(triangles: [UInt32])
        /// The core's events for one step and its progress after them.
        case events([CaptureEvent], CaptureProgress)
        /// The template at a prompt's expression (`nil`: no picture).
        case preview(promptIndex: UInt32, vertices: [Float]?)
        /// A skip or retake the core refused, in words.
        case refused(String)
        /// The capture is complete and saved.
        case saved(SavedSession)
        /// The capture cannot go on, in words.
        case failed(String)
    }

    /// The session the camera view shows. Its delegate calls arrive on
    /// `CoreQueue`.
    let arSession = ARSession()

    // Touched on CoreQueue only.
    private let reader: FaceFrameReader
    private var core: CaptureSession?
    private var lastWeights: [Float] = []
    private var lastVertices = Data()
    private var lastTimestamp = -TimeInterval.infinity
    private var stopped = false
    private let deliver: @MainActor (Update) -> Void

    /// - Parameter deliver: receives every update, on the main actor, in order.
    init(deliver: @escaping @MainActor (Update) -> Void) {
        reader = FaceFrameReader(names: arkitNames(), rawKeys: arkitKeys())
        self.deliver = deliver
        super.init()
        arSession.delegate = self
        arSession.delegateQueue = CoreQueue.queue
    }

    /// Starts the front camera and face tracking. ARKit asks for camera
    /// access the first time.
    func run() {
        let configuration = ARFaceTrackingConfiguration()
        configuration.isLightEstimationEnabled = true
        arSession.run(configuration, options: [.resetTracking, .removeExistingAnchors])
    }

    /// Stops the camera and ignores whatever ARKit still delivers.
    func stop() {
        arSession.pause()
        CoreQueue.queue.async { self.stopped = true }
    }

    /// Skips the current prompt.
    func skip() {
        CoreQueue.queue.async {
            self.step(refusalIsFatal: false) { (core: CaptureSession) in try core.skip() }
        }
    }

    /// Asks for the prompt at `promptIndex` again.
    func retake(promptIndex: UInt32) {
        CoreQueue.queue.async {
            self.step(refusalIsFatal: false) { (core: CaptureSession) in try core.retake(index: promptIndex) }
        }
    }

    // MARK: ARSessionDelegate (on CoreQueue)

    func session(_ session: ARSession, didUpdate anchors: [ARAnchor]) {
        guard !stopped,
              let anchor = anchors.lazy.compactMap({ $0 as? ARFaceAnchor }).first,
              let timestamp = session.currentFrame?.timestamp,
              timestamp > lastTimestamp
        else { return }
        do {
            if core == nil {
                try startCore(with: anchor)
            }
            lastWeights = try reader.weights(of: anchor)
            lastVertices = reader.packedVertices(of: anchor)
        } catch {
            fail(error)
            return
        }
        push(timestamp: timestamp, tracked: anchor.isTracked)
    }

    func session(_ session: ARSession, didRemove anchors: [ARAnchor]) {
        // The face left for good: the core hears an untracked frame and pauses.
        guard !stopped, core != nil, !lastWeights.isEmpty,
              anchors.contains(where: { $0 is ARFaceAnchor }),
              let timestamp = session.currentFrame?.timestamp,
              timestamp > lastTimestamp
        else { return }
        push(timestamp: timestamp, tracked: false)
    }

    func session(_ session: ARSession, didFailWithError error: Error) {
        guard !stopped else { return }
        fail(error)
    }

    // MARK: Steps (on CoreQueue)

    private func startCore(with anchor: ARFaceAnchor) throws {
        send(.preparing)
        let keys = try reader.blendShapeKeys(for: anchor)
        let template = try FaceTemplateBuilder.build(names: reader.names, keys: keys)
        let session = try CaptureSession(template: template, device: DeviceModel.identifier)
        core = session
        send(.started(triangles: template.triangles))
        step(refusalIsFatal: true) { (core: CaptureSession) in try core.start() }
    }

    private func push(timestamp: TimeInterval, tracked: Bool) {
        lastTimestamp = timestamp
        let weights = lastWeights
        let vertices = lastVertices
        step(refusalIsFatal: true) { (core: CaptureSession) in
            try core.pushFramePacked(timestamp: timestamp, weights: weights, vertices: vertices, tracked: tracked)
        }
    }

    /// One call into the core; its events go to the screen, with a picture
    /// for each new prompt. A refused frame ends the capture; a refused skip
    /// or retake is only reported.
    private func step(refusalIsFatal: Bool, _ call: (CaptureSession) throws -> [CaptureEvent]) {
        guard !stopped, let core else { return }
        let events: [CaptureEvent]
        do {
            events = try call(core)
        } catch {
            if refusalIsFatal {
                fail(error)
            } else {
                send(.refused(CoreErrors.message(for: error)))
            }
            return
        }
        guard !events.isEmpty else { return }
        send(.events(events, core.progress()))
        for event in events {
            switch event {
            case .promptStarted(let prompt):
                let picture = try? core.promptPreview(index: prompt.index)
                send(.preview(promptIndex: prompt.index, vertices: picture))
            default:
                break
            }
        }
        if core.isFinished() {
            finish(core)
        }
    }

    private func finish(_ core: CaptureSession) {
        stopped = true
        pauseCamera()
        do {
            let handle = try core.finish()
            let folder = try Storage.newCaptureFolder()
            let file = folder.appendingPathComponent(Storage.sessionFileName)
            try handle.save(path: file.path(percentEncoded: false))
            try Storage.protect(file)
            send(.saved(SavedSession(handle: handle, folder: folder, sessionFile: file)))
        } catch {
            send(.failed(CoreErrors.message(for: error)))
        }
    }

    private func fail(_ error: Error) {
        stopped = true
        pauseCamera()
        send(.failed(CoreErrors.message(for: error)))
    }

    private func pauseCamera() {
        let session = arSession
        DispatchQueue.main.async { session.pause() }
    }

    private func send(_ update: Update) {
        let deliver = self.deliver
        CoreQueue.onMain { deliver(update) }
    }
}
