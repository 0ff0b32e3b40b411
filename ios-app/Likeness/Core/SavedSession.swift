import Foundation
import LikenessFFI

/// A finished capture: the core's session and the file it is saved in
/// (`Unprocessed/…` until processed, then its capture folder; see `Storage`).
struct SavedSession {
    /// The core's handle on the session.
    let handle: SessionHandle
    /// The `.likeness` file.
    let sessionFile: URL

    /// Saves `handle` as a new unprocessed session, atomically (the core
    /// writes a temporary file beside the target and renames it), with the
    /// app's file protection. On the core's thread.
    static func saveUnprocessed(_ handle: SessionHandle) throws -> SavedSession {
        let file = try Storage.newUnprocessedSessionFile()
        try handle.save(path: file.path(percentEncoded: false))
        try Storage.protect(file)
        return SavedSession(handle: handle, sessionFile: file)
    }

    /// Reads the session saved at `file`. On the core's thread.
    static func load(_ file: URL) throws -> SavedSession {
        SavedSession(handle: try SessionHandle.load(path: file.path(percentEncoded: false)), sessionFile: file)
    }
}
