import Foundation
import LikenessFFI

/// A finished capture: the core's session and where it is saved.
struct SavedSession {
    /// The core's handle on the session.
    let handle: SessionHandle
    /// The capture's folder (see `Storage`).
    let folder: URL
    /// The `.likeness` file inside it.
    let sessionFile: URL
}
