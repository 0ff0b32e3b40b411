"""Hostile and out-of-order calls raise the right LikenessError subclass,
with a message naming what is wrong, and leave the interpreter and the
objects usable."""

import json
import struct

import pytest

from conftest import SUBJECT_1

ZEROS = [0.0] * 52


@pytest.fixture
def template(subject_1):
    return subject_1.template()


@pytest.fixture
def capture(ffi, template):
    c = ffi.CaptureSession(template, "test")
    c.start()
    return c


def neutral_frames(capture, template, count, start=0):
    """`count` still neutral frames at 60 fps from frame `start`."""
    events = []
    for i in range(start, start + count):
        events += capture.push_frame(i / 60, ZEROS, template.neutral, True)
    return events


def glb_without_morph_targets():
    """A valid GLB holding one triangle and nothing else."""
    data = struct.pack("<9f", 0, 0, 0, 0.1, 0, 0, 0, 0.1, 0) + struct.pack("<3H2x", 0, 1, 2)
    doc = {
        "asset": {"version": "2.0"},
        "scene": 0,
        "scenes": [{"nodes": [0]}],
        "nodes": [{"mesh": 0}],
        "meshes": [{"primitives": [{"attributes": {"POSITION": 0}, "indices": 1}]}],
        "buffers": [{"byteLength": len(data)}],
        "bufferViews": [
            {"buffer": 0, "byteOffset": 0, "byteLength": 36},
            {"buffer": 0, "byteOffset": 36, "byteLength": 6},
        ],
        "accessors": [
            {"bufferView": 0, "componentType": 5126, "count": 3, "type": "VEC3",
             "min": [0, 0, 0], "max": [0.1, 0.1, 0]},
            {"bufferView": 1, "componentType": 5123, "count": 3, "type": "SCALAR"},
        ],
    }
    text = json.dumps(doc).encode()
    text += b" " * (-len(text) % 4)
    total = 12 + 8 + len(text) + 8 + len(data)
    return (
        struct.pack("<4sII", b"glTF", 2, total)
        + struct.pack("<I4s", len(text), b"JSON") + text
        + struct.pack("<I4s", len(data), b"BIN\0") + data
    )


def test_frames_with_bad_weights_or_meshes_are_refused_by_field(ffi, capture, template):
    bad = [
        (ZEROS[:51], [], "weights: 51 values, expected 52"),
        (ZEROS + [0.0], [], "weights: 53 values"),
        (ZEROS[:17] + [float("nan")] + ZEROS[18:], [], "is NaN"),
        (ZEROS[:3] + [float("inf")] + ZEROS[4:], [], "is inf"),
        (ZEROS, template.neutral[:-3], "frame 0: 1219 vertices, but the topology has 1220"),
        (ZEROS, template.neutral[:-1], "vertices: 3659 values are not a whole number"),
        (ZEROS, template.neutral[:-3] + [float("inf")] * 3, "frame 0: vertex 1219"),
    ]
    for weights, vertices, message in bad:
        with pytest.raises(ffi.LikenessError.InvalidInput) as error:
            capture.push_frame(0.0, weights, vertices, True)
        assert message in error.value.message, error.value.message
    packed = struct.pack(f"<{len(template.neutral)}f", *template.neutral)
    for vertices, message in [
        (packed[:-1], "vertices: 14639 bytes are not a whole number"),
        (packed[:-12], "frame 0: 1219 vertices, but the topology has 1220"),
        (packed[:-4] + struct.pack("<f", float("nan")), "frame 0: vertex 1219"),
    ]:
        with pytest.raises(ffi.LikenessError.InvalidInput) as error:
            capture.push_frame_packed(0.0, ZEROS, vertices, True)
        assert message in error.value.message, error.value.message
    # Nothing was recorded: the next good frame is frame 0.
    capture.push_frame(0.0, ZEROS, template.neutral, True)
    with pytest.raises(ffi.LikenessError.InvalidInput, match="frame 1: 3 vertices"):
        capture.push_frame(0.1, ZEROS, template.neutral[:9], True)


def test_time_going_backwards_or_not_finite_is_refused(ffi, capture, template):
    capture.push_frame(1.0, ZEROS, [], True)
    with pytest.raises(ffi.LikenessError.InvalidInput, match="earlier than the previous"):
        capture.push_frame(0.5, ZEROS, [], True)
    with pytest.raises(ffi.LikenessError.InvalidInput, match="not a finite number"):
        capture.push_frame(float("nan"), ZEROS, [], True)
    capture.push_frame(1.0, ZEROS, [], True)  # the same time again is fine


def test_a_capture_past_ten_minutes_ends_instead_of_refusing_frames(ffi, capture):
    capture.push_frame(100.0, ZEROS, [], True)
    capture.push_frame(700.0, ZEROS, [], True)  # exactly ten minutes: the last
    events = capture.push_frame(700.5, ZEROS, [], True)
    assert events[0].is_limit_reached() and events[0].seconds == 600.5
    assert "limit" in events[0].message and "kept" in events[0].message
    assert events[-1].is_finished()
    assert capture.is_finished() and capture.progress().ended_at_limit
    assert capture.push_frame(701.0, ZEROS, [], True) == []  # ignored
    with pytest.raises(ffi.LikenessError.WrongOrder, match="length limit"):
        capture.retake(1)
    # Its neutral scan (the still frames) has no mesh: nothing to save, and
    # it says so.
    with pytest.raises(ffi.LikenessError.Capture, match="no neutral face"):
        capture.finish()


def test_templates_that_do_not_fit_are_refused(ffi, template):
    cases = [
        (dict(shapes=template.shapes[:51]), "51 blendshapes, expected 52"),
        (dict(triangles=template.triangles[:-1]), "not a whole number of triangles"),
        (dict(triangles=[0, 1, 5000] + template.triangles[3:]), "refers to vertex 5000"),
        (dict(shapes=template.shapes[:4] + [template.shapes[4][:-3]] + template.shapes[5:]),
         "eyeLookUpLeft: 1219 vertices"),
        (dict(neutral=[float("nan")] * 3 + template.neutral[3:]), "neutral: vertex 0"),
    ]
    for change, message in cases:
        fields = dict(triangles=template.triangles, neutral=template.neutral, shapes=template.shapes)
        fields.update(change)
        with pytest.raises(ffi.LikenessError.InvalidInput) as error:
            ffi.CaptureSession(ffi.FaceTemplate(**fields), "test")
        assert message in error.value.message, error.value.message


def test_calls_in_the_wrong_order(ffi, template):
    capture = ffi.CaptureSession(template, "test")
    with pytest.raises(ffi.LikenessError.WrongOrder, match="not started"):
        capture.skip()
    with pytest.raises(ffi.LikenessError.WrongOrder, match="not finished: 0 of 53"):
        capture.finish()
    assert [e.is_prompt_started() for e in capture.start()] == [True]
    assert capture.start() == []
    with pytest.raises(ffi.LikenessError.WrongOrder, match="neutral scan cannot be skipped"):
        capture.skip()
    with pytest.raises(ffi.LikenessError.InvalidInput, match="no step 53"):
        capture.retake(53)
    events = neutral_frames(capture, template, 90)
    assert [e.is_captured() for e in events[:2]] == [True, False]
    for _ in range(52):
        capture.skip()
    assert capture.is_finished()
    with pytest.raises(ffi.LikenessError.WrongOrder, match="no step to skip"):
        capture.skip()
    session = capture.finish()
    # Personalizing needs a capture; deformation transfer alone does not.
    with pytest.raises(ffi.LikenessError.WrongOrder, match="no captured expressions"):
        session.personalize(None, None)
    assert session.personalize("dt", None).method() == "dt"
    with pytest.raises(ffi.LikenessError.InvalidInput, match="unknown method"):
        session.personalize("best", None)
    summary = session.quality_summary()
    assert (summary.captured, len(summary.skipped)) == (0, 52)


def test_previews_are_the_template_and_bad_indices_are_refused(ffi, capture, template):
    assert capture.prompt_preview(0) == pytest.approx(template.neutral)
    first = capture.current_prompt()
    assert first.is_neutral and first.index == 0 and first.total == 53
    neutral_frames(capture, template, 61)
    prompt = capture.current_prompt()
    assert prompt.index == 1 and not prompt.is_neutral
    j = ffi.arkit_names().index(prompt.name)
    assert capture.prompt_preview(1) == pytest.approx(template.shapes[j])
    with pytest.raises(ffi.LikenessError.InvalidInput, match="no step 99"):
        capture.prompt_preview(99)
    with pytest.raises(ffi.LikenessError.InvalidInput, match="recorded frame 9000000"):
        ffi.SessionHandle.load(str(SUBJECT_1)).recorded_frame(9_000_000)


def test_empty_corrupt_and_missing_files_are_file_errors(ffi, tmp_path):
    data = SUBJECT_1.read_bytes()
    flipped = bytearray(data)
    flipped[len(data) // 2] ^= 0xFF
    cases = {
        "empty.likeness": (b"", "not a Likeness session file"),
        "text.likeness": (b"hello, world", "not a Likeness session file"),
        "truncated.likeness": (data[: len(data) // 3], "truncated session file"),
        "flipped.likeness": (bytes(flipped), "checksum"),
    }
    for name, (content, message) in cases.items():
        (tmp_path / name).write_bytes(content)
        with pytest.raises(ffi.LikenessError.File) as error:
            ffi.SessionHandle.load(str(tmp_path / name))
        assert message in error.value.message, (name, error.value.message)
    with pytest.raises(ffi.LikenessError.File, match="missing.likeness"):
        ffi.SessionHandle.load(str(tmp_path / "missing.likeness"))
    session = ffi.SessionHandle.load(str(SUBJECT_1))
    with pytest.raises(ffi.LikenessError.File, match="no-such-folder"):
        session.save(str(tmp_path / "no-such-folder" / "x.likeness"))


def test_avatars_without_morph_targets_or_not_gltf_are_avatar_errors(ffi, subject_1):
    face = subject_1.personalize("dt", None)
    for glb, message in [
        (glb_without_morph_targets(), "avatar.glb: no morph targets on any mesh"),
        (b"", "not glTF"),
        (b"glTF\x02\x00\x00\x00", "truncated GLB"),
        (b"\x00" * 64, "not glTF"),
    ]:
        with pytest.raises(ffi.LikenessError.Avatar) as error:
            face.avatar(glb, None, None)
        assert message in error.value.message, error.value.message


def test_an_avatar_preview_of_a_bad_file_is_an_avatar_error(ffi):
    for glb, message in [
        (b"", "not glTF"),
        (b"glTF\x02\x00\x00\x00", "truncated GLB"),
        (b"\x00" * 64, "not glTF"),
    ]:
        with pytest.raises(ffi.LikenessError.Avatar) as error:
            ffi.AvatarPreview(glb)
        assert message in error.value.message, error.value.message


def test_an_avatar_without_targets_previews_still_and_takes_52_weights(ffi):
    preview = ffi.AvatarPreview(glb_without_morph_targets())
    assert preview.shapes_found() == 0
    assert preview.pose(ZEROS) == preview.pose([1.0] * 52)
    with pytest.raises(ffi.LikenessError.InvalidInput, match="weights: 51 values"):
        preview.pose(ZEROS[:51])
    with pytest.raises(ffi.LikenessError.InvalidInput, match="is NaN"):
        preview.pose([float("nan")] * 52)


def test_pose_takes_52_finite_weights(ffi, subject_1):
    face = subject_1.personalize("dt", None)
    assert len(face.pose(ZEROS)) == 3660
    with pytest.raises(ffi.LikenessError.InvalidInput, match="weights: 0 values"):
        face.pose([])
    with pytest.raises(ffi.LikenessError.InvalidInput, match="jawOpen is NaN"):
        weights = list(ZEROS)
        weights[ffi.arkit_names().index("jawOpen")] = float("nan")
        face.pose(weights)
