import SwiftUI

/// The capture and its review, one after the other on one model: the
/// capture (`CaptureView`) while the core asks for expressions, the review
/// (`ReviewView`) once no step is left, and back to the capture for a retake.
/// The camera (or the demo's replay) starts when this screen appears and
/// stops when it goes.
struct CaptureScreen: View {
    let model: CaptureModel
    /// Leave the capture (back to the start screen).
    let onCancel: () -> Void
    /// Start a new capture after a failure.
    let onRetry: () -> Void

    var body: some View {
        Group {
            switch model.stage {
            case .reviewing, .saving:
                ReviewView(model: model, onCancel: onCancel)
            case .lookingForFace, .preparing, .capturing, .failed:
                CaptureView(model: model, onCancel: onCancel, onRetry: onRetry)
            }
        }
        .onAppear { model.start() }
        .onDisappear { model.stop() }
    }
}
