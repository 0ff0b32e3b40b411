import Foundation

/// Where the app keeps its files, and how it writes them.
///
/// A capture the person confirmed is saved at once, before processing, to
/// `Application Support/Unprocessed/<date time>.likeness` (not shown in the
/// Files app). Once processed, it moves into `Documents/Captures/<date time>/`
/// beside the avatar (`avatar.glb`, or `avatar-<name>.glb` for an avatar the
/// person brought) and its retarget map; Documents is visible in the Files
/// app ("On My iPhone › Likeness"). A session left in `Unprocessed` (the app
/// was closed, processing was cancelled or stopped) is offered on the start
/// screen to resume.
///
/// Every file and folder has the protection `completeUntilFirstUserAuthentication`:
/// encrypted and unreadable from a restart until the first unlock, readable
/// afterwards, so that processing, which goes on in the background for a
/// while, can still read and write when the phone locks. Nothing is ever sent
/// anywhere; files leave the phone only through the share sheet.
enum Storage {
    /// The session file's name inside a capture folder.
    static let sessionFileName = "session.likeness"
    /// The session files' extension.
    static let sessionExtension = "likeness"

    /// The protection of every file and folder the app writes.
    static let protection = FileProtectionType.completeUntilFirstUserAuthentication

    private static var attributes: [FileAttributeKey: Any] {
        [.protectionKey: protection]
    }

    /// The avatar's and the retarget map's file names: `avatar.glb` for the
    /// default avatar, `avatar-robot.glb` for `robot.glb`.
    static func exportNames(avatarName: String?) -> (avatar: String, retargetMap: String) {
        guard let avatarName else { return ("avatar.glb", "retarget-map.json") }
        let stem = URL(fileURLWithPath: avatarName).deletingPathExtension().lastPathComponent
        return ("avatar-\(stem).glb", "retarget-map-\(stem).json")
    }

    /// `Documents/Captures`, made if missing.
    static func capturesFolder() throws -> URL {
        let documents = try FileManager.default.url(
            for: .documentDirectory, in: .userDomainMask, appropriateFor: nil, create: true)
        return try folder(documents.appendingPathComponent("Captures", isDirectory: true))
    }

    /// `Application Support/Unprocessed`, made if missing.
    static func unprocessedFolder() throws -> URL {
        let support = try FileManager.default.url(
            for: .applicationSupportDirectory, in: .userDomainMask, appropriateFor: nil, create: true)
        return try folder(support.appendingPathComponent("Unprocessed", isDirectory: true))
    }

    /// A new file name for a confirmed, not yet processed session.
    static func newUnprocessedSessionFile(date: Date = Date()) throws -> URL {
        let folder = try unprocessedFolder()
        let stem = stamp(date)
        var file = folder.appendingPathComponent(stem).appendingPathExtension(sessionExtension)
        var number = 1
        while FileManager.default.fileExists(atPath: file.path(percentEncoded: false)) {
            number += 1
            file = folder.appendingPathComponent("\(stem) \(number)").appendingPathExtension(sessionExtension)
        }
        return file
    }

    /// The most recent session saved but not processed, if there is one.
    static func unprocessedSessionFile() -> URL? {
        guard let folder = try? unprocessedFolder(),
              let entries = try? FileManager.default.contentsOfDirectory(
                  at: folder, includingPropertiesForKeys: nil, options: [.skipsHiddenFiles])
        else { return nil }
        // Names are dates that sort as text.
        return entries
            .filter { $0.pathExtension == sessionExtension }
            .max { $0.lastPathComponent < $1.lastPathComponent }
    }

    /// Whether `file` is a session waiting in `Unprocessed`.
    static func isUnprocessed(_ file: URL) -> Bool {
        guard let folder = try? unprocessedFolder() else { return false }
        return file.deletingLastPathComponent().resolvingSymlinksInPath().pathComponents
            == folder.resolvingSymlinksInPath().pathComponents
    }

    /// The capture folder an unprocessed session moves into, named after it.
    static func captureFolder(for unprocessed: URL) throws -> URL {
        let name = unprocessed.deletingPathExtension().lastPathComponent
        return try folder(try capturesFolder().appendingPathComponent(name, isDirectory: true))
    }

    /// The session file of the most recent processed capture, if there is one.
    static func latestSessionFile() -> URL? {
        guard let folder = try? capturesFolder(),
              let entries = try? FileManager.default.contentsOfDirectory(
                  at: folder, includingPropertiesForKeys: nil, options: [.skipsHiddenFiles])
        else { return nil }
        // Folder names are dates that sort as text.
        let newestFirst = entries.sorted { $0.lastPathComponent > $1.lastPathComponent }
        return newestFirst
            .map { $0.appendingPathComponent(sessionFileName) }
            .first { FileManager.default.fileExists(atPath: $0.path(percentEncoded: false)) }
    }

    /// Writes `data` to `url` atomically (a temporary file renamed), with the
    /// app's file protection.
    static func write(_ data: Data, to url: URL) throws {
        try data.write(to: url, options: [.atomic, .completeFileProtectionUntilFirstUserAuthentication])
    }

    /// Gives a file someone else wrote (the core saves the session itself)
    /// the app's file protection.
    static func protect(_ url: URL) throws {
        try FileManager.default.setAttributes(attributes, ofItemAtPath: url.path(percentEncoded: false))
    }

    /// Moves `file` to `destination` (a rename within the app's container),
    /// replacing what is there.
    static func move(_ file: URL, to destination: URL) throws {
        if FileManager.default.fileExists(atPath: destination.path(percentEncoded: false)) {
            _ = try FileManager.default.replaceItemAt(destination, withItemAt: file)
        } else {
            try FileManager.default.moveItem(at: file, to: destination)
        }
        try protect(destination)
    }

    /// Deletes `file` (an unprocessed session the person discarded).
    static func discard(_ file: URL) throws {
        try FileManager.default.removeItem(at: file)
    }

    private static func folder(_ url: URL) throws -> URL {
        try FileManager.default.createDirectory(at: url, withIntermediateDirectories: true, attributes: attributes)
        try protect(url)
        return url
    }

    private static func stamp(_ date: Date) -> String {
        let formatter = DateFormatter()
        formatter.locale = Locale(identifier: "en_US_POSIX")
        formatter.dateFormat = "yyyy-MM-dd HH.mm.ss"
        return formatter.string(from: date)
    }
}
