import Foundation
import LikenessFFI
import LikenessGlue

/// Turns any error the app meets into a sentence for the screen.
///
/// The core throws `LikenessError`, whose cases the bindings spell in
/// UpperCamelCase: `.InvalidInput`, `.File`, `.Capture`, `.Personalization`,
/// `.Avatar`, `.WrongOrder`, `.Cancelled` and `.Internal` (the generated doc
/// comment above the enum, copied from Rust, still says `.invalidInput` and
/// `.cancelled`, which do not exist). A Rust panic arrives as another error.
enum CoreErrors {
    /// The sentence for `error`: the core's errors by kind with the core's
    /// message, ARKit's with what to do, anything else as it describes itself.
    static func message(for error: Error) -> String {
        if let coreError = error as? LikenessError {
            let (kind, detail) = classify(coreError)
            return ErrorText.text(for: kind, detail: detail)
        }
        return ErrorText.text(forOther: error)
    }

    /// Whether `error` is the core stopping because the person cancelled.
    static func isCancellation(_ error: Error) -> Bool {
        guard let coreError = error as? LikenessError else { return false }
        return classify(coreError).0 == .cancelled
    }

    /// The kind of a core error and its message.
    static func classify(_ error: LikenessError) -> (ErrorText.CoreFailure, String?) {
        switch error {
        case .InvalidInput(let message):
            return (.invalidInput, message)
        case .File(let message):
            return (.file, message)
        case .Capture(let message):
            return (.capture, message)
        case .Personalization(let message):
            return (.personalization, message)
        case .Avatar(let message):
            return (.avatar, message)
        case .WrongOrder(let message):
            return (.wrongOrder, message)
        case .Cancelled:
            return (.cancelled, nil)
        case .Internal(let message):
            return (.internal, message)
        }
    }
}
