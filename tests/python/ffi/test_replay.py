"""A stored stream pushed through the FFI one frame at a time, as the app
pushes ARKit's frames, captures what `likeness replay` captures.

The FFI's capture asks for no test expressions, so it matches the
command's first 53 steps (the neutral scan and the 52 prompts) and
finishes there; the command goes on to the session's test expressions.
"""

import pytest

from conftest import SUBJECT_1, replay

STEPS = 53


def expected_warning_starts(step):
    """What each quality flag of a `likeness replay --json` step says first."""
    starts = []
    if step["weak"]:
        starts.append("weak")
    if step["dominated_by"]:
        starts.append(step["dominated_by"])
    if step["tracking_lost"]:
        starts.append("the face was lost")
    if step["high_rest"]:
        starts.append("the relaxed face rests high on " + step["high_rest"])
    return starts


def assert_same_captures(result, cli_steps):
    infos = result.captures
    assert len(infos) == STEPS
    assert [i.prompt.index for i in infos] == list(range(STEPS))
    for info, step in zip(infos, cli_steps[:STEPS]):
        assert info.prompt.name == step["name"]
        assert info.prompt.is_neutral == (step["kind"] == "neutral")
        assert info.frame == step["frame"], step["name"]
        starts = expected_warning_starts(step)
        assert len(info.warnings) == len(starts), (step, info.warnings)
        for warning, start in zip(info.warnings, starts):
            assert warning.startswith(start), (warning, start)


def assert_events_in_step_order(result, cli_steps):
    events = result.events
    started = [e.prompt.name for e in events if e.is_prompt_started()]
    captured = [e.prompt.name for e in events if e.is_captured()]
    names = [s["name"] for s in cli_steps[:STEPS]]
    assert started == names
    assert captured == [s["name"] for s in cli_steps[:STEPS] if s["frame"] is not None]
    finished = [e for e in events if e.is_finished()]
    assert len(finished) == 1 and events[-1] == finished[0]
    assert (finished[0].captured, finished[0].skipped) == (len(captured), STEPS - len(captured))
    progress = result.progress
    assert (progress.captured, progress.total, progress.fraction) == (len(captured), STEPS, 1.0)
    assert result.finished and result.current_prompt is None


def test_the_committed_session_replays_to_the_commands_captures(
    ffi, subject_1, subject_1_replay, cli_replay
):
    cli = cli_replay(SUBJECT_1)
    assert cli["frames"] == subject_1.recorded_frame_count()
    assert_same_captures(subject_1_replay, cli["steps"])
    assert_events_in_step_order(subject_1_replay, cli["steps"])


def test_the_committed_stream_finishes_with_a_still_mesh_as_its_neutral(ffi, subject_1):
    """The sample keeps meshes within 0.4 s of the simulator's own neutral
    frame (1.5 s); the live detector takes the neutral at 1.0 s (frame 60),
    which has none. The capture takes the nearest mesh of the same still
    face instead (the demo mode replays this file), and the session it
    makes personalizes."""
    result = replay(ffi, subject_1)
    neutral = result.captures[0]
    assert neutral.prompt.is_neutral and neutral.frame == 60
    assert not subject_1.recorded_frame(60).vertices
    session = result.capture.finish()
    face = session.personalize(None, None)
    assert len(face.pose([0.0] * 52)) == 1220 * 3


def test_a_stream_with_every_mesh_replays_to_the_commands_captures(
    full_stream, full_replay, cli_replay
):
    cli = cli_replay(full_stream)
    assert_same_captures(full_replay, cli["steps"])
    assert_events_in_step_order(full_replay, cli["steps"])
    assert all(full_replay.with_mesh)


def test_packed_meshes_replay_to_the_same_captures_and_events(full_replay, full_replay_packed):
    assert full_replay_packed.events == full_replay.events
    assert full_replay_packed.captures == full_replay.captures
    assert full_replay_packed.progress == full_replay.progress


def test_the_events_carry_prompts_the_app_can_show(ffi, full_replay):
    first = full_replay.events[0]
    assert first.is_prompt_started() and first.prompt.is_neutral
    assert first.prompt.instruction.startswith("Relax your face")
    prompts = [e.prompt for e in full_replay.events if e.is_prompt_started()]
    names = ffi.arkit_names()
    assert sorted(p.name for p in prompts[1:]) == sorted(names)
    assert all(p.total == STEPS and p.instruction for p in prompts)


def test_an_interruption_in_the_middle_of_a_prompt_resumes_it(ffi, full_stream, full_replay):
    """The phone is away for 30 s in the middle of a prompt (a call). Told
    (interrupt()), the capture asks for the same prompt again and captures
    every step it captured without the interruption; not told, the time
    away times the prompt out."""
    handle = ffi.SessionHandle.load(str(full_stream))
    captured = {i.prompt.name: i.frame for i in full_replay.captures if i.frame is not None}
    # The frame 20 frames after the tenth prompt began, before its peak.
    prompt = full_replay.captures[10].prompt.name
    probe = ffi.CaptureSession(handle.template(), "probe")
    probe.start()
    at = None
    for i in range(handle.recorded_frame_count()):
        f = handle.recorded_frame(i)
        events = probe.push_frame(f.timestamp, f.weights, f.vertices, f.tracked)
        if any(e.is_prompt_started() and e.prompt.name == prompt for e in events):
            at = i + 20
            break
    assert at is not None and at < captured[prompt], "interrupted before the peak"

    told = replay(ffi, handle, away=(at, 30.0, True))
    again = [e for e in told.events if e.is_prompt_started() and e.prompt.name == prompt]
    assert len(again) == 2, "the prompt is asked for again after the interruption"
    assert not any(e.is_skipped() for e in told.events)
    resumed = {i.prompt.name: i.frame for i in told.captures if i.frame is not None}
    assert resumed.keys() == captured.keys()
    # Every capture but the interrupted prompt's is the same frame.
    assert all(resumed[n] == captured[n] for n in captured if n != prompt)
    assert resumed[prompt] >= at
    session = told.capture.finish()
    # The summary counts expressions: every capture but the neutral scan.
    assert session.quality_summary().captured == len(captured) - 1

    untold = replay(ffi, handle, away=(at, 30.0, False))
    timed_out = [e for e in untold.events if e.is_skipped() and e.prompt.name == prompt]
    assert len(timed_out) == 1 and "timed out" in timed_out[0].reason


def test_a_capture_that_reaches_its_limit_saves_what_it_has(ffi, full_stream, full_replay, tmp_path):
    """Left running past ten minutes (the phone put down mid-capture), the
    capture ends at the limit with the captures made so far, and saves."""
    handle = ffi.SessionHandle.load(str(full_stream))
    half = full_replay.captures[27].frame
    result = replay(ffi, handle, away=(half, 601.0, False))
    limit = [e for e in result.events if e.is_limit_reached()]
    assert len(limit) == 1 and limit[0].seconds > 600.0
    assert result.finished and result.progress.ended_at_limit
    kept = [i for i in result.captures if i.frame is not None]
    assert 20 <= len(kept) < STEPS
    assert all(i.skipped for i in result.captures if i.frame is None)
    # A captured prompt's weight bar: its own weight at the captured frame.
    names = ffi.arkit_names()
    for info in kept[1:]:
        frame = handle.recorded_frame(info.frame)
        assert info.weight == frame.weights[names.index(info.prompt.name)]
    assert kept[0].prompt.is_neutral and kept[0].weight is None
    session = result.capture.finish()
    path = tmp_path / "cut-short.likeness"
    session.save(str(path))
    back = ffi.SessionHandle.load(str(path))
    assert back.quality_summary().captured == len(kept) - 1  # not the neutral scan
    assert back.recorded_frame_count() == half
