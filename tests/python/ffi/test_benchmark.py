"""The cost of push_frame and push_frame_packed with a 1,220-vertex mesh,
called from Python through the FFI: measured on every frame of the
full-mesh replay (8,461 frames), printed, never asserted."""

import statistics
import time


def percentile(values, share):
    ordered = sorted(values)
    return ordered[min(len(ordered) - 1, int(share * len(ordered)))]


def lowering_seconds(ffi, vertices, repeat):
    """Python's half alone: UniFFI's generated code writing the 3,660
    floats into a buffer, as push_frame does before calling Rust (a
    private converter of the generated module, at the pinned UniFFI)."""
    converter = ffi._UniffiFfiConverterSequenceFloat32
    seconds = []
    for _ in range(repeat):
        started = time.perf_counter()
        converter.check_lower(vertices)
        builder = ffi._UniffiRustBufferBuilder()
        converter.write(vertices, builder)
        builder.discard()
        seconds.append(time.perf_counter() - started)
    return seconds


def test_push_frame_cost(ffi, full_replay, full_replay_packed, subject_1_replay, subject_1, capsys):
    with_mesh = [s for s, m in zip(full_replay.push_seconds, full_replay.with_mesh) if m]
    packed = [s for s, m in zip(full_replay_packed.push_seconds, full_replay_packed.with_mesh) if m]
    assert len(with_mesh) >= 1000
    assert len(subject_1.template().neutral) == 1220 * 3
    without = [s for s, m in zip(subject_1_replay.push_seconds, subject_1_replay.with_mesh) if not m]
    lowering = lowering_seconds(ffi, subject_1.template().neutral, 1000)
    with capsys.disabled():
        print(
            f"\npush_frame with a 1,220-vertex mesh, {len(with_mesh)} frames: "
            f"median {statistics.median(with_mesh) * 1e3:.3f} ms, "
            f"p99 {percentile(with_mesh, 0.99) * 1e3:.3f} ms; "
            f"of which Python lowering the mesh: median "
            f"{statistics.median(lowering) * 1e3:.3f} ms; "
            f"push_frame_packed (struct.pack included): median "
            f"{statistics.median(packed) * 1e3:.3f} ms, "
            f"p99 {percentile(packed, 0.99) * 1e3:.3f} ms; "
            f"push_frame without a mesh ({len(without)} frames): median "
            f"{statistics.median(without) * 1e3:.3f} ms"
        )


def test_live_preview_cost(ffi, subject_1, capsys):
    """The result screen's live preview: the morph mesh crosses once; then
    per frame nothing does (SceneKit's morpher takes the 52 weights). For
    comparison, what posing the whole avatar in the core per frame costs
    (`pose`, as the app did before). Printed, never asserted."""
    result = subject_1.personalize(None, None).avatar(None, None, None)
    preview = ffi.AvatarPreview(result.glb)
    started = time.perf_counter()
    mesh = preview.morph_mesh()
    once = time.perf_counter() - started
    size = len(mesh.positions) + len(mesh.normals) + len(mesh.triangles)
    size += sum(map(len, mesh.position_targets)) + sum(map(len, mesh.normal_targets))
    weights = [0.3] * 52
    pose = []
    for _ in range(30):
        started = time.perf_counter()
        preview.pose(weights)
        pose.append(time.perf_counter() - started)
    with capsys.disabled():
        print(
            f"\nlive preview: morph_mesh once {once * 1e3:.0f} ms, {size / 1e6:.1f} MB "
            f"({len(mesh.positions) // 12} vertices, 52 targets with normals); per frame "
            f"0 bytes cross the FFI; pose() per frame instead: median "
            f"{statistics.median(pose) * 1e3:.2f} ms, {len(mesh.positions) // 4} floats"
        )
