import SwiftUI

/// The review before anything is finished: every step the core lists
/// (`captures()`) with its capture, a Retake on each, and "Use these
/// captures", which makes the session only when the person presses it.
/// Everything shown is the core's; the app only lays it out.
struct ReviewView: View {
    let model: CaptureModel
    /// Leave the capture (back to the start screen).
    let onCancel: () -> Void

    var body: some View {
        if let review = model.review {
            List {
                Section {
                    header(review)
                }
                Section("Your captures") {
                    ForEach(review.captures, id: \.prompt.index) { info in
                        ReviewRow(
                            info: info,
                            canRetake: !review.progress.endedAtLimit && model.stage == .reviewing,
                            onRetake: { model.retake(index: info.prompt.index) })
                    }
                }
            }
            .safeAreaInset(edge: .bottom) {
                actions
            }
        } else {
            ProgressView()
        }
    }

    private func header(_ review: CaptureReview) -> some View {
        VStack(alignment: .leading, spacing: 8) {
            Text("Check your captures")
                .font(.title2.bold())
            Text(countText(review))
                .font(.subheadline.monospacedDigit())
            if let limit = review.limitMessage {
                Label(limit, systemImage: "clock.badge.exclamationmark")
                    .font(.footnote)
            }
            if review.saved != nil {
                Label("Your capture is saved.", systemImage: "checkmark.circle")
                    .font(.footnote)
            } else {
                Text("Retake any expression that does not look right, then use them.")
                    .font(.footnote)
                    .foregroundStyle(.secondary)
            }
            if model.isDemo {
                Text("Demo: the retakes replay the same recording, so they may not catch the expression.")
                    .font(.footnote)
                    .foregroundStyle(.secondary)
            }
        }
    }

    private var actions: some View {
        VStack(spacing: 10) {
            if let problem = model.reviewProblem {
                Label(problem, systemImage: "exclamationmark.triangle")
                    .font(.footnote)
                    .frame(maxWidth: .infinity, alignment: .leading)
            }
            Button {
                model.confirm()
            } label: {
                if model.stage == .saving {
                    ProgressView()
                        .frame(maxWidth: .infinity)
                } else {
                    Text("Use these captures")
                        .frame(maxWidth: .infinity)
                }
            }
            .buttonStyle(.borderedProminent)
            .controlSize(.large)
            .disabled(model.stage == .saving)
            Button("Discard and start over", role: .destructive, action: onCancel)
                .disabled(model.stage == .saving)
        }
        .padding()
        .background(.bar)
    }

    private func countText(_ review: CaptureReview) -> String {
        let progress = review.progress
        var text = "\(progress.captured) of \(progress.total) captured"
        if progress.skipped > 0 {
            text += ", \(progress.skipped) skipped"
        }
        return text
    }
}
