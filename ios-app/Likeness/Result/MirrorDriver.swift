import ARKit
import LikenessFFI

/// The live mirror: the person's own face shapes and their avatar, driven by
/// their ARKit weights frame by frame.
///
/// Runs its own face-tracking session (no camera picture is shown). Each
/// frame's weights go to the core's `PersonalizedFace.pose(weights:)` and
/// `AvatarPreview.pose(weights:)`, on `CoreQueue`, and the posed vertices to
/// the screen.
final class MirrorDriver: NSObject, ARSessionDelegate, @unchecked Sendable {
    /// What the mirror tells the screen, on the main actor.
    enum Update {
        /// The face's and the avatar's vertices for the latest frame (xyz
        /// flattened).
        case posed(face: [Float], avatar: [Float])
        /// The mirror stopped, in words.
        case failed(String)
    }

    private let arSession = ARSession()
    private let face: PersonalizedFace
    private let avatar: AvatarPreview
    // Touched on CoreQueue only.
    private let reader: FaceFrameReader
    private var stopped = false
    private let deliver: @MainActor (Update) -> Void

    /// - Parameters:
    ///   - face: the person's shapes from the core.
    ///   - avatar: the avatar they were implanted into.
    ///   - deliver: receives every update, on the main actor, in order.
    init(face: PersonalizedFace, avatar: AvatarPreview, deliver: @escaping @MainActor (Update) -> Void) {
        self.face = face
        self.avatar = avatar
        self.deliver = deliver
        reader = FaceFrameReader(names: arkitNames(), rawKeys: arkitKeys())
        super.init()
        arSession.delegate = self
        arSession.delegateQueue = CoreQueue.queue
    }

    /// Shows the face at rest, then follows the person's face.
    func run() {
        let names = reader.names
        CoreQueue.queue.async {
            self.stopped = false
            self.pose(weights: [Float](repeating: 0, count: names.count))
        }
        arSession.run(ARFaceTrackingConfiguration(), options: [.resetTracking, .removeExistingAnchors])
    }

    /// Stops the camera.
    func stop() {
        arSession.pause()
        CoreQueue.queue.async { self.stopped = true }
    }

    // MARK: ARSessionDelegate (on CoreQueue)

    func session(_ session: ARSession, didUpdate anchors: [ARAnchor]) {
        guard !stopped,
              let anchor = anchors.lazy.compactMap({ $0 as? ARFaceAnchor }).first,
              anchor.isTracked
        else { return }
        do {
            pose(weights: try reader.weights(of: anchor))
        } catch {
            fail(error)
        }
    }

    func session(_ session: ARSession, didFailWithError error: Error) {
        fail(error)
    }

    private func pose(weights: [Float]) {
        do {
            let faceVertices = try face.pose(weights: weights)
            let avatarVertices = try avatar.pose(weights: weights)
            send(.posed(face: faceVertices, avatar: avatarVertices))
        } catch {
            fail(error)
        }
    }

    private func fail(_ error: Error) {
        guard !stopped else { return }
        stopped = true
        let session = arSession
        DispatchQueue.main.async { session.pause() }
        send(.failed(CoreErrors.message(for: error)))
    }

    private func send(_ update: Update) {
        let deliver = self.deliver
        CoreQueue.onMain { deliver(update) }
    }
}
