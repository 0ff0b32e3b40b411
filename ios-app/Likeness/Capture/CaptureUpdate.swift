import Foundation
import LikenessFFI

/// What the core's side of the capture (`CaptureRunner`) tells the screen,
/// on the main actor, in order.
enum CaptureUpdate {
    /// A face (or the recording) was found; the core is being set up.
    case preparing
    /// The core is ready; `triangles` are its template's, for pictures.
    case started(triangles: [UInt32])
    /// The core's events for one call, and its progress after them.
    case events([CaptureEvent], CaptureProgress)
    /// The template at a prompt's expression (`nil`: no picture).
    case preview(promptIndex: UInt32, vertices: [Float]?)
    /// The capture was interrupted; the core starts the step under way again.
    case interrupted
    /// A skip or retake the core refused, in words.
    case refused(String)
    /// One frame the core refused and the runner dropped, in words.
    case frameRefused(String)
    /// No step is left: the captures to review.
    case review(CaptureReview)
    /// A retake from the review was taken: the capture goes on.
    case retaking
    /// The person confirmed; the session is saved, ready to process.
    case saved(SavedSession)
    /// The session could not be made or saved, in words; the review stays.
    case saveRefused(String)
    /// The capture cannot go on, in words.
    case failed(String)
}

/// What the review screen shows, all of it the core's.
struct CaptureReview {
    /// Every step and its capture (`CaptureSession.captures()`).
    let captures: [CaptureInfo]
    /// The core's count, and whether the capture ended at its length limit.
    let progress: CaptureProgress
    /// The core's words when the capture reached its length limit.
    let limitMessage: String?
    /// At the length limit the session is saved at once (no retake is
    /// possible); otherwise `nil` until the person confirms.
    let saved: SavedSession?
}
