import ARKit
import LikenessFFI
import LikenessGlue

/// Replays a recorded session (`subject-1.likeness`, bundled with the app)
/// into a new capture at the speed it was recorded: for an iPhone without a
/// TrueDepth camera, and the simulator.
///
/// The recording is read with `SessionHandle.load(path:)`; its template sets
/// the core up (`template()`), and its frames (`recordedFrame(index:)`) are
/// pushed one by one into a real `CaptureSession`, each when as much time has
/// passed as between it and the previous one in the recording
/// (`ReplaySchedule`). The same screens show it as a live capture. A
/// recording that runs out starts again, its timestamps moved on.
///
/// Everything but `start`/`pause`/`resume`/`stop` runs on the core's thread.
final class DemoFeed: FrameFeed, @unchecked Sendable {
    /// The bundled recording.
    static var recording: URL? {
        Bundle.main.url(forResource: "subject-1", withExtension: Storage.sessionExtension)
    }

    private let runner: CaptureRunner
    private let timer = DispatchQueue(label: "org.likeness.demo", qos: .userInitiated)
    // Touched on the core's thread only.
    private var handle: SessionHandle?
    private var schedule: ReplaySchedule?
    private var frameCount: UInt32 = 0
    private var next: UInt32 = 0
    private var pass = 0
    private var playing = false
    private var generation = 0

    init(runner: CaptureRunner) {
        self.runner = runner
    }

    // MARK: FrameFeed (main thread)

    var arSession: ARSession? { nil }

    func start() {
        CoreQueue.async {
            self.load()
            self.play()
        }
    }

    func pause() {
        CoreQueue.async { self.halt() }
    }

    func resume() {
        CoreQueue.async { self.play() }
    }

    func stop() {
        pause()
    }

    // MARK: Playing (core thread)

    private func load() {
        guard handle == nil else { return }
        guard let file = Self.recording else {
            runner.fail(message: "The demo's recorded capture is missing from the app.")
            return
        }
        do {
            let recording = try SessionHandle.load(path: file.path(percentEncoded: false))
            let count = recording.recordedFrameCount()
            guard count > 0 else {
                runner.fail(message: "The demo's recorded capture has no frames.")
                return
            }
            let first = try recording.recordedFrame(index: 0).timestamp
            var second: TimeInterval?
            if count > 1 {
                second = try recording.recordedFrame(index: 1).timestamp
            }
            let last = try recording.recordedFrame(index: count - 1).timestamp
            schedule = ReplaySchedule(first: first, second: second, last: last)
            frameCount = count
            handle = recording
            runner.begin(device: DeviceModel.identifier) { try recording.template() }
        } catch {
            runner.fail(error)
        }
    }

    private func play() {
        guard handle != nil, !playing else { return }
        playing = true
        generation += 1
        tick(generation, restart: true)
    }

    private func halt() {
        playing = false
        generation += 1
    }

    /// Pushes every frame that is due, then waits for the next one.
    private func tick(_ run: Int, restart: Bool = false) {
        guard playing, run == generation, let handle, var schedule else { return }
        do {
            var pinned = !restart
            while true {
                let frame = try handle.recordedFrame(index: next)
                guard let timestamp = schedule.timestamp(of: frame.timestamp, pass: pass) else {
                    halt()
                    return
                }
                let now = ProcessInfo.processInfo.systemUptime
                if !pinned {
                    schedule.start(recordedTime: timestamp, uptime: now)
                    self.schedule = schedule
                    pinned = true
                }
                let wait = schedule.delay(until: timestamp, now: now)
                if wait > 0 {
                    timer.asyncAfter(deadline: .now() + wait) {
                        CoreQueue.async { self.tick(run) }
                    }
                    return
                }
                runner.push(CaptureFrame(
                    timestamp: timestamp,
                    weights: frame.weights,
                    vertices: ARKitGlue.packed(flat: frame.vertices),
                    tracked: frame.tracked))
                advance()
            }
        } catch {
            halt()
            runner.fail(error)
        }
    }

    private func advance() {
        next += 1
        if next == frameCount {
            next = 0
            pass += 1
        }
    }
}
