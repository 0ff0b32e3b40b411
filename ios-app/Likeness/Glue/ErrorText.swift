import ARKit

/// What went wrong, in words for the person holding the phone.
///
/// The core's errors reach this file as a `CoreFailure` kind plus the core's
/// own message (the app's `CoreErrors.swift` classifies `LikenessError`), so
/// the wording is tested without the core.
public enum ErrorText {
    /// The kinds of failure the core reports, one per `LikenessError` case.
    public enum CoreFailure: Equatable, CaseIterable {
        case invalidInput, file, capture, personalization, avatar, wrongOrder, cancelled, `internal`
    }

    /// A sentence for a failure of the core, ending with the core's own
    /// message when there is one.
    public static func text(for kind: CoreFailure, detail: String?) -> String {
        let lead: String
        switch kind {
        case .invalidInput:
            lead = "The app handed the core something it could not use."
        case .file:
            lead = "A file could not be read or written."
        case .capture:
            lead = "The capture could not go on."
        case .personalization:
            lead = "Your expressions could not be turned into your own shapes."
        case .avatar:
            lead = "Your shapes could not be put on the avatar."
        case .wrongOrder:
            lead = "The app asked the core for a step out of order."
        case .cancelled:
            lead = "Cancelled."
        case .internal:
            lead = "Something went wrong inside the core."
        }
        guard let detail, !detail.isEmpty else { return lead }
        return "\(lead) \(detail)"
    }

    /// A sentence for ARKit's own errors, saying what the person can do.
    public static func text(for error: ARError) -> String {
        switch error.code {
        case .cameraUnauthorized:
            return "Likeness may not use the camera. Allow it in Settings › Likeness › Camera, then try again."
        case .unsupportedConfiguration:
            return "This iPhone cannot track faces: it needs the TrueDepth camera used for Face ID."
        case .sensorUnavailable, .sensorFailed:
            return "The TrueDepth camera is not available right now. Close other camera apps and try again."
        default:
            return "Face tracking stopped: \(error.localizedDescription)"
        }
    }

    /// A sentence for any other error: its own description.
    public static func text(forOther error: Error) -> String {
        if let arError = error as? ARError {
            return text(for: arError)
        }
        return error.localizedDescription
    }
}
