import Foundation
import LikenessFFI
import Observation

/// Runs the long steps on the core's thread (personalize the 52 shapes, put
/// them on the avatar, write the files) and shows how far the core has got.
///
/// The session is already saved when this starts (see `Storage`), so nothing
/// is lost if processing stops. It runs inside a background task: if the
/// person leaves the app, iOS gives it a while to finish; if that time runs
/// out, the core is told to cancel, and the start screen offers to resume.
@MainActor @Observable
final class ProcessingModel {
    /// The steps, in order.
    enum Step: Equatable {
        case personalizing, buildingAvatar, writingFiles
    }

    /// Where processing stands.
    enum State: Equatable {
        case running, cancelling, cancelled
        case failed(String)
    }

    private(set) var state: State = .running
    private(set) var step: Step = .personalizing
    /// The core's name for what it is doing now.
    private(set) var stage: String = ""
    /// How far the current stage is, 0…1, as the core reports it.
    private(set) var fraction: Double = 0

    /// The capture being processed.
    let saved: SavedSession
    /// The person's shapes when they are already made (a new avatar for the
    /// same capture): personalizing is skipped.
    let face: PersonalizedFace?
    /// The avatar the person brought; `nil`: the core's default avatar.
    let avatar: ChosenAvatar?
    @ObservationIgnored private var reporter: ProgressReporter?
    private let background = BackgroundTask()
    private let onDone: (ResultModel) -> Void

    /// - Parameters:
    ///   - saved: the confirmed, saved capture.
    ///   - face: the person's shapes if already made.
    ///   - avatar: the avatar to put them on (`nil`: the default).
    ///   - onDone: receives the result once the avatar is written.
    init(saved: SavedSession, face: PersonalizedFace?, avatar: ChosenAvatar?, onDone: @escaping (ResultModel) -> Void) {
        self.saved = saved
        self.face = face
        self.avatar = avatar
        self.onDone = onDone
    }

    /// Whether processing has stopped (cancelled or failed).
    var isStopped: Bool {
        switch state {
        case .running, .cancelling:
            return false
        case .cancelled, .failed:
            return true
        }
    }

    /// Starts (or restarts) processing.
    func start() {
        state = .running
        step = face == nil ? .personalizing : .buildingAvatar
        stage = ""
        fraction = 0
        let reporter = ProgressReporter { [weak self] stage, fraction in
            CoreQueue.onMain {
                self?.progressed(stage: stage, fraction: fraction)
            }
        }
        self.reporter = reporter
        background.begin(name: "Making your avatar") { [weak self] in
            self?.cancel()
        }
        let saved = self.saved
        let given = self.face
        let avatar = self.avatar
        CoreQueue.async {
            do {
                let face: PersonalizedFace
                if let given {
                    face = given
                } else {
                    face = try saved.handle.personalize(method: nil, listener: reporter)
                    CoreQueue.onMain { [weak self] in self?.advance(to: .buildingAvatar) }
                }
                let made = try face.avatar(avatarGlb: avatar?.bytes, restFace: nil, listener: reporter)
                CoreQueue.onMain { [weak self] in self?.advance(to: .writingFiles) }
                let (files, stored) = try ExportFiles.write(made, avatarName: avatar?.name, for: saved)
                let preview = try AvatarPreview(glb: made.glb)
                let outcome = ProcessingOutcome(
                    saved: stored,
                    face: face,
                    avatarName: avatar?.name,
                    mesh: try preview.morphMesh(),
                    focus: try preview.focus(),
                    names: arkitNames(),
                    keys: arkitKeys(),
                    method: face.method(),
                    triangles: try face.triangles(),
                    quality: try saved.handle.qualitySummary(),
                    avatar: made,
                    files: files)
                CoreQueue.onMain { [weak self] in self?.finished(outcome) }
            } catch {
                CoreQueue.onMain { [weak self] in self?.stopped(by: error) }
            }
        }
    }

    /// Asks the core to stop; it does at its next progress check.
    func cancel() {
        guard state == .running else { return }
        state = .cancelling
        reporter?.cancel()
    }

    private func progressed(stage: String, fraction: Double) {
        self.stage = stage
        self.fraction = min(max(fraction, 0), 1)
    }

    private func advance(to step: Step) {
        self.step = step
        stage = ""
        fraction = 0
    }

    private func finished(_ outcome: ProcessingOutcome) {
        reporter = nil
        background.end()
        onDone(ResultModel(outcome: outcome))
    }

    private func stopped(by error: Error) {
        reporter = nil
        background.end()
        state = CoreErrors.isCancellation(error) ? .cancelled : .failed(CoreErrors.message(for: error))
    }
}

/// Everything processing produced, handed to the result screen.
struct ProcessingOutcome {
    /// The session, where it is saved now.
    let saved: SavedSession
    /// The person's 52 shapes, to pose live.
    let face: PersonalizedFace
    /// The avatar the person brought; `nil`: the default.
    let avatarName: String?
    /// The avatar just written, as one mesh with its ARKit shapes as morph
    /// targets (built into SceneKit once).
    let mesh: PreviewMesh
    /// Where the avatar's face is, to point the preview at it.
    let focus: PreviewFocus
    /// The core's ARKit names and ARKit's keys for them, for the mirror.
    let names: [String]
    let keys: [String]
    /// The personalization method the core used.
    let method: String
    /// The face mesh's triangles.
    let triangles: [UInt32]
    /// What the core thinks of the capture.
    let quality: QualitySummary
    /// The avatar and what the core says about it.
    let avatar: AvatarResult
    /// The files to share.
    let files: ExportFiles
}
