import ARKit
import LikenessFFI
import SwiftUI

/// The first screen: whether this iPhone can do it, what will happen, and
/// that nothing leaves the phone.
struct StartView: View {
    /// Why reopening the last capture failed, if it did.
    let problem: String?
    let onBegin: () -> Void
    let onReprocess: (URL) -> Void

    @State private var lastSession: URL?

    var body: some View {
        ScrollView {
            VStack(alignment: .leading, spacing: 24) {
                Text("Likeness")
                    .font(.largeTitle.bold())
                if ARFaceTrackingConfiguration.isSupported {
                    supported
                } else {
                    unsupported
                }
            }
            .padding()
        }
        .onAppear { lastSession = Storage.latestSessionFile() }
    }

    private var supported: some View {
        VStack(alignment: .leading, spacing: 20) {
            Text("Teach your avatar your own expressions.")
                .font(.title3)
            Step(systemImage: "timer", text: "It takes about two minutes.")
            Step(systemImage: "face.smiling",
                 text: "You make about \(arkitNames().count + 1) faces: a relaxed one first, then one expression at a time, each shown and described on screen.")
            Step(systemImage: "iphone",
                 text: "Hold the phone at arm's length, level with your face, in even light. If your face leaves the view, the capture pauses until you are back.")
            Step(systemImage: "lock.shield",
                 text: "Nothing leaves this iPhone. The app contains no networking code; your capture and avatar are kept encrypted on the phone and leave it only if you share them.")
            Button(action: onBegin) {
                Text("Begin")
                    .frame(maxWidth: .infinity)
            }
            .buttonStyle(.borderedProminent)
            .controlSize(.large)
            if let lastSession {
                Button {
                    onReprocess(lastSession)
                } label: {
                    Text("Process my last capture again")
                        .frame(maxWidth: .infinity)
                }
                .buttonStyle(.bordered)
            }
            if let problem {
                Label(problem, systemImage: "exclamationmark.triangle")
                    .font(.footnote)
            }
        }
    }

    private var unsupported: some View {
        VStack(alignment: .leading, spacing: 16) {
            Label("This device can't capture faces", systemImage: "xmark.octagon")
                .font(.title3.bold())
            Text("Likeness follows your face with the TrueDepth camera, the front camera used for Face ID. This device has none, so it cannot make a capture.")
            Text("Use an iPhone with Face ID.")
                .foregroundStyle(.secondary)
        }
    }
}

/// One line of what will happen.
private struct Step: View {
    let systemImage: String
    let text: String

    var body: some View {
        Label {
            Text(text)
        } icon: {
            Image(systemName: systemImage)
                .foregroundStyle(.tint)
        }
    }
}
