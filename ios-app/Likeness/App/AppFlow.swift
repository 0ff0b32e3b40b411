import Foundation
import LikenessFFI
import Observation

/// Which screen is up, and the hand-overs between them:
/// start → capture → processing → result.
@MainActor @Observable
final class AppFlow {
    /// The screens, each with the model it shows.
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

    /// Why reopening the last capture failed, for the start screen.
    private(set) var startProblem: String? = nil

    /// A new guided capture.
    func startCapture() {
        startProblem = nil
        screen = .capture(CaptureModel { [weak self] saved in
            self?.process(saved)
        })
    }

    /// Processes the most recent saved capture again.
    func reprocess(sessionFile: URL) {
        startProblem = nil
        let path = sessionFile.path(percentEncoded: false)
        CoreQueue.queue.async {
            do {
                let handle = try SessionHandle.load(path: path)
                let saved = SavedSession(
                    handle: handle,
                    folder: sessionFile.deletingLastPathComponent(),
                    sessionFile: sessionFile)
                CoreQueue.onMain { [weak self] in self?.process(saved) }
            } catch {
                let message = CoreErrors.message(for: error)
                CoreQueue.onMain { [weak self] in self?.startProblem = message }
            }
        }
    }

    /// Back to the start screen.
    func startOver() {
        screen = .start
    }

    private func process(_ saved: SavedSession) {
        let model = ProcessingModel(saved: saved) { [weak self] result in
            self?.screen = .result(result)
        }
        screen = .processing(model)
        model.start()
    }
}
