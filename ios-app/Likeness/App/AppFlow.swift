import Foundation
import LikenessFFI
import Observation

/// Which screen is up, and the hand-overs between them:
/// start → capture (or the demo) → review → processing → result, plus the
/// avatar the person brings, from the file importer or opened from another app.
@MainActor @Observable
final class AppFlow {
    /// The screens, each with the model it shows. The capture screen holds
    /// its review too (the same capture).
    enum Screen {
        case start
        case capture(CaptureModel)
        case processing(ProcessingModel)
        case result(ResultModel)
    }

    private(set) var screen: Screen = .start
    /// Whether the screen should stay on: during capture, processing and the
    /// live mirror the person is not touching the phone.
    var keepsScreenAwake: Bool {
        switch screen {
        case .start:
            return false
        case .capture, .processing, .result:
            return true
        }
    }

    /// Why reopening a saved capture failed, for the start screen.
    private(set) var startProblem: String? = nil
    /// The avatar the person brought, used by the next processing; `nil`:
    /// the core's default avatar.
    private(set) var avatar: ChosenAvatar? = nil
    /// An avatar file is being read and checked.
    private(set) var isReadingAvatar = false
    /// Why the last avatar file was refused, in the core's words.
    private(set) var avatarProblem: String? = nil

    /// A new guided capture with the camera.
    func startCapture() {
        beginCapture(demo: false)
    }

    /// The demo: a recorded capture replayed through the same screens.
    func startDemo() {
        beginCapture(demo: true)
    }

    /// Starts again the kind of capture `model` was, after it failed.
    func retry(_ model: CaptureModel) {
        beginCapture(demo: model.isDemo)
    }

    /// Processes a saved session: one left unprocessed (Resume), or the most
    /// recent processed one again.
    func process(sessionFile: URL) {
        startProblem = nil
        CoreQueue.async {
            do {
                let saved = try SavedSession.load(sessionFile)
                CoreQueue.onMain { [weak self] in self?.process(saved, face: nil) }
            } catch {
                let message = CoreErrors.message(for: error)
                CoreQueue.onMain { [weak self] in self?.startProblem = message }
            }
        }
    }

    /// Deletes a session the person chose not to process.
    func discard(sessionFile: URL) {
        do {
            try Storage.discard(sessionFile)
        } catch {
            startProblem = CoreErrors.message(for: error)
        }
    }

    /// Back to the start screen.
    func startOver() {
        screen = .start
    }

    /// Reads the avatar file at `url` (from the importer, or opened in the
    /// app from Files or AirDrop). Once the core accepts it, the result on
    /// screen is made again on it; otherwise it is used by the next
    /// processing.
    func openAvatar(at url: URL) {
        avatarProblem = nil
        isReadingAvatar = true
        AvatarFile.read(url) { [weak self] outcome in
            self?.avatarRead(outcome)
        }
    }

    /// The file importer could not give a file.
    func avatarImportFailed(_ error: Error) {
        avatarProblem = CoreErrors.message(for: error)
    }

    /// Goes back to the core's default avatar, and makes the result on
    /// screen (or the processing that stopped) again with it.
    func useDefaultAvatar() {
        avatar = nil
        avatarProblem = nil
        remakeOnScreen()
    }

    private func beginCapture(demo: Bool) {
        startProblem = nil
        screen = .capture(CaptureModel(demo: demo) { [weak self] saved in
            self?.process(saved, face: nil)
        })
    }

    private func avatarRead(_ outcome: Result<ChosenAvatar, Error>) {
        isReadingAvatar = false
        switch outcome {
        case .success(let chosen):
            avatar = chosen
            remakeOnScreen()
        case .failure(let error):
            avatarProblem = CoreErrors.message(for: error)
        }
    }

    /// A result (or a stopped processing) on screen is made again with the
    /// avatar now chosen, from the person's shapes already made.
    private func remakeOnScreen() {
        switch screen {
        case .result(let result):
            process(result.saved, face: result.face)
        case .processing(let model) where model.isStopped:
            process(model.saved, face: model.face)
        case .start, .capture, .processing:
            break
        }
    }

    private func process(_ saved: SavedSession, face: PersonalizedFace?) {
        let model = ProcessingModel(saved: saved, face: face, avatar: avatar) { [weak self] result in
            self?.screen = .result(result)
        }
        screen = .processing(model)
        model.start()
    }
}
