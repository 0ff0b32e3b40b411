import Foundation

/// Where the app keeps its files, and how it writes them.
///
/// Every capture gets a folder `Documents/Captures/<date time>/` holding the
/// session (`session.likeness`), the avatar (`avatar.glb`) and the retarget
/// map (`retarget-map.json`). Documents is visible in the Files app
/// ("On My iPhone › Likeness"). Every file and folder is written with
/// complete file protection: encrypted and unreadable while the phone is
/// locked. Nothing is ever sent anywhere; files leave the phone only through
/// the share sheet.
enum Storage {
    /// The session file's name inside a capture folder.
    static let sessionFileName = "session.likeness"
    /// The avatar's file name.
    static let avatarFileName = "avatar.glb"
    /// The retarget map's file name.
    static let retargetMapFileName = "retarget-map.json"

    private static var protection: [FileAttributeKey: Any] {
        [.protectionKey: FileProtectionType.complete]
    }

    /// `Documents/Captures`, made if missing.
    static func capturesFolder() throws -> URL {
        let documents = try FileManager.default.url(
            for: .documentDirectory, in: .userDomainMask, appropriateFor: nil, create: true)
        let folder = documents.appendingPathComponent("Captures", isDirectory: true)
        try FileManager.default.createDirectory(
            at: folder, withIntermediateDirectories: true, attributes: protection)
        return folder
    }

    /// A new, empty capture folder named after `date`.
    static func newCaptureFolder(date: Date = Date()) throws -> URL {
        let formatter = DateFormatter()
        formatter.locale = Locale(identifier: "en_US_POSIX")
        formatter.dateFormat = "yyyy-MM-dd HH.mm.ss"
        let folder = try capturesFolder()
            .appendingPathComponent(formatter.string(from: date), isDirectory: true)
        try FileManager.default.createDirectory(
            at: folder, withIntermediateDirectories: true, attributes: protection)
        return folder
    }

    /// The session file of the most recent capture, if there is one.
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

    /// Writes `data` to `url` atomically, with complete file protection.
    static func write(_ data: Data, to url: URL) throws {
        try data.write(to: url, options: [.atomic, .completeFileProtection])
    }

    /// Gives a file someone else wrote (the core saves the session itself)
    /// complete file protection.
    static func protect(_ url: URL) throws {
        try FileManager.default.setAttributes(protection, ofItemAtPath: url.path(percentEncoded: false))
    }
}
