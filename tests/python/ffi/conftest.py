"""Fixtures of the FFI tests: the generated bindings, the `likeness` command,
and sessions replayed through a CaptureSession one frame at a time, as the
app feeds it.

run.sh sets LIKENESS_FFI_PYTHON (the folder of the generated likeness_ffi.py
and the library) and LIKENESS_CLI (the built command).
"""

import importlib
import json
import os
import struct
import subprocess
import sys
import time
from dataclasses import dataclass, field
from pathlib import Path

import pytest

REPO = Path(__file__).resolve().parents[3]
SUBJECT_1 = REPO / "sim-data" / "sessions" / "subject-1.likeness"


def _required_env(name):
    value = os.environ.get(name)
    if not value:
        pytest.exit(f"{name} is not set: run tests/python/ffi/run.sh", returncode=2)
    return value


@pytest.fixture(scope="session")
def ffi():
    """The generated module `likeness_ffi`."""
    sys.path.insert(0, _required_env("LIKENESS_FFI_PYTHON"))
    return importlib.import_module("likeness_ffi")


@pytest.fixture(scope="session")
def cli():
    """Runs `likeness ARGS...` and returns its standard output (fails the
    test on a non-zero exit)."""
    command = _required_env("LIKENESS_CLI")

    def run(*args):
        done = subprocess.run(
            [command, *map(str, args)], capture_output=True, text=True
        )
        assert done.returncode == 0, f"likeness {args}: {done.stderr}"
        return done.stdout

    return run


@dataclass
class Replay:
    """A stored session's stream pushed through a new CaptureSession."""

    capture: object
    events: list
    # Seconds of each push_frame call, and whether its frame had a mesh.
    push_seconds: list = field(default_factory=list)
    with_mesh: list = field(default_factory=list)
    # The capture's state after the last frame (a later test may finish it).
    captures: list = field(default_factory=list)
    progress: object = None
    finished: bool = False
    current_prompt: object = None


def replay(ffi, handle, packed=False, away=None, stop=None):
    """Pushes every frame of `handle`'s recorded stream, one call each:
    `push_frame`, or `push_frame_packed` with the mesh packed as
    little-endian floats (the packing timed with the call). With `away =
    (frame, seconds, tell)`, the phone is away for `seconds` before that
    frame (a call, the app in the background): every later frame comes
    that much later, and with `tell` the app calls `interrupt()` first, as
    it does when ARKit's session is interrupted. With `stop`, the replay
    ends before that frame."""
    capture = ffi.CaptureSession(handle.template(), "replay")
    result = Replay(capture, list(capture.start()))
    shift = 0.0
    for i in range(handle.recorded_frame_count() if stop is None else stop):
        f = handle.recorded_frame(i)
        if away is not None and i == away[0]:
            shift = away[1]
            if away[2]:
                result.events.extend(capture.interrupt())
        timestamp = f.timestamp + shift
        started = time.perf_counter()
        if packed:
            vertices = struct.pack(f"<{len(f.vertices)}f", *f.vertices)
            events = capture.push_frame_packed(timestamp, f.weights, vertices, f.tracked)
        else:
            events = capture.push_frame(timestamp, f.weights, f.vertices, f.tracked)
        result.push_seconds.append(time.perf_counter() - started)
        result.with_mesh.append(bool(f.vertices))
        result.events.extend(events)
    result.captures = capture.captures()
    result.progress = capture.progress()
    result.finished = capture.is_finished()
    result.current_prompt = capture.current_prompt()
    return result


@pytest.fixture(scope="session")
def subject_1(ffi):
    """The committed sample session, loaded through the FFI."""
    return ffi.SessionHandle.load(str(SUBJECT_1))


@pytest.fixture(scope="session")
def subject_1_replay(ffi, subject_1):
    return replay(ffi, subject_1)


@pytest.fixture(scope="session")
def full_stream(cli, tmp_path_factory):
    """Subject 1 simulated with a mesh in every frame, as the phone sends
    them (the committed file keeps meshes only near the simulator's own
    captures)."""
    path = tmp_path_factory.mktemp("full") / "subject-1-full.likeness"
    cli("simulate", "--seed", 1, "--out", path)
    return path


@pytest.fixture(scope="session")
def full_replay(ffi, full_stream):
    return replay(ffi, ffi.SessionHandle.load(str(full_stream)))


@pytest.fixture(scope="session")
def full_replay_packed(ffi, full_stream):
    return replay(ffi, ffi.SessionHandle.load(str(full_stream)), packed=True)


@pytest.fixture(scope="session")
def cli_replay(cli):
    """`likeness replay FILE --json`, parsed."""
    return lambda path: json.loads(cli("replay", path, "--json"))


@pytest.fixture(scope="session")
def listener(ffi):
    """A ProgressListener implemented in Python: listener(cancel_at=None)
    records every report and cancels once `cancel_at` reports have arrived
    (never when None)."""

    class Listener(ffi.ProgressListener):
        def __init__(self, cancel_at=None):
            self.reports = []
            self.cancel_at = cancel_at

        def on_progress(self, stage, fraction):
            self.reports.append((stage, fraction))

        def is_cancelled(self):
            return self.cancel_at is not None and len(self.reports) >= self.cancel_at

    return Listener
