import SwiftUI

/// Covers the capture while ARKit has lost the face; the core waits, and the
/// capture goes on where it stopped once the face is back.
struct PauseOverlay: View {
    var body: some View {
        ZStack {
            Theme.pauseBackground.ignoresSafeArea()
            VStack(spacing: 12) {
                Image(systemName: "face.dashed")
                    .font(.system(size: 56))
                Text("Paused")
                    .font(.title.bold())
                Text("Your face is out of view. Hold the phone at arm's length and look at the screen; the capture goes on where it stopped.")
                    .multilineTextAlignment(.center)
            }
            .foregroundStyle(.white)
            .padding(32)
        }
    }
}
