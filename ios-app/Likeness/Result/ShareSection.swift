import SwiftUI

/// The files, offered through the system share sheet (AirDrop, Files, Mail…).
/// Nothing is sent unless the person picks a destination there.
struct ShareSection: View {
    let files: ExportFiles

    var body: some View {
        VStack(alignment: .leading, spacing: 12) {
            Text("Share")
                .font(.title2.bold())
            ShareLink(items: files.all) {
                Label("Everything (avatar, session, retarget map)", systemImage: "square.and.arrow.up.on.square")
            }
            .buttonStyle(.borderedProminent)
            ShareLink(item: files.avatar) {
                Label("Avatar (.glb)", systemImage: "person.crop.square")
            }
            ShareLink(item: files.session) {
                Label("Capture session (.likeness)", systemImage: "face.smiling")
            }
            ShareLink(item: files.retargetMap) {
                Label("Retarget map (.json)", systemImage: "arrow.triangle.branch")
            }
            Text("The files are also in the Files app, under On My iPhone › Likeness › Captures.")
                .font(.footnote)
                .foregroundStyle(.secondary)
        }
    }
}
