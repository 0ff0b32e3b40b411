import ARKit
import LikenessFFI
import LikenessGlue

/// The live mirror: the person's own face shapes and their avatar, driven by
/// their ARKit weights as they move.
///
/// Runs its own face-tracking session (no camera picture is shown), whose
/// anchors arrive on this driver's serial queue and are read there into the
/// 52 weights. Two paths, each coalesced (`Coalescer`: at most one update in
/// flight, always the latest weights):
///
/// * the avatar: the weights go straight to the main queue, where the
///   avatar's morpher takes them (`AvatarMorph.apply`); no mesh moves;
/// * the face mask: the core poses the person's own shapes on its thread
///   (`PersonalizedFace.pose`), and the 1,220 posed vertices go to the main
///   queue to be drawn.
final class MirrorDriver: NSObject, ARSessionDelegate, @unchecked Sendable {
    /// What the mirror tells the screen, on the main actor.
    enum Update {
        /// The latest weights, for the avatar's morpher.
        case weights([Float])
        /// The person's face posed by the latest weights (xyz flattened).
        case face([Float])
        /// The mirror stopped, in words.
        case failed(String)
    }

    private let arSession = ARSession()
    private let queue = DispatchQueue(label: "org.likeness.mirror", qos: .userInitiated)
    // Touched on `queue` only.
    private let reader: FaceFrameReader
    private let avatarWeights: Coalescer
    private let faceWeights: Coalescer
    private let deliver: @MainActor (Update) -> Void
    // Touched on the main thread only.
    private var running = false

    /// - Parameters:
    ///   - face: the person's shapes from the core.
    ///   - names: `arkitNames()`; `keys`: `arkitKeys()`.
    ///   - deliver: receives every update, on the main actor, in order.
    init(face: PersonalizedFace, names: [String], keys: [String], deliver: @escaping @MainActor (Update) -> Void) {
        self.deliver = deliver
        reader = FaceFrameReader(names: names, rawKeys: keys)
        let onMain: Coalescer.Schedule = { job in DispatchQueue.main.async(execute: job) }
        avatarWeights = Coalescer(schedule: onMain) { weights in
            MainActor.assumeIsolated { deliver(.weights(weights)) }
        }
        let posedFaces = Coalescer(schedule: onMain) { vertices in
            MainActor.assumeIsolated { deliver(.face(vertices)) }
        }
        faceWeights = Coalescer(schedule: { job in CoreQueue.async(job) }) { weights in
            do {
                posedFaces.offer(try face.pose(weights: weights))
            } catch {
                let message = CoreErrors.message(for: error)
                CoreQueue.onMain { deliver(.failed(message)) }
            }
        }
        super.init()
        arSession.delegate = self
        arSession.delegateQueue = queue
    }

    /// Shows the face at rest, then follows the person's face.
    func run() {
        running = true
        let rest = [Float](repeating: 0, count: reader.names.count)
        avatarWeights.offer(rest)
        faceWeights.offer(rest)
        arSession.run(ARFaceTrackingConfiguration(), options: [.resetTracking, .removeExistingAnchors])
    }

    /// Stops the camera.
    func stop() {
        running = false
        arSession.pause()
    }

    // MARK: ARSessionDelegate (on `queue`)

    func session(_ session: ARSession, didUpdate anchors: [ARAnchor]) {
        guard let anchor = anchors.lazy.compactMap({ $0 as? ARFaceAnchor }).first(where: { $0.isTracked }) else {
            return
        }
        do {
            let weights = try reader.weights(of: anchor)
            avatarWeights.offer(weights)
            faceWeights.offer(weights)
        } catch {
            let message = CoreErrors.message(for: error)
            let deliver = self.deliver
            CoreQueue.onMain { deliver(.failed(message)) }
        }
    }

    func sessionInterruptionEnded(_ session: ARSession) {
        DispatchQueue.main.async { [weak self] in
            guard let self, self.running else { return }
            self.arSession.run(ARFaceTrackingConfiguration(), options: [.resetTracking, .removeExistingAnchors])
        }
    }

    func session(_ session: ARSession, didFailWithError error: Error) {
        let message = CoreErrors.message(for: error)
        let deliver = self.deliver
        CoreQueue.onMain { deliver(.failed(message)) }
    }
}
