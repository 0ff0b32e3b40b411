import LikenessFFI
import SwiftUI

/// Progress through the prompts, and the person's two choices: retake the
/// last capture, or skip this prompt.
struct CaptureControls: View {
    let progress: CaptureProgress?
    let canSkip: Bool
    let canRetake: Bool
    let onSkip: () -> Void
    let onRetake: () -> Void

    var body: some View {
        VStack(spacing: 12) {
            if let progress {
                VStack(spacing: 4) {
                    ProgressView(value: progress.fraction)
                        .tint(.white)
                    Text(countText(progress))
                        .font(.footnote.monospacedDigit())
                }
            }
            HStack(spacing: 16) {
                Button(action: onRetake) {
                    Label("Retake last", systemImage: "arrow.counterclockwise")
                        .frame(maxWidth: .infinity)
                }
                .disabled(!canRetake)
                Button(action: onSkip) {
                    Label("Skip", systemImage: "forward.fill")
                        .frame(maxWidth: .infinity)
                }
                .disabled(!canSkip)
            }
            .buttonStyle(.bordered)
            .controlSize(.large)
        }
        .foregroundStyle(.white)
        .padding()
        .background(Theme.cardBackground, in: RoundedRectangle(cornerRadius: Theme.cornerRadius))
    }

    private func countText(_ progress: CaptureProgress) -> String {
        var text = "\(progress.captured) / \(progress.total) captured"
        if progress.skipped > 0 {
            text += ", \(progress.skipped) skipped"
        }
        return text
    }
}
