"""Tests of swift_checks.py (pytest): the fixtures under fixtures/ are a small
app that uses the core correctly, a file with a syntax error, a small bindings
file in UniFFI's style, and a copy of the bindings UniFFI 0.32 generates for
the FFI (tests/run checks that the copy is what the library generates now). Each rule is shown to pass on correct code and to fail, with file,
line and column, on a deliberate mistake."""
from __future__ import annotations

import shutil
import sys
from pathlib import Path

import pytest

HERE = Path(__file__).resolve().parent
sys.path.insert(0, str(HERE))

import swift_checks  # noqa: E402

FIXTURES = HERE / "fixtures"
SMALL_BINDINGS = FIXTURES / "bindings_small.swift"
GENERATED_BINDINGS = FIXTURES / "likeness_ffi_generated.swift"
GOOD_APP = FIXTURES / "app_good"
DRIVER = Path("Likeness/Capture/Driver.swift")
NAMES = swift_checks.DEFAULT_NAMES_FILE


def run(root: Path, bindings: Path = SMALL_BINDINGS) -> swift_checks.Report:
    return swift_checks.run_checks(root, bindings, NAMES)


def mutated(tmp_path: Path, file: Path, old: str, new: str) -> Path:
    """A copy of the good fixture app with one edit."""
    root = tmp_path / "app"
    shutil.copytree(GOOD_APP, root)
    path = root / file
    source = path.read_text()
    assert old in source, f"fixture lacks {old!r}"
    path.write_text(source.replace(old, new, 1))
    return root


def line_of(root: Path, file: Path, needle: str) -> int:
    return next(i for i, line in enumerate((root / file).read_text().splitlines(), 1) if needle in line)


# ---------------------------------------------------------------- the fixtures

def test_the_good_fixture_app_passes_every_rule():
    report = run(GOOD_APP)
    assert report.problems == []
    uses = "\n".join(report.uses)
    for expected in ("call CaptureSession(template:device:)",
                     "call CaptureSession.pushFrame(timestamp:weights:vertices:tracked:)",
                     "case CaptureEvent.promptStarted", "case LikenessError.InvalidInput",
                     "static member LikenessError.Cancelled", "call SessionHandle.load(path:)",
                     "conformance to ProgressListener", "call arkitNames()", "member Prompt.isNeutral"):
        assert expected in uses


def test_the_app_passes_against_the_generated_bindings():
    report = run(swift_checks.REPO / "ios-app", GENERATED_BINDINGS)
    assert report.problems == [], "\n".join(map(str, report.problems))
    assert len(report.uses) > 40


def test_small_bindings_surface_leaves_uniffi_plumbing_out():
    bindings = swift_checks.load_bindings(SMALL_BINDINGS)
    session = bindings.types["CaptureSession"]
    assert [s.describe("CaptureSession") for s in session.inits] == ["CaptureSession(template:device:)"]
    assert set(session.methods) == {"pushFrame", "skip", "currentPrompt"}
    assert session.methods["pushFrame"][0].returns == "[CaptureEvent]"
    assert bindings.types["SessionHandle"].methods["load"][0].static
    assert "FfiConverterTypePrompt" not in bindings.types
    assert set(bindings.functions) == {"arkitNames"}
    assert bindings.types["CaptureEvent"].cases["captured"] == [("prompt", "Prompt"), ("warnings", "[String]")]
    assert bindings.types["LikenessError"].cases["Cancelled"] == []
    assert bindings.types["ProgressListener"].kind == "protocol"


def test_the_generated_bindings_hold_the_whole_surface():
    bindings = swift_checks.load_bindings(GENERATED_BINDINGS)
    assert set(bindings.functions) == {"arkitNames", "arkitKeys", "coreVersion", "methods", "defaultMethod"}
    methods = {name: set(t.methods) for name, t in bindings.types.items()}
    assert methods["CaptureSession"] == {"start", "pushFrame", "pushFramePacked", "skip", "retake", "interrupt",
                                         "progress", "currentPrompt", "isFinished", "promptPreview", "captures",
                                         "finish"}
    assert methods["SessionHandle"] == {"load", "save", "qualitySummary", "personalize", "template",
                                        "recordedFrameCount", "recordedFrame"}
    assert methods["PersonalizedFace"] == {"method", "triangles", "pose", "maskGlb", "avatar"}
    assert methods["AvatarPreview"] == {"triangles", "focus", "morphMesh", "shapesFound", "pose"}
    assert methods["ProgressListener"] == {"onProgress", "isCancelled"}
    assert set(bindings.types["CaptureEvent"].cases) == {"promptStarted", "captured", "skipped", "trackingLost",
                                                         "trackingResumed", "limitReached", "finished"}
    assert set(bindings.types["LikenessError"].cases) == {"InvalidInput", "File", "Capture", "Personalization",
                                                          "Avatar", "WrongOrder", "Cancelled", "Internal"}
    assert set(bindings.types["Prompt"].fields) == {"index", "total", "name", "instruction", "isNeutral"}


# ---------------------------------------------------------------- rule: syntax

def test_a_syntax_error_is_reported_with_file_line_and_column():
    report = run(FIXTURES / "app_syntax_error")
    assert [(p.rule, Path(p.path).name, p.line, p.column) for p in report.problems] == [
        ("syntax", "Broken.swift", 5, 22)]


def test_main_prints_problems_and_exits_nonzero(capsys):
    code = swift_checks.main(["--bindings", str(SMALL_BINDINGS), "--root", str(FIXTURES / "app_syntax_error")])
    out = capsys.readouterr().out
    assert code == 1
    assert "Broken.swift:5:22: [syntax]" in out


def test_main_exits_zero_on_the_good_app(capsys):
    assert swift_checks.main(["--bindings", str(SMALL_BINDINGS), "--root", str(GOOD_APP)]) == 0
    assert "0 problem(s)" in capsys.readouterr().out


# ---------------------------------------------------------------- rule: ffi

FFI_MISTAKES = [
    # (what, old, new, words the message must hold)
    ("misspelled method", "try core.pushFrame(", "try core.pushframe(", ["no member `pushframe`", "pushFrame"]),
    ("wrong argument label", "timestamp: timestamp, weights:", "time: timestamp, weights:",
     ["pushFrame(time:weights:vertices:tracked:)", "does not match"]),
    ("misspelled enum case", "case .promptStarted(let prompt):", "case .PromptStarted(let prompt):",
     ["no case `PromptStarted`", "promptStarted"]),
    ("unknown enum case", "case .trackingLost, .trackingResumed:", "case .trackingLoss, .trackingResumed:",
     ["no case `trackingLoss`"]),
    ("too many bound values", "case let .captured(prompt, warnings):", "case let .captured(prompt, warnings, x):",
     ["carries 2 value(s)"]),
    ("error case in lowerCamelCase", "case .Cancelled:", "case .cancelled:", ["did you mean `Cancelled`"]),
    ("error case in catch", "catch LikenessError.Cancelled", "catch LikenessError.cancelled",
     ["no case or static member `cancelled`"]),
    ("misspelled free function", "arkitNames()", "arkitName()", ["unknown function `arkitName`"]),
    ("misspelled type", "try CaptureSession(template:", "try CaptureSesion(template:",
     ["unknown name `CaptureSesion`", "did you mean `CaptureSession`"]),
    ("wrong initializer label", "CaptureSession(template: template, device:", "CaptureSession(face: template, device:",
     ["CaptureSession(face:device:)"]),
    ("unknown static method", "SessionHandle.load(path: path)", "SessionHandle.open(path: path)",
     ["no case or static member `open`"]),
    ("unknown record field", "prompt.isNeutral", "prompt.is_neutral", ["`Prompt` has no member `is_neutral`"]),
    ("field called as a method", "status = prompt.instruction\n            case",
     "status = prompt.instruction()\n            case",
     ["is a field, not a method"]),
    ("protocol requirement misspelled", "func isCancelled() -> Bool", "func isCanceled() -> Bool",
     ["does not implement isCancelled()", "found `isCanceled`"]),
    ("protocol requirement with other labels", "func onProgress(stage: String", "func onProgress(_ stage: String",
     ["does not implement onProgress(stage:fraction:)"]),
]


@pytest.mark.parametrize("what, old, new, words", FFI_MISTAKES, ids=[m[0] for m in FFI_MISTAKES])
def test_a_wrong_use_of_the_core_fails(tmp_path, what, old, new, words):
    root = mutated(tmp_path, DRIVER, old, new)
    report = run(root)
    ffi = [p for p in report.problems if p.rule == "ffi"]
    assert len(ffi) == 1, "\n".join(map(str, report.problems))
    message = str(ffi[0])
    for word in words:
        assert word in message
    assert ffi[0].path.endswith(str(DRIVER))
    # A missing protocol requirement is reported where the conformance is declared.
    needle = "final class Listener" if "conforms to" in message else new.split("\n")[0].strip()[:20]
    assert ffi[0].line == line_of(root, DRIVER, needle)


def test_the_same_mistakes_fail_against_the_generated_bindings(tmp_path):
    for number, (_, old, new, _) in enumerate(FFI_MISTAKES):
        root = mutated(tmp_path / str(number), DRIVER, old, new)
        assert any(p.rule == "ffi" for p in run(root, GENERATED_BINDINGS).problems), new


def test_apple_names_must_be_known(tmp_path):
    root = mutated(tmp_path, DRIVER, "final class Driver {", "final class Driver {\n    let view = ARSVNView()")
    (problem,) = run(root).problems
    assert "unknown name `ARSVNView`" in problem.message and "APPLE_NAMES" in problem.message


def test_the_apps_own_names_are_not_the_cores(tmp_path):
    extra = "\nenum Stage { case preparing, capture }\nfunc pushframe() -> Stage { .capture }\n"
    root = mutated(tmp_path, DRIVER, "final class Listener", extra + "final class Listener")
    assert run(root).problems == []


# ---------------------------------------------------------------- rule: arkit-names

def test_names_come_from_the_rust_core():
    names = swift_checks.arkit_names(NAMES)
    assert len(names) == 52 and names[0] == "eyeBlinkLeft" and names[-1] == "tongueOut"
    assert swift_checks.raw_spelling("eyeBlinkLeft") == "eyeBlink_L"
    assert swift_checks.raw_spelling("jawOpen") == "jawOpen"


def test_a_name_list_in_swift_fails(tmp_path):
    # The fixture's test names two shapes; two more in a literal, in ARKit's
    # raw spelling and as a member, make four.
    root = mutated(tmp_path, DRIVER, 'var status = ""',
                   'var status = "mouthSmile_L"\n    let key = ARFaceAnchor.BlendShapeLocation.browInnerUp')
    problems = [p for p in run(root).problems if p.rule == "arkit-names"]
    assert {p.message.split("`")[1] for p in problems} == {"eyeBlinkLeft", "jawOpen", "mouthSmileLeft", "browInnerUp"}


def test_three_names_pass(tmp_path):
    root = mutated(tmp_path, DRIVER, 'var status = ""', 'var status = "cheekPuff"')
    assert run(root).problems == []


# ---------------------------------------------------------------- rule: threshold

def test_a_fraction_in_capture_code_fails(tmp_path):
    root = mutated(tmp_path, DRIVER, "private var core: CaptureSession?",
                   "private var core: CaptureSession?\n    private let holdFor = 0.25")
    (problem,) = run(root).problems
    assert (problem.rule, problem.line) == ("threshold", line_of(root, DRIVER, "holdFor"))


def test_a_comparison_with_a_fraction_fails_outside_capture_code(tmp_path):
    root = mutated(tmp_path, Path("Likeness/App/Theme.swift"), "static let card =",
                   "static func strong(_ weight: Float) -> Bool { weight >= 0.8 }\n    static let card =")
    (problem,) = run(root).problems
    assert problem.rule == "threshold" and "0.8" in problem.message


def test_fractions_are_fine_in_looks_and_in_tests():
    # Theme.swift has 0.55; GlueTests.swift compares with 0.5.
    assert run(GOOD_APP).problems == []


# ---------------------------------------------------------------- rule: network

@pytest.mark.parametrize("line", ["import Network", "let session = URLSession.shared"])
def test_networking_fails(tmp_path, line):
    root = mutated(tmp_path, DRIVER, "import LikenessFFI\n", f"import LikenessFFI\n{line}\n")
    assert any(p.rule == "network" for p in run(root).problems)
