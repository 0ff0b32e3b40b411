import ARKit
import LikenessFFI
import SwiftUI

/// The first screen: what will happen and that nothing leaves the phone;
/// Begin on an iPhone with a TrueDepth camera, the demo elsewhere (and in the
/// simulator); Resume for a capture saved but not yet processed; processing
/// the last capture again; and which avatar the expressions go on.
struct StartView: View {
    let flow: AppFlow

    @State private var unprocessed: URL?
    @State private var lastSession: URL?
    @State private var confirmsDiscard = false

    var body: some View {
        ScrollView {
            VStack(alignment: .leading, spacing: 24) {
                Text("Likeness")
                    .font(.largeTitle.bold())
                if ARFaceTrackingConfiguration.isSupported {
                    supported
                } else {
                    demo
                }
                if let unprocessed {
                    resume(unprocessed)
                }
                if let lastSession {
                    Button {
                        flow.process(sessionFile: lastSession)
                    } label: {
                        Text("Process my last capture again")
                            .frame(maxWidth: .infinity)
                    }
                    .buttonStyle(.bordered)
                }
                AvatarChoice(flow: flow)
                if let problem = flow.startProblem {
                    Label(problem, systemImage: "exclamationmark.triangle")
                        .font(.footnote)
                }
            }
            .padding()
        }
        .onAppear(perform: refresh)
    }

    private func refresh() {
        unprocessed = Storage.unprocessedSessionFile()
        lastSession = Storage.latestSessionFile()
    }

    private var supported: some View {
        VStack(alignment: .leading, spacing: 20) {
            Text("Teach your avatar your own expressions.")
                .font(.title3)
            Step(systemImage: "timer", text: "It takes about two minutes.")
            Step(systemImage: "face.smiling",
                 text: "You make about \(arkitNames().count + 1) faces: a relaxed one first, then one expression at a time, each shown and described on screen. You check them all before anything is made.")
            Step(systemImage: "iphone",
                 text: "Hold the phone at arm's length, level with your face, in even light. If your face leaves the view, the capture pauses until you are back.")
            privacy
            Button(action: { flow.startCapture() }) {
                Text("Begin")
                    .frame(maxWidth: .infinity)
            }
            .buttonStyle(.borderedProminent)
            .controlSize(.large)
        }
    }

    private var demo: some View {
        VStack(alignment: .leading, spacing: 16) {
            Text("Teach your avatar your own expressions.")
                .font(.title3)
            Step(systemImage: "faceid",
                 text: "Capturing your face needs the TrueDepth camera of an iPhone with Face ID, which this device does not have.")
            Step(systemImage: "play.rectangle",
                 text: "The demo plays a capture recorded on such an iPhone through the same screens, at the speed it was made: the prompts, the review, the processing and the avatar.")
            privacy
            Button(action: { flow.startDemo() }) {
                Text("Try the demo")
                    .frame(maxWidth: .infinity)
            }
            .buttonStyle(.borderedProminent)
            .controlSize(.large)
        }
    }

    private var privacy: some View {
        Step(systemImage: "lock.shield",
             text: "Nothing leaves this iPhone. The app contains no networking code; your capture and avatar are kept encrypted on the phone and leave it only if you share them.")
    }

    private func resume(_ file: URL) -> some View {
        VStack(alignment: .leading, spacing: 10) {
            Label("A capture is saved but not yet made into an avatar.", systemImage: "tray.full")
                .font(.headline)
            HStack {
                Button("Resume") { flow.process(sessionFile: file) }
                    .buttonStyle(.borderedProminent)
                Button("Discard", role: .destructive) { confirmsDiscard = true }
                    .buttonStyle(.bordered)
            }
        }
        .confirmationDialog("Delete this capture?", isPresented: $confirmsDiscard, titleVisibility: .visible) {
            Button("Delete", role: .destructive) {
                flow.discard(sessionFile: file)
                refresh()
            }
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
