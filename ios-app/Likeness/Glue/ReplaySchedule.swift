import Foundation

/// When to hand a recorded frame to the capture so that a stored session
/// replays at its own speed, over and over.
///
/// The recording's clock is its frames' timestamps; the phone's is the
/// system uptime. `start` pins one to the other (a frame's time to the moment
/// playing begins or goes on after a pause); a frame is due when as much
/// time has passed on the phone as between the two frames in the recording.
/// A replay that reaches the end starts again from the first frame, its
/// timestamps moved on by `loopLength` each time, so they keep increasing as
/// the capture needs.
public struct ReplaySchedule: Equatable {
    /// The recording's time pinned to `uptime`.
    public private(set) var recordedTime: TimeInterval = 0
    /// The phone's uptime pinned to `recordedTime`.
    public private(set) var uptime: TimeInterval = 0
    /// How far each pass moves the timestamps on: the recording's length
    /// plus one frame interval, or `nil` if it has too few frames to repeat.
    public let loopLength: TimeInterval?

    /// - Parameters:
    ///   - first: the first frame's timestamp.
    ///   - second: the second frame's (`nil` with a single frame).
    ///   - last: the last frame's.
    public init(first: TimeInterval, second: TimeInterval?, last: TimeInterval) {
        if let second, second > first, last >= second {
            loopLength = last - first + (second - first)
        } else {
            loopLength = nil
        }
    }

    /// Pins the recording's `recordedTime` to the phone's `uptime`.
    public mutating func start(recordedTime: TimeInterval, uptime: TimeInterval) {
        self.recordedTime = recordedTime
        self.uptime = uptime
    }

    /// Seconds until the frame recorded at `time` is due (zero or less: now).
    public func delay(until time: TimeInterval, now: TimeInterval) -> TimeInterval {
        (time - recordedTime) - (now - uptime)
    }

    /// The timestamp to push for a frame recorded at `time` on pass `pass`
    /// (0 the first), or `nil` if the recording cannot repeat.
    public func timestamp(of time: TimeInterval, pass: Int) -> TimeInterval? {
        if pass == 0 {
            return time
        }
        guard let loopLength else { return nil }
        return time + Double(pass) * loopLength
    }
}
