"""A stored stream pushed through the FFI one frame at a time, as the app
pushes ARKit's frames, captures what `likeness replay` captures.

The FFI's capture asks for no test expressions, so it matches the
command's first 53 steps (the neutral scan and the 52 prompts) and
finishes there; the command goes on to the session's test expressions.
"""

import pytest

from conftest import SUBJECT_1

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


def test_the_committed_stream_has_no_mesh_at_the_live_neutral_scan(ffi, subject_1_replay):
    # The sample keeps meshes within 0.4 s of the simulator's own neutral
    # frame (1.5 s); the live detector takes the neutral at 1.0 s.
    with pytest.raises(ffi.LikenessError.Capture) as error:
        subject_1_replay.capture.finish()
    assert "neutral scan (frame 60) carries no mesh" in error.value.message
    # The capture is still usable after the refusal.
    assert len(subject_1_replay.capture.captures()) == STEPS


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
