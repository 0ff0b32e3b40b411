#!/usr/bin/env python3
"""Static checks of the Swift iOS app (``ios-app/``) that run on Linux, with no
Swift toolchain: the app is parsed with tree-sitter-swift and compared with the
UniFFI-generated bindings of the core.

Usage::

    python3 tests/python/swift_checks.py --bindings PATH/likeness_ffi.swift [--root ios-app]
        [--names rust-core/src/arkit/blendshape.rs] [--verbose]

``--verbose`` also lists every use of the core that was checked.

Prints one line per problem, ``file:line:column: [rule] message``, and exits 1
if there is any (2 for bad arguments). Needs the PyPI packages pinned in
``tests/python/requirements-swift.txt``.

Rules
-----
``syntax``
    Every ``.swift`` file under ROOT parses with no ERROR or MISSING node.

``ffi``
    Every name the app takes from the core exists, spelled so, in the
    bindings. From the bindings the checker reads the public surface: types
    (classes, records, enums, protocols) with their methods, static methods,
    initializer labels, fields and enum cases (with associated values), and
    free functions. UniFFI's plumbing (``FfiConverter*``, ``uniffi*``, and
    whatever it marks ``@_documentation(visibility: private)``) is not part of
    the surface. In the app:

    * a capitalized name (type or value) that the app does not declare must be
      a bindings type or on the list of Apple / Swift names in
      ``swift_ffi_checker.py`` (``APPLE_NAMES``): ``CaptureSesion`` fails;
    * a call of a free function the app does not declare must be a bindings
      function (with its argument labels) or on ``APPLE_FUNCTIONS``:
      ``arkitName()`` fails;
    * ``T(...)`` for a bindings type must match one of its initializers'
      labels (records: the memberwise initializer); ``T.member`` must be a
      static method or an enum case of ``T``;
    * ``value.member`` where the checker can tell that ``value`` is of a
      bindings type must be a method or field of that type, and a call must
      use one of its signatures' labels: ``session.pushframe(...)`` and
      ``session.pushFrame(time: ...)`` fail. The type of a name comes from its
      annotation (``let s: CaptureSession``, parameters, closure parameters,
      properties of the app's own types), from an initializer or a call into
      the bindings (``let events = try core.pushFrame(...)`` is
      ``[CaptureEvent]``), from ``for x in`` over such an array, from
      ``if let`` / ``guard let``, ``catch let e as T``, and from the values a
      ``case`` pattern binds;
    * in a ``switch`` over a value of a bindings enum, every ``case .name``
      must be one of its cases and bind at most as many values as it carries:
      ``.PromptStarted`` fails;
    * an app type declaring conformance to a bindings protocol must implement
      each requirement with the same name and labels: ``isCanceled()`` fails;
    * any other ``.member`` that equals a bindings member or case except in
      letter case is reported as a misspelling (``.invalidInput`` for
      ``.InvalidInput``).

``arkit-names``
    The app holds no list of ARKit's blendshape names: the core's
    ``arkitNames()`` is the list. The 52 names are read from the Rust core
    (``--names``, where they are spelled once) and counted in the app's string
    literals, in either spelling (``"eyeBlinkLeft"`` or ARKit's raw value
    ``"eyeBlink_L"``), and as member names (``.eyeBlinkLeft``). More than
    ``MAX_ARKIT_NAMES`` (3) distinct shapes across all Swift files under ROOT
    fail; a unit test may name a few to pin the conversion down.

``threshold``
    The app holds no capture threshold: when a face counts is the core's
    decision. Weights and their thresholds live in 0…1, so:

    * anywhere outside ``Tests/``, a comparison (``<``, ``<=``, ``>``,
      ``>=``, ``==``, ``!=``) with a number strictly between 0 and 1 as an
      operand fails (``if weight > 0.5``);
    * under ``Likeness/Capture/`` (the code that carries frames to the core and
      its answers to the screen) any number strictly between 0 and 1 fails,
      wherever it stands: capture code has no tuning constants at all. Looks
      such as opacities live in ``Likeness/App/Theme.swift``.

``network``
    Nothing leaves the phone: networking APIs (``URLSession``,
    ``URLRequest``, ``NWConnection``, ``WKWebView``, ``import Network``, ...)
    do not appear in the app.
"""
from __future__ import annotations

import argparse
import re
import sys
from dataclasses import dataclass
from pathlib import Path

from tree_sitter import Node

from swift_syntax import Problem, problem_at, text, walk
from swift_bindings import Bindings, load_bindings
from swift_app import SwiftFile, display_path, index_app, load_app, preceded_by_dot
from swift_ffi_checker import FfiChecker

MAX_ARKIT_NAMES = 3

CAPTURE_DIR = ("Likeness", "Capture")

TESTS_DIR = "Tests"

REPO = Path(__file__).resolve().parents[2]

DEFAULT_NAMES_FILE = REPO / "rust-core" / "src" / "arkit" / "blendshape.rs"

NETWORK_NAMES = frozenset(
    """
    URLSession URLSessionConfiguration URLSessionTask URLSessionDataTask
    URLSessionWebSocketTask URLRequest URLConnection NWConnection NWListener
    NWPathMonitor NWBrowser NWEndpoint NWParameters WKWebView
    SFSafariViewController CFSocket CFStream SCNetworkReachability
    MCSession MCNearbyServiceAdvertiser
    """.split()
)


COMPARISON_OPERATORS = frozenset({"<", "<=", ">", ">=", "==", "!="})

NETWORK_MODULES = frozenset({"Network", "WebKit", "CFNetwork", "MultipeerConnectivity", "SafariServices"})


def check_syntax(files: list[SwiftFile]) -> list[Problem]:
    problems = []
    for swift_file in files:
        for node in walk(swift_file.root):
            if node.is_missing:
                problems.append(problem_at(swift_file.display, node, "syntax", f"missing `{node.type}`"))
            elif node.type == "ERROR":
                snippet = text(node).split("\n")[0][:40]
                problems.append(problem_at(swift_file.display, node, "syntax", f"cannot parse here: `{snippet}`"))
    return problems


def check_ffi(files: list[SwiftFile], bindings: Bindings) -> tuple[list[Problem], list[str]]:
    """The ``ffi`` rule: problems, and every use of the core that was checked."""
    app = index_app(files)
    # The app may not declare a type the bindings declare: it would shadow it.
    app.types -= set(bindings.types)
    problems: list[Problem] = []
    uses: list[str] = []
    for swift_file in files:
        checker = FfiChecker(swift_file, bindings, app)
        problems += checker.run()
        uses += checker.uses
    return problems, uses


def arkit_names(names_file: Path) -> list[str]:
    names = re.findall(r'^\s*\w+\s*=\s*"(\w+)"\s*,\s*\w+\s*;', names_file.read_text(encoding="utf-8"), re.M)
    if len(names) != 52:
        raise SystemExit(f"swift_checks: expected 52 ARKit names in {names_file}, found {len(names)}")
    return names


def raw_spelling(name: str) -> str:
    """ARKit's raw value for a name with a side: ``eyeBlinkLeft`` → ``eyeBlink_L``."""
    for side, short in (("Left", "_L"), ("Right", "_R")):
        if name.endswith(side):
            return name[: -len(side)] + short
    return name


def check_arkit_names(files: list[SwiftFile], names: list[str]) -> list[Problem]:
    spellings = {}
    for name in names:
        spellings[name] = name
        spellings[raw_spelling(name)] = name
    found: dict[str, tuple[SwiftFile, Node]] = {}
    for swift_file in files:
        for node in walk(swift_file.root):
            if node.type in ("line_str_text", "multi_line_str_text"):
                for word in re.findall(r"\w+", text(node)):
                    if word in spellings:
                        found.setdefault(spellings[word], (swift_file, node))
            elif node.type == "simple_identifier" and text(node) in names \
                    and preceded_by_dot(swift_file.source, node):
                found.setdefault(text(node), (swift_file, node))
    if len(found) <= MAX_ARKIT_NAMES:
        return []
    return [
        problem_at(swift_file.display, node, "arkit-names",
                   f"ARKit blendshape name `{name}` spelled in Swift ({len(found)} distinct names in the app, at most "
                   f"{MAX_ARKIT_NAMES} allowed): take the names from the core's arkitNames()")
        for name, (swift_file, node) in sorted(found.items(),
                                               key=lambda item: (item[1][0].display, item[1][1].start_byte))
    ]


def fraction_literal(node: Node) -> float | None:
    """The value of a number literal strictly between 0 and 1, else ``None``."""
    if node.type != "real_literal":
        return None
    try:
        value = float(text(node).replace("_", ""))
    except ValueError:
        return None
    return value if 0 < value < 1 else None


def check_thresholds(files: list[SwiftFile]) -> list[Problem]:
    problems = []
    for swift_file in files:
        in_tests = swift_file.relative.parts[:1] == (TESTS_DIR,)
        in_capture = swift_file.under(*CAPTURE_DIR)
        for node in walk(swift_file.root):
            if in_capture and fraction_literal(node) is not None:
                problems.append(problem_at(
                    swift_file.display, node, "threshold",
                    f"number {text(node)} in capture code: thresholds are the core's; looks belong in Theme.swift"))
            elif not in_tests and not in_capture and text(node.child_by_field_name("op")) in COMPARISON_OPERATORS:
                # tree-sitter-swift reads some comparisons as an infix_expression
                # with a "custom" operator, so go by the operator itself.
                for operand in (node.child_by_field_name("lhs"), node.child_by_field_name("rhs")):
                    if operand is None:
                        continue
                    if fraction_literal(operand) is not None:
                        problems.append(problem_at(
                            swift_file.display, operand, "threshold",
                            f"comparison with {text(operand)}: a threshold on weights is the core's decision"))
    return problems


def check_network(files: list[SwiftFile]) -> list[Problem]:
    problems = []
    for swift_file in files:
        for node in walk(swift_file.root):
            if node.type == "import_declaration":
                module = text(node.named_children[0]) if node.named_children else ""
                if module.split(".")[0] in NETWORK_MODULES:
                    problems.append(problem_at(swift_file.display, node, "network",
                                               f"`import {module}`: the app does no networking"))
            elif node.type in ("type_identifier", "simple_identifier") and text(node) in NETWORK_NAMES:
                problems.append(problem_at(swift_file.display, node, "network",
                                           f"`{text(node)}`: the app does no networking"))
    return problems


@dataclass
class Report:
    """The outcome of all rules."""

    problems: list[Problem]
    uses: list[str]
    summary: str


def run_checks(root: Path, bindings_path: Path, names_path: Path) -> Report:
    """Every rule over the Swift files under ``root``."""
    files = load_app(root)
    if not files:
        return Report([Problem(str(root), 0, 0, "syntax", "no .swift files found")], [], "")
    bindings = load_bindings(bindings_path)
    if not bindings.types or not bindings.functions:
        return Report([Problem(display_path(bindings_path), 1, 1, "ffi",
                               "no public declarations found in the bindings")], [], "")
    problems = check_syntax(files)
    ffi_problems, uses = check_ffi(files, bindings)
    problems += ffi_problems
    problems += check_arkit_names(files, arkit_names(names_path))
    problems += check_thresholds(files)
    problems += check_network(files)
    summary = (f"swift_checks: {len(files)} Swift files, {len(uses)} uses of the core checked against "
               f"{len(bindings.types)} types and {len(bindings.functions)} function(s) in the bindings")
    return Report(sorted(set(problems)), uses, summary)


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--bindings", required=True, type=Path, help="the UniFFI-generated likeness_ffi.swift")
    parser.add_argument("--root", type=Path, default=REPO / "ios-app", help="the app's folder (default: ios-app)")
    parser.add_argument("--names", type=Path, default=DEFAULT_NAMES_FILE,
                        help="the Rust file spelling ARKit's 52 names (default: rust-core/src/arkit/blendshape.rs)")
    parser.add_argument("--verbose", action="store_true", help="also list every use of the core that was checked")
    args = parser.parse_args(argv)
    for path in (args.bindings, args.root, args.names):
        if not path.exists():
            parser.error(f"{path} does not exist")
    report = run_checks(args.root, args.bindings, args.names)
    if args.verbose:
        for use in report.uses:
            print(use)
    for found in report.problems:
        print(found)
    if report.summary:
        print(report.summary)
    print(f"swift_checks: {len(report.problems)} problem(s)")
    return 1 if report.problems else 0


if __name__ == "__main__":
    sys.exit(main())
