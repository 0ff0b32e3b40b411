import SwiftUI
import UIKit

/// The result: the person's own face shapes and their avatar moving with them
/// (a mirror), what the core says about the capture and the avatar, and the
/// files to share.
///
/// SceneKit cannot read GLB and the app takes no third-party packages, so the
/// avatar preview is the core's: `AvatarPreview` reads the GLB just written and
/// poses it by the live weights, and the app draws its one triangle list in
/// clay. The GLB goes out through the share sheet to Blender, Unity, Reality
/// Composer or any glTF viewer.
struct ResultView: View {
    let model: ResultModel
    /// Back to the start screen.
    let onStartOver: () -> Void

    var body: some View {
        ScrollView {
            VStack(alignment: .leading, spacing: 20) {
                Text("Your likeness")
                    .font(.largeTitle.bold())
                mirror
                summary
                ShareSection(files: model.files)
                Button("Start over", action: onStartOver)
                    .buttonStyle(.bordered)
                    .frame(maxWidth: .infinity)
            }
            .padding()
        }
        .onAppear { model.startMirror() }
        .onDisappear { model.stopMirror() }
    }

    private var mirror: some View {
        VStack(spacing: 8) {
            HStack(spacing: 8) {
                MeshView(node: model.mirrorNode, continuous: true)
                    .accessibilityLabel("Your personalized face, moving with you")
                MeshView(node: model.avatarNode, continuous: true)
                    .accessibilityLabel("Your avatar, moving with you")
            }
            .frame(maxWidth: .infinity)
            .frame(height: Theme.mirrorHeight)
            .background(Color(.secondarySystemBackground), in: RoundedRectangle(cornerRadius: Theme.cornerRadius))
            if let problem = model.mirrorProblem {
                Label(problem, systemImage: "exclamationmark.triangle")
                    .font(.footnote)
            } else {
                Text("Your own 52 expressions and your avatar, driven live by your face. Try a smile.")
                    .font(.footnote)
                    .foregroundStyle(.secondary)
            }
        }
    }

    private var summary: some View {
        VStack(alignment: .leading, spacing: 8) {
            Text(model.quality.headline)
                .font(.headline)
            Label(
                model.ownFace ? "Your avatar has your face, from your neutral scan" : "Your avatar keeps its own face",
                systemImage: model.ownFace ? "person.crop.circle.badge.checkmark" : "person.crop.circle")
                .font(.subheadline)
            Text(model.avatarSummary)
            ForEach(model.quality.warnings + model.avatarWarnings, id: \.self) { warning in
                Label(warning, systemImage: "exclamationmark.triangle")
                    .font(.footnote)
            }
            if !model.quality.skipped.isEmpty {
                Text("Skipped: \(model.quality.skipped.joined(separator: ", "))")
                    .font(.footnote)
                    .foregroundStyle(.secondary)
            }
            Text("Method: \(model.method)")
                .font(.footnote)
                .foregroundStyle(.secondary)
        }
    }
}
