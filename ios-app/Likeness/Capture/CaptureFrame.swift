import Foundation

/// One frame on its way to the core, read out of ARKit (or a recording) into
/// plain values, so no `ARFrame` is held while it waits for the core's thread.
struct CaptureFrame {
    /// `ARFrame.timestamp` (s), or the recorded frame's.
    let timestamp: TimeInterval
    /// The 52 weights in the core's order; `nil` when no face is tracked
    /// (the runner then sends the last weights it sent, or zeros).
    let weights: [Float]?
    /// The face mesh, packed as `pushFramePacked` takes it; empty when no
    /// face is tracked.
    let vertices: Data
    /// Whether a face is tracked in this frame.
    let tracked: Bool

    /// A frame in which ARKit tracks no face: the core hears it and pauses.
    static func untracked(at timestamp: TimeInterval) -> CaptureFrame {
        CaptureFrame(timestamp: timestamp, weights: nil, vertices: Data(), tracked: false)
    }
}
