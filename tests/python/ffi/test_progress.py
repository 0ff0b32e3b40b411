"""Progress reaches a listener written in Python, cancelling stops the work
with LikenessError.Cancelled, and a listener that raises (a panic in Rust)
costs an InternalError, not the interpreter."""

import pytest

PERSONALIZE = [
    ("carrying the template onto the neutral face", 0.0),
    ("choosing the regularization", 0.13),
    ("fitting the blendshapes", 0.75),
    ("personalized", 1.0),
]

AVATAR = [
    "checking the avatar",
    "finding the face",
    "taking the person's face",
    "retargeting (Eq. 4)",
    "implanting the person's shapes",
    "writing the GLB",
    "done",
]


def test_personalization_reports_each_stage(subject_1, listener):
    heard = listener()
    face = subject_1.personalize("multi", heard)
    assert heard.reports == PERSONALIZE
    assert face.method() == "multi"
    dt = listener()
    subject_1.personalize("dt", dt)
    assert dt.reports == [PERSONALIZE[0], PERSONALIZE[-1]]


def test_the_avatar_reports_each_step_in_order(subject_1, listener):
    heard = listener()
    result = subject_1.personalize("dt", None).avatar(None, None, heard)
    assert [stage for stage, _ in heard.reports] == AVATAR
    fractions = [f for _, f in heard.reports]
    assert fractions == sorted(fractions) and fractions[0] == 0.0 and fractions[-1] == 1.0
    assert result.glb[:4] == b"glTF"


def test_cancelling_stops_personalization(ffi, subject_1, listener):
    for cancel_at in (0, 1, 2, 3):
        heard = listener(cancel_at)
        with pytest.raises(ffi.LikenessError.Cancelled):
            subject_1.personalize("multi", heard)
        assert heard.reports == PERSONALIZE[:cancel_at]


def test_cancelling_stops_the_avatar(ffi, subject_1, listener):
    face = subject_1.personalize("dt", None)
    for cancel_at in (0, 2, 4):
        heard = listener(cancel_at)
        with pytest.raises(ffi.LikenessError.Cancelled):
            face.avatar(None, None, heard)
        assert [stage for stage, _ in heard.reports] == AVATAR[:cancel_at]


def test_a_listener_that_raises_is_an_internal_error_not_a_crash(ffi, subject_1, listener):
    class Raising(listener):
        def on_progress(self, stage, fraction):
            raise RuntimeError("the app's listener broke")

    with pytest.raises(ffi.InternalError):
        subject_1.personalize("dt", Raising())
    face = subject_1.personalize("dt", None)
    with pytest.raises(ffi.InternalError):
        face.avatar(None, None, Raising())
    # Both objects still work.
    assert len(face.pose([0.0] * 52)) == 3660
    assert subject_1.personalize("dt", listener()).method() == "dt"
