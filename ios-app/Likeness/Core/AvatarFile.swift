import Foundation
import LikenessFFI
import UniformTypeIdentifiers

/// An avatar the person brought: a `.glb` or `.gltf` from Files or AirDrop,
/// read by the core once (`AvatarPreview`) so a file it cannot use is refused
/// at once, in its words.
struct ChosenAvatar {
    /// The file's name, for the screen and the exported files.
    let name: String
    /// The file's bytes, as `PersonalizedFace.avatar(avatarGlb:)` takes them.
    let bytes: Data
    /// How many of ARKit's shapes the core found in it…
    let shapesFound: UInt32
    /// …of how many (`arkitNames().count`).
    let shapeTotal: Int
}

/// Reading avatar files.
enum AvatarFile {
    /// What the file importer offers: glTF binary (`.glb`) and glTF JSON
    /// (`.gltf`), as declared in Info.plist.
    static let contentTypes: [UTType] = {
        let types = ["glb", "gltf"].compactMap { UTType(filenameExtension: $0) }
        return types.isEmpty ? [.data] : types
    }()

    /// Reads the file at `url` (security-scoped: a file picked in Files or
    /// opened in place from another app) and has the core check it. Off the
    /// main thread; the check runs on the core's thread.
    static func read(_ url: URL, then deliver: @escaping @MainActor (Result<ChosenAvatar, Error>) -> Void) {
        DispatchQueue.global(qos: .userInitiated).async {
            let bytes = Result { try readBytes(url) }
            CoreQueue.async {
                let checked: Result<ChosenAvatar, Error> = bytes.flatMap { data in
                    Result { () throws -> ChosenAvatar in
                        let preview = try AvatarPreview(glb: data)
                        return ChosenAvatar(
                            name: url.lastPathComponent, bytes: data,
                            shapesFound: preview.shapesFound(), shapeTotal: arkitNames().count)
                    }
                }
                CoreQueue.onMain { deliver(checked) }
            }
        }
    }

    private static func readBytes(_ url: URL) throws -> Data {
        let scoped = url.startAccessingSecurityScopedResource()
        let bytes = Result { try Data(contentsOf: url) }
        if scoped {
            url.stopAccessingSecurityScopedResource()
        }
        return try bytes.get()
    }
}
