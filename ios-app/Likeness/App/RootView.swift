import SwiftUI
import UIKit

/// Shows the screen `AppFlow` has up, and keeps the display on while the
/// person is busy with the phone at arm's length.
struct RootView: View {
    let flow: AppFlow

    var body: some View {
        screen
            .onAppear { UIApplication.shared.isIdleTimerDisabled = flow.keepsScreenAwake }
            .onChange(of: flow.keepsScreenAwake) { _, awake in
                UIApplication.shared.isIdleTimerDisabled = awake
            }
    }

    @ViewBuilder private var screen: some View {
        switch flow.screen {
        case .start:
            StartView(flow: flow)
        case .capture(let model):
            CaptureScreen(
                model: model,
                onCancel: { flow.startOver() },
                onRetry: { flow.retry(model) })
                // A new capture is a new screen: its camera starts on appear.
                .id(ObjectIdentifier(model))
        case .processing(let model):
            ProcessingView(
                model: model,
                onStartOver: { flow.startOver() },
                onDefaultAvatar: model.avatar == nil ? nil : { flow.useDefaultAvatar() })
                .id(ObjectIdentifier(model))
        case .result(let model):
            ResultView(model: model, flow: flow)
                .id(ObjectIdentifier(model))
        }
    }
}
