import SwiftUI

/// Which avatar the person's expressions go on: the core's default, or one
/// they bring (`.glb` or `.gltf`, picked in Files here or opened in the app
/// from Files or AirDrop). A file the core refuses is explained in its words.
struct AvatarChoice: View {
    let flow: AppFlow
    /// The button's title.
    var pickTitle = "Use my own avatar…"

    @State private var isImporting = false

    var body: some View {
        VStack(alignment: .leading, spacing: 8) {
            if let avatar = flow.avatar {
                Label(
                    "Avatar: \(avatar.name), with \(avatar.shapesFound) of \(avatar.shapeTotal) ARKit expressions",
                    systemImage: "person.crop.square")
            } else {
                Label("Avatar: the default avatar", systemImage: "person.crop.square")
            }
            HStack {
                Button(pickTitle) { isImporting = true }
                    .buttonStyle(.bordered)
                    .disabled(flow.isReadingAvatar)
                if flow.avatar != nil {
                    Button("Use the default") { flow.useDefaultAvatar() }
                        .buttonStyle(.bordered)
                        .disabled(flow.isReadingAvatar)
                }
                if flow.isReadingAvatar {
                    ProgressView()
                }
            }
            if let problem = flow.avatarProblem {
                Label(problem, systemImage: "exclamationmark.triangle")
                    .font(.footnote)
            }
        }
        .fileImporter(isPresented: $isImporting, allowedContentTypes: AvatarFile.contentTypes) { result in
            switch result {
            case .success(let url):
                flow.openAvatar(at: url)
            case .failure(let error):
                flow.avatarImportFailed(error)
            }
        }
    }
}
