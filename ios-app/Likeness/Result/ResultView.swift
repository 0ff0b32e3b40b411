import SwiftUI
import UIKit

/// The result: the person's own face shapes and their avatar moving with them
/// (a mirror), which avatar it is and whose face it has, what the core says
/// about the capture and the avatar, another avatar to try, and the files to
/// share.
///
/// SceneKit cannot read GLB and the app takes no third-party packages, so the
/// avatar preview is the core's: `AvatarPreview.morphMesh()` hands over the
/// GLB just written as one mesh with its ARKit shapes, built into SceneKit
/// once, and the live weights play it. The GLB goes out through the share
/// sheet to Blender, Unity, Reality Composer or any glTF viewer.
struct ResultView: View {
    let model: ResultModel
    let flow: AppFlow

    var body: some View {
        ScrollView {
            VStack(alignment: .leading, spacing: 20) {
                Text("Your likeness")
                    .font(.largeTitle.bold())
                mirror
                summary
                AvatarChoice(flow: flow, pickTitle: "Try it on my own avatar…")
                ShareSection(files: model.files)
                Button("Start over") { flow.startOver() }
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
                Text("Your own expressions and your avatar, driven live by your face. Try a smile.")
                    .font(.footnote)
                    .foregroundStyle(.secondary)
            }
        }
    }

    private var summary: some View {
        VStack(alignment: .leading, spacing: 8) {
            Text(model.quality.headline)
                .font(.headline)
            Label(faceText, systemImage: model.ownFace ? "person.crop.circle.badge.checkmark" : "person.crop.circle")
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

    /// Whose face the avatar has at rest, as the core decided.
    private var faceText: String {
        let avatar = model.avatarName ?? "The default avatar"
        return model.ownFace
            ? "\(avatar) has your face, from your neutral scan, and your expressions"
            : "\(avatar) keeps its own face and makes your expressions"
    }
}
