"""Capture, save, load, personalize, avatar: through the FFI the same
numbers and the same bytes as `likeness` gives on the same session file.
"""

import json
from pathlib import Path

import pytest

from conftest import SUBJECT_1

# OBJ files carry 7 decimals (0.1 µm); pose is single precision.
OBJ_TOLERANCE = 1.5e-7


@pytest.fixture(scope="module")
def captured(ffi, full_replay, tmp_path_factory):
    """The session the FFI's capture made of the full stream, saved: the
    handle and its file."""
    handle = full_replay.capture.finish()
    path = tmp_path_factory.mktemp("captured") / "captured.likeness"
    handle.save(str(path))
    return handle, path


def read_obj(path):
    return [
        float(x)
        for line in Path(path).read_text().splitlines()
        if line.startswith("v ")
        for x in line.split()[1:]
    ]


def assert_close(a, b, what):
    assert len(a) == len(b), what
    worst = max(abs(x - y) for x, y in zip(a, b))
    assert worst <= OBJ_TOLERANCE, f"{what}: {worst}"


def assert_personalization_matches_the_command(ffi, cli, face, path, tmp_path):
    out = tmp_path / "shapes"
    cli("personalize", path, "--out", out)
    names = ffi.arkit_names()
    assert_close(face.pose([0.0] * 52), read_obj(out / "neutral.obj"), "neutral")
    for j, name in enumerate(names):
        one = [0.0] * 52
        one[j] = 1.0
        assert_close(face.pose(one), read_obj(out / f"{name}.obj"), name)


def test_the_finished_capture_is_a_session_that_saves_and_loads_back(ffi, captured, full_replay):
    handle, path = captured
    loaded = ffi.SessionHandle.load(str(path))
    assert loaded.template() == handle.template()
    count = len(full_replay.push_seconds)
    assert loaded.recorded_frame_count() == handle.recorded_frame_count() == count
    assert loaded.quality_summary() == handle.quality_summary()
    summary = handle.quality_summary()
    assert summary.captured == 52 and summary.skipped == []
    assert summary.headline.startswith("All 52 expressions captured")
    # Meshes are kept near the captures only.
    frames = [loaded.recorded_frame(i) for i in range(0, loaded.recorded_frame_count(), 7)]
    with_mesh = sum(1 for f in frames if f.vertices)
    assert 0 < with_mesh < len(frames)
    assert all(len(f.vertices) in (0, 3660) for f in frames)
    # The capture takes no more calls once finished.
    with pytest.raises(ffi.LikenessError.WrongOrder):
        full_replay.capture.push_frame(1e6, [0.0] * 52, [], True)
    with pytest.raises(ffi.LikenessError.WrongOrder):
        full_replay.capture.finish()
    assert full_replay.capture.is_finished()
    assert full_replay.capture.progress() == full_replay.progress


def test_saving_replaces_the_file_whole_and_leaves_no_temporary(ffi, subject_1, tmp_path):
    path = tmp_path / "again.likeness"
    path.write_bytes(b"an older file")
    subject_1.save(str(path))
    assert path.read_bytes() == SUBJECT_1.read_bytes()
    assert [p.name for p in tmp_path.iterdir()] == ["again.likeness"]


def test_the_committed_session_personalizes_to_the_commands_shapes(ffi, cli, subject_1, tmp_path):
    face = subject_1.personalize(None, None)
    assert face.method() == ffi.default_method() == "multi"
    assert len(face.triangles()) == len(subject_1.template().triangles)
    assert_personalization_matches_the_command(ffi, cli, face, SUBJECT_1, tmp_path)


def test_the_captured_session_personalizes_to_the_commands_shapes(ffi, cli, captured, tmp_path):
    handle, path = captured
    face = handle.personalize("multi", None)
    assert_personalization_matches_the_command(ffi, cli, face, path, tmp_path)


def test_the_mask_glb_is_the_commands(cli, subject_1, tmp_path):
    out = tmp_path / "mask.glb"
    cli("avatar", SUBJECT_1, "--mask-only", "--out", out)
    assert subject_1.personalize(None, None).mask_glb() == out.read_bytes()


def test_the_captured_sessions_avatar_is_the_commands_byte_for_byte(ffi, cli, captured, tmp_path):
    handle, path = captured
    out, map_path = tmp_path / "avatar.glb", tmp_path / "map.json"
    report = json.loads(
        cli(
            "avatar", path, "--out", out, "--retarget-map", map_path,
            "--cache-dir", tmp_path / "cache", "--json",
        )
    )
    result = handle.personalize(None, None).avatar(None, None, None)
    assert result.glb == out.read_bytes()
    assert result.retarget_map_json == map_path.read_text()
    assert result.warnings == report["warnings"]
    assert result.summary.startswith("default avatar: ")
    assert f"{report['face_vertices']} vertices" in result.summary
    retarget = json.loads(result.retarget_map_json)
    assert retarget["arkit"] == ffi.arkit_names()
    # The default avatar takes the person's face, as the command does.
    assert report["rest_face"] == "person"
    assert result.rest_face == ffi.RestFaceChoice.PERSON
    assert "It has your face at rest" in result.summary


def test_keeping_the_stock_face_is_the_commands_keep_face(ffi, cli, subject_1, tmp_path):
    out = tmp_path / "avatar.glb"
    report = json.loads(cli("avatar", SUBJECT_1, "--keep-face", "--out", out, "--json"))
    assert report["rest_face"] == "stock"
    face = subject_1.personalize(None, None)
    kept = face.avatar(None, ffi.RestFaceChoice.STOCK, None)
    assert kept.glb == out.read_bytes()
    assert kept.rest_face == ffi.RestFaceChoice.STOCK
    assert "It keeps its own face at rest." in kept.summary
    assert face.avatar(None, None, None).glb != kept.glb


def test_the_avatar_preview_poses_the_written_avatar_by_live_weights(ffi, subject_1):
    result = subject_1.personalize(None, None).avatar(None, None, None)
    preview = ffi.AvatarPreview(result.glb)
    assert preview.shapes_found() == 52
    rest = preview.pose([0.0] * 52)
    triangles = preview.triangles()
    assert len(rest) % 3 == 0 and len(triangles) % 3 == 0
    assert max(triangles) < len(rest) // 3
    names = ffi.arkit_names()

    def moved(weight, name):
        w = [0.0] * 52
        w[names.index(name)] = weight
        posed = preview.pose(w)
        return [p - r for p, r in zip(posed, rest)]

    jaw = moved(1.0, "jawOpen")
    # The default avatar is in metres: the chin drops by centimetres, down (-y).
    drop = min(jaw[1::3])
    assert -0.06 < drop < -0.01
    # Poses are linear in the weights, as an engine plays morph targets.
    half = moved(0.5, "jawOpen")
    assert max(abs(h - 0.5 * j) for h, j in zip(half, jaw)) < 1e-6
    # A blink moves far less than the jaw, most at its own eye: the left and
    # right blinks peak on opposite sides of the face.
    def peak_x(d):
        motion = [d[i] ** 2 + d[i + 1] ** 2 + d[i + 2] ** 2 for i in range(0, len(d), 3)]
        return rest[3 * motion.index(max(motion))]

    left, right = moved(1.0, "eyeBlinkLeft"), moved(1.0, "eyeBlinkRight")
    assert 0 < max(map(abs, left)) < max(map(abs, jaw)) / 2
    assert peak_x(left) * peak_x(right) < 0
    # The focus is the face: on the default avatar (metres, face at the
    # origin as ARKit's mask), a box of head size around what the shapes move.
    focus = preview.focus()
    assert 0.05 < focus.radius < 0.25
    xs, ys = rest[0::3], rest[1::3]
    assert min(xs) <= focus.x <= max(xs) and min(ys) <= focus.y <= max(ys)


def test_the_morph_mesh_plays_as_pose_does(ffi, subject_1):
    """What SceneKit's morpher is given once (rest, normals, triangles, 52
    dense targets) poses the avatar exactly as `pose` does: rest plus the
    weighted targets."""
    import random
    import struct

    result = subject_1.personalize(None, None).avatar(None, None, None)
    preview = ffi.AvatarPreview(result.glb)
    mesh = preview.morph_mesh()
    floats = lambda b: struct.unpack(f"<{len(b) // 4}f", b)
    rest = floats(mesh.positions)
    assert len(rest) == len(preview.pose([0.0] * 52))
    assert list(struct.unpack(f"<{len(mesh.triangles) // 4}I", mesh.triangles)) == preview.triangles()
    normals = floats(mesh.normals)
    assert len(normals) == len(rest)
    assert all(abs(sum(n * n for n in normals[i:i + 3]) - 1) < 1e-4 for i in range(0, len(normals), 300))
    assert len(mesh.position_targets) == len(mesh.normal_targets) == 52
    assert all(len(t) == len(mesh.positions) for t in mesh.position_targets)
    random.seed(3)
    weights = [random.random() for _ in range(52)]
    played = list(rest)
    for w, target in zip(weights, mesh.position_targets):
        for i, d in enumerate(floats(target)):
            if d:
                played[i] += w * d
    posed = preview.pose(weights)
    assert max(abs(a - b) for a, b in zip(played, posed)) < 1e-5
