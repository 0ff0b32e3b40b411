/// Counts the camera frames the core refused, so that one bad frame is
/// dropped and the capture goes on, while a run of them stops it.
///
/// A policy of the screen, not a capture rule: which frame is refused, and
/// why, is the core's decision; this only decides how many refusals in a row
/// the person sees as a passing notice before the capture stops with the
/// core's message.
public struct FrameRefusals: Equatable {
    /// Refused frames in a row that stop the capture: half a second of
    /// ARKit's 60 frames a second. One refused frame (a glitch in a single
    /// ARKit mesh) is dropped with a notice; this many in a row mean the
    /// frames are wrong for good, and going on would only hide it. UI policy,
    /// not a capture threshold.
    public static let stopAfterInARow = 30

    /// Refused frames since the last accepted one.
    public private(set) var inARow = 0
    /// Refused frames in the whole capture.
    public private(set) var total = 0

    public init() {}

    /// Counts a refused frame; whether the capture should stop now.
    public mutating func refused() -> Bool {
        inARow += 1
        total += 1
        return inARow >= Self.stopAfterInARow
    }

    /// Counts an accepted frame: the run of refusals is over.
    public mutating func accepted() {
        inARow = 0
    }
}
