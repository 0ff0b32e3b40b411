import Foundation
import LikenessFFI
import Observation
import SceneKit

/// The result screen's content: the live mirror of the person's own face and
/// their avatar, what the core says about the capture and the avatar, and the
/// files to share.
@MainActor @Observable
final class ResultModel {
    /// What the core thinks of the capture.
    let quality: QualitySummary
    /// The core's one-paragraph account of the avatar.
    let avatarSummary: String
    /// The core's warnings about the avatar.
    let avatarWarnings: [String]
    /// Whether the avatar wears the person's own face at rest.
    let ownFace: Bool
    /// The files to share.
    let files: ExportFiles
    /// The method the core used to personalize.
    let method: String
    /// Why the mirror stopped, if it did.
    private(set) var mirrorProblem: String? = nil

    /// The mirrored face; its geometry changes every frame.
    let mirrorNode = SCNNode()
    /// The avatar, moving with the face: `avatarMesh` inside it, moved and
    /// scaled so the avatar's face fills the view as the mirrored face does.
    let avatarNode = SCNNode()
    private let avatarMesh = SCNNode()
    private let triangles: [UInt32]
    private let avatarTriangles: [UInt32]
    @ObservationIgnored private var mirror: MirrorDriver?

    init(outcome: ProcessingOutcome) {
        quality = outcome.quality
        avatarSummary = outcome.avatar.summary
        avatarWarnings = outcome.avatar.warnings
        ownFace = outcome.avatar.restFace == .person
        files = outcome.files
        method = outcome.method
        triangles = outcome.triangles
        avatarTriangles = outcome.previewTriangles
        let focus = outcome.preview.focus()
        avatarMesh.pivot = SCNMatrix4MakeTranslation(focus.x, focus.y, focus.z)
        if focus.radius > 0 {
            let scale = Theme.faceRadius / focus.radius
            avatarMesh.scale = SCNVector3(scale, scale, scale)
        }
        avatarNode.addChildNode(avatarMesh)
        mirror = MirrorDriver(face: outcome.face, avatar: outcome.preview) { [weak self] update in
            self?.apply(update)
        }
    }

    /// Starts the live mirror.
    func startMirror() {
        mirrorProblem = nil
        mirror?.run()
    }

    /// Stops the live mirror's camera.
    func stopMirror() {
        mirror?.stop()
    }

    private func apply(_ update: MirrorDriver.Update) {
        switch update {
        case .posed(let face, let avatar):
            mirrorNode.geometry = MeshGeometry.make(vertices: face, triangles: triangles)
            avatarMesh.geometry = MeshGeometry.make(vertices: avatar, triangles: avatarTriangles)
        case .failed(let message):
            mirrorProblem = message
        }
    }
}
