import LikenessFFI
import SwiftUI

/// One step on the review: what was asked, how strongly the expression was
/// made at the capture (the core's prompted weight, as a bar), what the core
/// found wrong with it, whether it was skipped, and a Retake.
struct ReviewRow: View {
    let info: CaptureInfo
    let canRetake: Bool
    let onRetake: () -> Void

    var body: some View {
        HStack(alignment: .top, spacing: 12) {
            VStack(alignment: .leading, spacing: 6) {
                Text(info.prompt.instruction)
                    .font(.subheadline.weight(.semibold))
                    .fixedSize(horizontal: false, vertical: true)
                Text(info.prompt.name)
                    .font(.caption.monospaced())
                    .foregroundStyle(.secondary)
                if let weight = info.weight {
                    WeightBar(weight: weight)
                }
                status
                ForEach(info.warnings, id: \.self) { warning in
                    Label(warning, systemImage: "exclamationmark.triangle.fill")
                        .font(.caption)
                        .foregroundStyle(.orange)
                }
            }
            Spacer(minLength: 0)
            Button("Retake", action: onRetake)
                .buttonStyle(.bordered)
                .disabled(!canRetake)
                .accessibilityLabel("Retake \(info.prompt.instruction)")
        }
        .padding(.vertical, 4)
    }

    @ViewBuilder private var status: some View {
        if info.skipped {
            Label("Skipped", systemImage: "forward.fill")
                .font(.caption)
                .foregroundStyle(.secondary)
        } else if info.frame == nil {
            Label("Not captured", systemImage: "circle.dashed")
                .font(.caption)
                .foregroundStyle(.secondary)
        }
    }
}

/// The prompted weight at the capture (0–1, the core's), as a bar.
private struct WeightBar: View {
    let weight: Float

    var body: some View {
        let shown = Double(min(max(weight, 0), 1))
        ProgressView(value: shown)
            .frame(maxWidth: Theme.weightBarWidth)
            .accessibilityLabel("Strength \(Int((shown * 100).rounded())) percent")
    }
}
