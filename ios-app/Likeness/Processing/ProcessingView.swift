import SwiftUI

/// The wait while the core works: which step, the core's own stage name and
/// progress, and Cancel.
struct ProcessingView: View {
    let model: ProcessingModel
    /// Back to the start screen.
    let onStartOver: () -> Void
    /// Process again with the default avatar (offered when the person's own
    /// avatar was used); `nil` hides it.
    var onDefaultAvatar: (() -> Void)? = nil

    var body: some View {
        VStack(spacing: 24) {
            Spacer()
            switch model.state {
            case .running, .cancelling:
                running
            case .cancelled:
                stopped(title: "Cancelled", message: "Your capture is saved: process it again here, or later from the start screen.")
            case .failed(let message):
                stopped(title: "Processing stopped", message: message)
            }
            Spacer()
        }
        .padding(32)
    }

    private var running: some View {
        VStack(spacing: 16) {
            Text(stepTitle)
                .font(.title2.bold())
            ProgressView(value: model.fraction)
            Text(model.stage.isEmpty ? " " : model.stage)
                .font(.footnote)
                .foregroundStyle(.secondary)
            if let avatar = model.avatar {
                Text("Avatar: \(avatar.name)")
                    .font(.footnote)
            }
            Text("Everything runs on this iPhone. This can take a minute; it goes on for a while if you leave the app.")
                .font(.footnote)
                .multilineTextAlignment(.center)
                .foregroundStyle(.secondary)
            Button(model.state == .cancelling ? "Cancelling…" : "Cancel", role: .cancel) {
                model.cancel()
            }
            .buttonStyle(.bordered)
            .disabled(model.state == .cancelling)
        }
    }

    private func stopped(title: String, message: String) -> some View {
        VStack(spacing: 16) {
            Text(title)
                .font(.title2.bold())
            Text(message)
                .multilineTextAlignment(.center)
            Button("Process again") { model.start() }
                .buttonStyle(.borderedProminent)
            if let onDefaultAvatar {
                Button("Use the default avatar instead", action: onDefaultAvatar)
                    .buttonStyle(.bordered)
            }
            Button("Start over", action: onStartOver)
                .buttonStyle(.bordered)
        }
    }

    private var stepTitle: String {
        switch model.step {
        case .personalizing:
            return "Step 1 of 2: your own expressions"
        case .buildingAvatar:
            return "Step 2 of 2: your avatar"
        case .writingFiles:
            return "Saving your files"
        }
    }
}
