import Foundation

/// The phone's hardware model identifier (for example `iPhone15,2`), which the
/// core records in the session file so a capture says which camera made it.
public enum DeviceModel {
    /// `utsname.machine`, e.g. `iPhone15,2`; on a simulator, the host's
    /// architecture (`arm64`).
    public static var identifier: String {
        var info = utsname()
        uname(&info)
        return withUnsafeBytes(of: &info.machine) { raw in
            String(decoding: raw.prefix { $0 != 0 }, as: UTF8.self)
        }
    }
}
