import SwiftUI

/// Likeness: hold the phone for about two minutes, make the faces it asks
/// for, and get an avatar that moves the way your face does.
///
/// The app is the screens and the ARKit glue only; every rule (which faces,
/// in which order, when one counts, what is wrong with it) is the Rust core's,
/// reached through the `LikenessFFI` module.
@main
struct LikenessApp: App {
    @State private var flow = AppFlow()

    var body: some Scene {
        WindowGroup {
            RootView(flow: flow)
                // A .glb or .gltf opened from Files or AirDrop (Info.plist
                // declares both): the person's own avatar.
                .onOpenURL { url in flow.openAvatar(at: url) }
        }
    }
}
