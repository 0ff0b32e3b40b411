import Foundation
import LikenessFFI

/// The three files a person can share after processing.
struct ExportFiles {
    /// The avatar with the person's 52 ARKit blendshapes.
    let avatar: URL
    /// The capture session (`session.likeness`), to personalize again later
    /// or on a computer with the `likeness` command.
    let session: URL
    /// Which avatar targets each ARKit weight drives.
    let retargetMap: URL

    /// All three, for "share everything".
    var all: [URL] { [avatar, session, retargetMap] }

    /// Writes the avatar and its retarget map into the capture's folder, and
    /// moves an unprocessed session in beside them last (until then it stays
    /// where the start screen offers to resume it). Returns the files and the
    /// session where it now is. On the core's thread.
    static func write(
        _ result: AvatarResult, avatarName: String?, for saved: SavedSession
    ) throws -> (ExportFiles, SavedSession) {
        let unprocessed = Storage.isUnprocessed(saved.sessionFile)
        let folder: URL
        if unprocessed {
            folder = try Storage.captureFolder(for: saved.sessionFile)
        } else {
            folder = saved.sessionFile.deletingLastPathComponent()
        }
        let names = Storage.exportNames(avatarName: avatarName)
        let avatar = folder.appendingPathComponent(names.avatar)
        let map = folder.appendingPathComponent(names.retargetMap)
        try Storage.write(result.glb, to: avatar)
        try Storage.write(Data(result.retargetMapJson.utf8), to: map)
        var session = saved.sessionFile
        if unprocessed {
            session = folder.appendingPathComponent(Storage.sessionFileName)
            try Storage.move(saved.sessionFile, to: session)
        }
        let files = ExportFiles(avatar: avatar, session: session, retargetMap: map)
        return (files, SavedSession(handle: saved.handle, sessionFile: session))
    }
}
