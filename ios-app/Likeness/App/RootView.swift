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
                // A new capture is a new screen: its camera starts on appear.
                .id(ObjectIdentifier(model))
        case .processing(let model):
            ProcessingView(model: model, onStartOver: { flow.startOver() })
                .id(ObjectIdentifier(model))
        case .result(let model):
            ResultView(model: model, onStartOver: { flow.startOver() })
                .id(ObjectIdentifier(model))
        }
    }
}
