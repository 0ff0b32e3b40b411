import SwiftUI

/// Shows the screen `AppFlow` has up.
struct RootView: View {
    let flow: AppFlow

    var body: some View {
        switch flow.screen {
        case .start:
            StartView(
                problem: flow.startProblem,
                onBegin: { flow.startCapture() },
                onReprocess: { flow.reprocess(sessionFile: $0) })
        case .capture(let model):
            CaptureView(
                model: model,
                onCancel: { flow.startOver() },
                onRetry: { flow.startCapture() })
        case .processing(let model):
            ProcessingView(model: model, onStartOver: { flow.startOver() })
        case .result(let model):
            ResultView(model: model, onStartOver: { flow.startOver() })
        }
    }
}
