import Foundation
import LikenessFFI
import Observation
import SceneKit

/// The result screen's content: the live mirror of the person's own face, what
/// the core says about the capture and the avatar, and the files to share.
@MainActor @Observable
final class ResultModel {
    /// What the core thinks of the capture.
    let quality: QualitySummary
    /// The core's one-paragraph account of the avatar.
    let avatarSummary: String
    /// The core's warnings about the avatar.
    let avatarWarnings: [String]
    /// The files to share.
    let files: ExportFiles
    /// The method the core used to personalize.
    let method: String
    /// Why the mirror stopped, if it did.
    private(set) var mirrorProblem: String? = nil

    /// The mirrored face; its geometry changes every frame.
    let mirrorNode = SCNNode()
    private let triangles: [UInt32]
    @ObservationIgnored private var mirror: MirrorDriver?

    init(outcome: ProcessingOutcome) {
        quality = outcome.quality
        avatarSummary = outcome.avatar.summary
        avatarWarnings = outcome.avatar.warnings
        files = outcome.files
        method = outcome.method
        triangles = outcome.triangles
        mirror = MirrorDriver(face: outcome.face) { [weak self] update in
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
        case .posed(let vertices):
            mirrorNode.geometry = MeshGeometry.make(vertices: vertices, triangles: triangles)
        case .failed(let message):
            mirrorProblem = message
        }
    }
}
