import LikenessFFI
import SceneKit
import SwiftUI

/// The current request: a picture of the expression (the generic face making
/// it) beside the core's instruction, and what the core said about the last
/// capture.
struct PromptCard: View {
    let prompt: Prompt
    let previewNode: SCNNode
    let hasPreview: Bool
    let warnings: [String]
    let notice: String?

    var body: some View {
        VStack(alignment: .leading, spacing: 10) {
            HStack(alignment: .center, spacing: 14) {
                picture
                Text(prompt.instruction)
                    .font(.title3.weight(.semibold))
                    .fixedSize(horizontal: false, vertical: true)
            }
            ForEach(warnings, id: \.self) { warning in
                Label(warning, systemImage: "exclamationmark.triangle.fill")
                    .font(.footnote)
                    .foregroundStyle(.yellow)
            }
            if let notice {
                Label(notice, systemImage: "info.circle")
                    .font(.footnote)
            }
        }
        .foregroundStyle(.white)
        .padding()
        .frame(maxWidth: .infinity, alignment: .leading)
        .background(Theme.cardBackground, in: RoundedRectangle(cornerRadius: Theme.cornerRadius))
    }

    @ViewBuilder private var picture: some View {
        if hasPreview {
            MeshView(node: previewNode)
                .frame(width: Theme.previewSide, height: Theme.previewSide)
                .accessibilityHidden(true)
        } else {
            Image(systemName: prompt.isNeutral ? "face.smiling" : "theatermasks")
                .font(.system(size: 44))
                .frame(width: Theme.previewSide, height: Theme.previewSide)
                .accessibilityHidden(true)
        }
    }
}
