import SwiftUI
import UIKit

/// Guided capture: the camera with the tracked mask (or, in the demo, a note
/// that a recording plays), the core's current request with a picture of it,
/// progress, skip and retake, a pause screen while the face is out of view,
/// and a passing notice when a frame was dropped.
struct CaptureView: View {
    let model: CaptureModel
    /// Leave the capture (back to the start screen).
    let onCancel: () -> Void
    /// Start a new capture after a failure.
    let onRetry: () -> Void

    var body: some View {
        ZStack {
            if let session = model.arSession {
                FaceMaskView(session: session)
                    .ignoresSafeArea()
            } else {
                DemoBackdrop()
            }
            VStack(spacing: 12) {
                HStack {
                    Spacer()
                    Button(action: onCancel) {
                        Image(systemName: "xmark.circle.fill")
                            .font(.title)
                            .foregroundStyle(.white)
                    }
                    .accessibilityLabel("Stop capture")
                }
                stageContent
                Spacer()
                if let frameNotice = model.frameNotice {
                    Label(frameNotice, systemImage: "exclamationmark.bubble")
                        .font(.caption)
                        .foregroundStyle(.white)
                        .padding(8)
                        .background(Theme.cardBackground, in: Capsule())
                        .transition(.opacity)
                }
                if model.stage == .capturing {
                    CaptureControls(
                        progress: model.progress,
                        canSkip: !(model.prompt?.isNeutral ?? true),
                        canRetake: model.lastCaptured != nil,
                        onSkip: { model.skip() },
                        onRetake: { model.retakeLast() })
                }
            }
            .padding()
            if model.isPaused {
                PauseOverlay()
                    .transition(.opacity)
            }
        }
        .background(Color.black)
        .animation(Theme.animation, value: model.isPaused)
        .animation(Theme.animation, value: model.frameNotice)
    }

    @ViewBuilder private var stageContent: some View {
        switch model.stage {
        case .lookingForFace:
            StatusCard(
                systemImage: model.isDemo ? "play.circle" : "faceid",
                text: model.isDemo
                    ? "Loading a recorded capture…"
                    : "Hold the phone at arm's length, level with your face, and look at the screen.")
        case .preparing:
            StatusCard(systemImage: "hourglass", text: model.isDemo ? "Getting ready…" : "Found you. Getting ready…")
        case .capturing:
            if let prompt = model.prompt {
                PromptCard(
                    prompt: prompt,
                    previewNode: model.previewNode,
                    hasPreview: model.hasPreview,
                    warnings: model.captureWarnings,
                    notice: model.notice)
            }
        case .reviewing, .saving:
            EmptyView()
        case .failed(let message):
            FailureCard(message: message, showsSettings: !model.isDemo, onRetry: onRetry, onBack: onCancel)
        }
    }
}

/// A short message over the camera picture.
private struct StatusCard: View {
    let systemImage: String
    let text: String

    var body: some View {
        Label(text, systemImage: systemImage)
            .font(.headline)
            .foregroundStyle(.white)
            .padding()
            .frame(maxWidth: .infinity, alignment: .leading)
            .background(Theme.cardBackground, in: RoundedRectangle(cornerRadius: Theme.cornerRadius))
    }
}

/// Why the capture stopped, with a way on.
private struct FailureCard: View {
    let message: String
    let showsSettings: Bool
    let onRetry: () -> Void
    let onBack: () -> Void

    var body: some View {
        VStack(alignment: .leading, spacing: 12) {
            Label("The capture stopped", systemImage: "exclamationmark.octagon.fill")
                .font(.headline)
            Text(message)
            HStack {
                Button("Try again", action: onRetry)
                    .buttonStyle(.borderedProminent)
                if showsSettings {
                    Button("Open Settings") {
                        if let url = URL(string: UIApplication.openSettingsURLString) {
                            UIApplication.shared.open(url)
                        }
                    }
                    .buttonStyle(.bordered)
                }
                Button("Back", action: onBack)
                    .buttonStyle(.bordered)
            }
        }
        .foregroundStyle(.white)
        .padding()
        .frame(maxWidth: .infinity, alignment: .leading)
        .background(Theme.cardBackground, in: RoundedRectangle(cornerRadius: Theme.cornerRadius))
    }
}
