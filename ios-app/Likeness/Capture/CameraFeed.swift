import ARKit
import LikenessFFI
import LikenessGlue

/// Sends the TrueDepth camera's frames to the capture.
///
/// ARKit delivers each `ARFrame` on this feed's own serial queue; the frame's
/// face anchor is read there into plain values (`CaptureFrame`) and handed to
/// the core's thread, so no `ARFrame` outlives its callback. A frame without
/// a tracked face goes as untracked. The first face ARKit finds sets the core
/// up: ARKit's blendshape keys are paired with the core's names and ARKit's
/// face model becomes the core's template.
///
/// When ARKit's session is interrupted, the runner tells the core; when the
/// interruption ends, the face-tracking configuration runs again from scratch.
final class CameraFeed: NSObject, FrameFeed, ARSessionDelegate, @unchecked Sendable {
    private let session = ARSession()
    private let queue = DispatchQueue(label: "org.likeness.camera", qos: .userInitiated)
    private let runner: CaptureRunner
    // Touched on `queue` only.
    private let reader: FaceFrameReader
    private var foundFace = false
    // Touched on the main thread only.
    private var running = false

    init(runner: CaptureRunner) {
        self.runner = runner
        reader = FaceFrameReader(names: arkitNames(), rawKeys: arkitKeys())
        super.init()
        session.delegate = self
        session.delegateQueue = queue
    }

    // MARK: FrameFeed (main thread)

    var arSession: ARSession? { session }

    /// Starts the front camera and face tracking; ARKit asks for camera
    /// access the first time.
    func start() {
        running = true
        runConfiguration()
    }

    func pause() {
        running = false
        session.pause()
    }

    func resume() {
        guard !running else { return }
        start()
    }

    func stop() {
        pause()
    }

    private func runConfiguration() {
        let configuration = ARFaceTrackingConfiguration()
        configuration.isLightEstimationEnabled = true
        session.run(configuration, options: [.resetTracking, .removeExistingAnchors])
    }

    // MARK: ARSessionDelegate (on `queue`)

    func session(_ session: ARSession, didUpdate frame: ARFrame) {
        let runner = self.runner
        let timestamp = frame.timestamp
        guard let face = frame.anchors.lazy.compactMap({ $0 as? ARFaceAnchor }).first(where: { $0.isTracked }) else {
            let untracked = CaptureFrame.untracked(at: timestamp)
            CoreQueue.async { runner.push(untracked) }
            return
        }
        do {
            if !foundFace {
                let keys = try reader.blendShapeKeys(for: face)
                foundFace = true
                let names = reader.names
                CoreQueue.async {
                    runner.begin(device: DeviceModel.identifier) {
                        try FaceTemplateBuilder.build(names: names, keys: keys)
                    }
                }
            }
            let tracked = CaptureFrame(
                timestamp: timestamp,
                weights: try reader.weights(of: face),
                vertices: reader.packedVertices(of: face),
                tracked: true)
            CoreQueue.async { runner.push(tracked) }
        } catch {
            // ARKit lacks a key the core names: no frame can be read.
            CoreQueue.async { runner.fail(error) }
        }
    }

    func sessionWasInterrupted(_ session: ARSession) {
        let runner = self.runner
        CoreQueue.async { runner.interrupt() }
    }

    func sessionInterruptionEnded(_ session: ARSession) {
        DispatchQueue.main.async { [weak self] in
            guard let self, self.running else { return }
            self.runConfiguration()
        }
    }

    func session(_ session: ARSession, didFailWithError error: Error) {
        let runner = self.runner
        CoreQueue.async { runner.fail(error) }
    }
}
