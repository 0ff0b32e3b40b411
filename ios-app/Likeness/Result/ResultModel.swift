import Foundation
import LikenessFFI
import Observation
import SceneKit

/// The result screen's content: the live mirror of the person's own face and
/// their avatar, what the core says about the capture and the avatar, which
/// avatar it is and whose face it has, and the files to share.
@MainActor @Observable
final class ResultModel {
    /// What the core thinks of the capture.
    let quality: QualitySummary
    /// The core's one-paragraph account of the avatar.
    let avatarSummary: String
    /// The core's warnings about the avatar.
    let avatarWarnings: [String]
    /// Whether the avatar wears the person's own face at rest (the core's
    /// `RestFaceChoice`).
    let ownFace: Bool
    /// The file name of the avatar the person brought; `nil`: the default.
    let avatarName: String?
    /// The files to share.
    let files: ExportFiles
    /// The method the core used to personalize.
    let method: String
    /// The session, where it is saved now (to put the face on another avatar).
    let saved: SavedSession
    /// The person's shapes (to put them on another avatar).
    let face: PersonalizedFace
    /// Why the mirror stopped, if it did.
    private(set) var mirrorProblem: String? = nil

    /// The mirrored face; its geometry changes with the person's face.
    let mirrorNode = SCNNode()
    /// The avatar, moving with the face: `avatarMesh` inside it, moved and
    /// scaled so the avatar's face fills the view as the mirrored face does.
    let avatarNode = SCNNode()
    private let avatarMesh = SCNNode()
    private let triangles: [UInt32]
    @ObservationIgnored private var morph: AvatarMorph?
    @ObservationIgnored private var mirror: MirrorDriver?

    init(outcome: ProcessingOutcome) {
        quality = outcome.quality
        avatarSummary = outcome.avatar.summary
        avatarWarnings = outcome.avatar.warnings
        ownFace = outcome.avatar.restFace == .person
        avatarName = outcome.avatarName
        files = outcome.files
        method = outcome.method
        saved = outcome.saved
        face = outcome.face
        triangles = outcome.triangles
        // Built once; a frame only sets the morpher's weights.
        let morph = AvatarMorph(mesh: outcome.mesh)
        self.morph = morph
        avatarMesh.geometry = morph?.geometry
        avatarMesh.morpher = morph?.morpher
        let focus = outcome.focus
        avatarMesh.pivot = SCNMatrix4MakeTranslation(focus.x, focus.y, focus.z)
        if focus.radius > 0 {
            let scale = Theme.faceRadius / focus.radius
            avatarMesh.scale = SCNVector3(scale, scale, scale)
        }
        avatarNode.addChildNode(avatarMesh)
        if morph == nil {
            mirrorProblem = "The avatar's mesh could not be shown here; the file itself is fine to share."
        }
        mirror = MirrorDriver(face: outcome.face, names: outcome.names, keys: outcome.keys) { [weak self] update in
            self?.apply(update)
        }
    }

    /// Starts the live mirror.
    func startMirror() {
        mirror?.run()
    }

    /// Stops the live mirror's camera.
    func stopMirror() {
        mirror?.stop()
    }

    private func apply(_ update: MirrorDriver.Update) {
        switch update {
        case .weights(let weights):
            morph?.apply(weights: weights)
        case .face(let vertices):
            mirrorNode.geometry = MeshGeometry.make(vertices: vertices, triangles: triangles)
        case .failed(let message):
            mirrorProblem = message
            mirror?.stop()
        }
    }
}
