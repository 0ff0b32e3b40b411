import Foundation
import LikenessFFI
import Observation

/// Runs the two long steps on the core's queue (personalize the 52 shapes,
/// then put them on the avatar) and shows how far the core has got.
@MainActor @Observable
final class ProcessingModel {
    /// The two steps, in order.
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
    @ObservationIgnored private var reporter: ProgressReporter?
    private let onDone: (ResultModel) -> Void

    /// - Parameters:
    ///   - saved: the finished, saved capture.
    ///   - onDone: receives the result once the avatar is written.
    init(saved: SavedSession, onDone: @escaping (ResultModel) -> Void) {
        self.saved = saved
        self.onDone = onDone
    }

    /// Starts (or restarts) processing.
    func start() {
        state = .running
        step = .personalizing
        stage = ""
        fraction = 0
        let reporter = ProgressReporter { [weak self] stage, fraction in
            CoreQueue.onMain {
                self?.progressed(stage: stage, fraction: fraction)
            }
        }
        self.reporter = reporter
        let saved = self.saved
        CoreQueue.queue.async {
            do {
                let face = try saved.handle.personalize(method: nil, listener: reporter)
                CoreQueue.onMain { [weak self] in self?.advance(to: .buildingAvatar) }
                let avatar = try face.avatar(avatarGlb: nil, restFace: nil, listener: reporter)
                CoreQueue.onMain { [weak self] in self?.advance(to: .writingFiles) }
                let files = try ExportFiles.write(avatar, beside: saved)
                let preview = try AvatarPreview(glb: avatar.glb)
                let outcome = ProcessingOutcome(
                    face: face,
                    preview: preview,
                    previewTriangles: preview.triangles(),
                    method: face.method(),
                    triangles: face.triangles(),
                    quality: saved.handle.qualitySummary(),
                    avatar: avatar,
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
        onDone(ResultModel(outcome: outcome))
    }

    private func stopped(by error: Error) {
        reporter = nil
        state = CoreErrors.isCancellation(error) ? .cancelled : .failed(CoreErrors.message(for: error))
    }
}

/// Everything processing produced, handed to the result screen.
struct ProcessingOutcome {
    /// The person's 52 shapes, to pose live.
    let face: PersonalizedFace
    /// The avatar just written, to pose live beside the face.
    let preview: AvatarPreview
    /// The avatar's triangles.
    let previewTriangles: [UInt32]
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
