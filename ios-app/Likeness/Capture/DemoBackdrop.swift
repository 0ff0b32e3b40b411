import SwiftUI

/// What the demo shows where the camera picture would be: that a recorded
/// capture is playing, since this device has no TrueDepth camera.
struct DemoBackdrop: View {
    var body: some View {
        ZStack {
            Color.black.ignoresSafeArea()
            VStack(spacing: 12) {
                Image(systemName: "play.rectangle")
                    .font(.system(size: 56))
                Text("Demo")
                    .font(.title2.bold())
                Text("A capture recorded on an iPhone with Face ID plays through the real capture, at the speed it was made.")
                    .multilineTextAlignment(.center)
                    .font(.footnote)
            }
            .foregroundStyle(.secondary)
            .padding(32)
        }
    }
}
