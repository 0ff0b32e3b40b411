import Foundation
import LikenessFFI

/// The three files a person can share after processing.
struct ExportFiles {
    /// The avatar with the person's 52 ARKit blendshapes (`avatar.glb`).
    let avatar: URL
    /// The capture session (`session.likeness`), to personalize again later
    /// or on a computer with the `likeness` command.
    let session: URL
    /// Which avatar targets each ARKit weight drives (`retarget-map.json`).
    let retargetMap: URL

    /// All three, for "share everything".
    var all: [URL] { [avatar, session, retargetMap] }

    /// Writes the avatar and its retarget map next to the saved session, with
    /// complete file protection.
    static func write(_ result: AvatarResult, beside saved: SavedSession) throws -> ExportFiles {
        let avatar = saved.folder.appendingPathComponent(Storage.avatarFileName)
        let map = saved.folder.appendingPathComponent(Storage.retargetMapFileName)
        try Storage.write(result.glb, to: avatar)
        try Storage.write(Data(result.retargetMapJson.utf8), to: map)
        return ExportFiles(avatar: avatar, session: saved.sessionFile, retargetMap: map)
    }
}
