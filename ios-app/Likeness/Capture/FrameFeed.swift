import ARKit

/// Where a capture's frames come from: the TrueDepth camera (`CameraFeed`),
/// or a recorded session replayed at its own speed (`DemoFeed`). Either sends
/// them to a `CaptureRunner`. Called on the main thread.
protocol FrameFeed: AnyObject {
    /// The ARKit session to show behind the capture; `nil` for the demo.
    var arSession: ARSession? { get }
    /// Starts sending frames.
    func start()
    /// Stops sending frames for a while: the review, the app away.
    func pause()
    /// Goes on after `pause`.
    func resume()
    /// Stops for good.
    func stop()
}
