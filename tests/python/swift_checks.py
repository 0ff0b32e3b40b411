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
      a bindings type or on the list of Apple / Swift names below
      (``APPLE_NAMES``): ``CaptureSesion`` fails;
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
from dataclasses import dataclass, field
from pathlib import Path

import tree_sitter_swift
from tree_sitter import Language, Node, Parser

SWIFT = Language(tree_sitter_swift.language())

MAX_ARKIT_NAMES = 3
CAPTURE_DIR = ("Likeness", "Capture")
TESTS_DIR = "Tests"
REPO = Path(__file__).resolve().parents[2]
DEFAULT_NAMES_FILE = REPO / "rust-core" / "src" / "arkit" / "blendshape.rs"

# Apple framework and Swift standard library names the app may use besides its
# own and the core's. Add to it when the app starts using another one: the
# check is that every capitalized name is known, so a misspelled core type
# cannot slip through as "probably Apple's".
APPLE_NAMES = frozenset(
    """
    Any AnyObject Array Bool Character Dictionary Double Equatable Error Float
    Hashable Identifiable Int Int8 Int16 Int32 Int64 Never Optional Result Self
    Sendable Set String Substring UInt UInt8 UInt16 UInt32 UInt64 Void UTF8
    CaseIterable Comparable Codable Decodable Encodable Collection Sequence
    RandomAccessCollection MemoryLayout SIMD2 SIMD3 SIMD4 FixedWidthInteger
    BinaryFloatingPoint Range ClosedRange KeyPath MainActor Task TimeInterval
    Swift Foundation CustomStringConvertible ObjectIdentifier AnyHashable

    Bundle Data Date DateFormatter DispatchQueue FileAttributeKey FileManager
    FileProtectionType JSONDecoder JSONEncoder Locale LocalizedError NSError
    NSLock NSLocalizedDescriptionKey NSNumber NSObject NSString Notification
    NotificationCenter ProcessInfo URL UUID

    ARAnchor ARConfiguration ARError ARFaceAnchor ARFaceGeometry
    ARFaceTrackingConfiguration ARFrame ARSCNFaceGeometry ARSCNView
    ARSCNViewDelegate ARSession ARSessionDelegate ARSessionObserver ARKit
    ARTrackable

    SCNCamera SCNGeometry SCNGeometryElement SCNGeometrySource SCNLight
    SCNMaterial SCNNode SCNScene SCNSceneRenderer SCNTransaction SCNMatrix4MakeTranslation SCNVector3
    SCNView SceneKit

    CGFloat CGPoint CGRect CGSize UIActivityViewController UIApplication UIColor
    UIView UIViewController UIViewControllerRepresentable UIViewRepresentable
    UIKit

    Alignment Animation App AnyView Binding Button ButtonStyle Capsule Circle
    Color Context Divider EdgeInsets EmptyView Environment Font ForEach Form
    GeometryReader Group HStack Image Label LazyVStack List LocalizedStringKey
    NavigationStack Observable ObservationIgnored Observation ProgressView
    RoundedRectangle Scene ScrollView Section ShareLink SharePreview Spacer
    State StateObject SwiftUI Text Toggle VStack View ViewBuilder WindowGroup
    ZStack

    MTLDevice Metal XCTest XCTestCase XCTAssert XCTAssertEqual XCTAssertTrue
    XCTAssertFalse XCTAssertNil XCTAssertNotNil XCTAssertThrowsError
    XCTAssertNoThrow XCTAssertGreaterThan XCTAssertGreaterThanOrEqual
    XCTAssertLessThan XCTAssertLessThanOrEqual XCTAssertNotEqual
    XCTAssertIdentical XCTAssertNotIdentical XCTFail XCTUnwrap XCTSkip
    """.split()
)

# Free functions of Swift and Darwin the app may call.
APPLE_FUNCTIONS = frozenset(
    """
    abs assert assertionFailure debugPrint dump fatalError max min precondition
    preconditionFailure print repeatElement sequence simd_cross simd_distance
    simd_dot simd_length simd_normalize simd_quatf stride swap type uname
    utsname withAnimation withExtendedLifetime withUnsafeBytes
    withUnsafeMutableBytes withUnsafePointer withUnsafeMutablePointer zip
    """.split()
)

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

# Node types that open a scope for names declared in them.
SCOPE_TYPES = frozenset(
    {
        "source_file",
        "class_declaration",
        "protocol_declaration",
        "function_declaration",
        "init_declaration",
        "lambda_literal",
        "for_statement",
        "switch_entry",
        "catch_block",
        "if_statement",
        "computed_property",
    }
)


@dataclass(frozen=True, order=True)
class Problem:
    """One finding, printed as ``file:line:column: [rule] message``."""

    path: str
    line: int
    column: int
    rule: str
    message: str

    def __str__(self) -> str:
        return f"{self.path}:{self.line}:{self.column}: [{self.rule}] {self.message}"


def problem_at(path: str, node: Node, rule: str, message: str) -> Problem:
    row, column = node.start_point
    return Problem(path, row + 1, column + 1, rule, message)


def parse(source: bytes):
    return Parser(SWIFT).parse(source)


def text(node: Node | None) -> str:
    return "" if node is None else node.text.decode("utf-8")


def walk(node: Node):
    """Every node under ``node``, itself first, in source order."""
    stack = [node]
    while stack:
        current = stack.pop()
        yield current
        stack.extend(reversed(current.children))


def named_children(node: Node, field_name: str) -> list[Node]:
    return [c for i, c in enumerate(node.children) if node.field_name_for_child(i) == field_name]


# --------------------------------------------------------------------------
# Types as text

def type_text(node: Node | None) -> str | None:
    if node is None:
        return None
    return re.sub(r"\s+", "", text(node))


def strip_optional(type_name: str | None) -> str | None:
    if type_name is None:
        return None
    while type_name.endswith(("?", "!")):
        type_name = type_name[:-1]
    if type_name.startswith("Optional<") and type_name.endswith(">"):
        type_name = type_name[len("Optional<"):-1]
    return type_name


def element_type(type_name: str | None) -> str | None:
    """``X`` for ``[X]`` (after dropping optionality), else ``None``."""
    base = strip_optional(type_name)
    if base and base.startswith("[") and base.endswith("]") and ":" not in base:
        return base[1:-1]
    return None


# --------------------------------------------------------------------------
# The bindings

@dataclass(frozen=True)
class Param:
    label: str | None  # None: no label (`_`)
    has_default: bool


@dataclass(frozen=True)
class Signature:
    params: tuple[Param, ...]
    returns: str | None
    static: bool = False

    def describe(self, name: str) -> str:
        labels = "".join(f"{p.label or '_'}:" for p in self.params)
        return f"{name}({labels})"

    def accepts(self, labels: list[str | None]) -> bool:
        """Whether a call with these argument labels fits (defaults may be left out)."""
        remaining = list(labels)
        for param in self.params:
            if remaining and remaining[0] == param.label:
                remaining.pop(0)
            elif not param.has_default:
                return False
        return not remaining


@dataclass
class FfiType:
    name: str
    kind: str  # class, struct, enum, protocol
    methods: dict[str, list[Signature]] = field(default_factory=dict)
    fields: dict[str, str] = field(default_factory=dict)
    inits: list[Signature] = field(default_factory=list)
    cases: dict[str, list[tuple[str | None, str]]] = field(default_factory=dict)

    def member_names(self) -> set[str]:
        return set(self.methods) | set(self.fields) | set(self.cases)


@dataclass
class Bindings:
    types: dict[str, FfiType] = field(default_factory=dict)
    functions: dict[str, list[Signature]] = field(default_factory=dict)
    parse_errors: int = 0

    def all_member_names(self) -> set[str]:
        names: set[str] = set(self.functions)
        for ffi_type in self.types.values():
            names |= ffi_type.member_names()
        return names

    def lookup(self, type_name: str | None) -> FfiType | None:
        base = strip_optional(type_name)
        return self.types.get(base) if base else None


def is_plumbing(name: str) -> bool:
    return name.startswith(("FfiConverter", "uniffi", "Uniffi", "UNIFFI"))


def visibility(node: Node) -> str:
    for child in node.children:
        if child.type == "modifiers":
            for modifier in child.children:
                if modifier.type == "visibility_modifier":
                    return text(modifier).split("(")[0]
    return "internal"


def has_modifier(node: Node, word: str) -> bool:
    for child in node.children:
        if child.type == "modifiers":
            return any(text(m) == word for m in child.children)
    return False


def params_of(node: Node) -> tuple[Param, ...]:
    """The parameters of a function or initializer: label and whether a
    default value follows (tree-sitter puts ``= value`` after the parameter)."""
    params: list[Param] = []
    children = node.children
    for i, child in enumerate(children):
        if child.type != "parameter":
            continue
        external = child.child_by_field_name("external_name")
        if external is not None:
            label = text(external)
        else:
            names = [c for c in named_children(child, "name") if c.type == "simple_identifier"]
            label = text(names[0]) if names else None
        has_default = i + 1 < len(children) and children[i + 1].type == "="
        params.append(Param(None if label == "_" else label, has_default))
    return tuple(params)


def return_type(node: Node) -> str | None:
    seen_arrow = False
    for i, child in enumerate(node.children):
        if child.type == "->":
            seen_arrow = True
        elif seen_arrow and node.field_name_for_child(i) == "name":
            return type_text(child)
    return None


def preprocess_bindings(source: str) -> tuple[str, set[int]]:
    """Blank out the lines tree-sitter-swift cannot read in UniFFI's output
    (``#if`` around attributes, ``@_documentation``), keeping line numbers,
    and return the rows of ``@_documentation(visibility: private)``."""
    lines = source.split("\n")
    private_rows: set[int] = set()
    for row, line in enumerate(lines):
        stripped = line.strip()
        if stripped.startswith("@_documentation"):
            if "private" in stripped:
                private_rows.add(row)
            lines[row] = " " * len(line)
        elif re.match(r"#(if|elseif|else|endif)\b", stripped):
            lines[row] = " " * len(line)
    return "\n".join(lines), private_rows


DECLARATION_TYPES = frozenset(
    {
        "class_declaration",
        "protocol_declaration",
        "function_declaration",
        "init_declaration",
        "property_declaration",
        "protocol_function_declaration",
        "enum_entry",
    }
)


def load_bindings(path: Path) -> Bindings:
    source, private_rows = preprocess_bindings(path.read_text(encoding="utf-8"))
    tree = parse(source.encode("utf-8"))
    bindings = Bindings()
    bindings.parse_errors = sum(1 for n in walk(tree.root_node) if n.type == "ERROR" or n.is_missing)

    declaration_rows = sorted({n.start_point[0] for n in walk(tree.root_node) if n.type in DECLARATION_TYPES})
    hidden_rows: set[int] = set()
    for row in private_rows:
        following = [r for r in declaration_rows if r > row]
        if following:
            hidden_rows.add(following[0])

    def public(node: Node) -> bool:
        return visibility(node) in ("public", "open") and node.start_point[0] not in hidden_rows

    def add_members(ffi_type: FfiType, body: Node) -> None:
        for member in body.children:
            if member.type in ("function_declaration", "protocol_function_declaration"):
                name = text(member.child_by_field_name("name"))
                if is_plumbing(name) or (member.type == "function_declaration" and not public(member)):
                    continue
                signature = Signature(params_of(member), return_type(member), has_modifier(member, "static"))
                ffi_type.methods.setdefault(name, []).append(signature)
            elif member.type == "init_declaration" and public(member):
                ffi_type.inits.append(Signature(params_of(member), ffi_type.name))
            elif member.type == "property_declaration" and public(member):
                pattern = member.child_by_field_name("name")
                bound = pattern.child_by_field_name("bound_identifier") if pattern else None
                annotation = next((c for c in member.children if c.type == "type_annotation"), None)
                if bound is not None:
                    declared = annotation.child_by_field_name("name") if annotation else None
                    ffi_type.fields[text(bound)] = type_text(declared)
            elif member.type == "enum_entry":
                for name_node in named_children(member, "name"):
                    values: list[tuple[str | None, str]] = []
                    contents = member.child_by_field_name("data_contents")
                    if contents is not None:
                        label = None
                        for part in contents.children:
                            if part.type == "simple_identifier":
                                label = text(part)
                            elif part.type in (",", ")"):
                                pass
                            elif part.is_named:
                                values.append((label, type_text(part)))
                                label = None
                    ffi_type.cases[text(name_node)] = values

    for node in tree.root_node.children:
        if node.type == "class_declaration":
            kind = text(node.child_by_field_name("declaration_kind"))
            name = type_text(node.child_by_field_name("name"))
            body = node.child_by_field_name("body")
            if not name or is_plumbing(name) or body is None:
                continue
            if kind == "extension":
                if name in bindings.types:
                    add_members(bindings.types[name], body)
                continue
            if not public(node):
                continue
            ffi_type = bindings.types.setdefault(name, FfiType(name, kind))
            add_members(ffi_type, body)
        elif node.type == "protocol_declaration" and public(node):
            name = type_text(node.child_by_field_name("name"))
            ffi_type = bindings.types.setdefault(name, FfiType(name, "protocol"))
            body = node.child_by_field_name("body")
            if body is not None:
                add_members(ffi_type, body)
        elif node.type == "function_declaration" and public(node):
            name = text(node.child_by_field_name("name"))
            if not is_plumbing(name):
                bindings.functions.setdefault(name, []).append(Signature(params_of(node), return_type(node)))
    return bindings


# --------------------------------------------------------------------------
# The app

@dataclass
class SwiftFile:
    """One parsed Swift file of the app."""

    path: Path
    relative: Path  # to the app's root
    display: str  # as printed in problems
    source: bytes
    tree: object

    @property
    def root(self) -> Node:
        return self.tree.root_node

    def under(self, *parts: str) -> bool:
        return tuple(self.relative.parts[: len(parts)]) == parts


def load_app(root: Path) -> list[SwiftFile]:
    files = []
    for path in sorted(root.rglob("*.swift")):
        if any(part.startswith(".") or part.endswith(".xcodeproj") for part in path.relative_to(root).parts):
            continue
        source = path.read_bytes()
        files.append(SwiftFile(path, path.relative_to(root), display_path(path), source, parse(source)))
    return files


def display_path(path: Path) -> str:
    try:
        return str(path.resolve().relative_to(Path.cwd().resolve()))
    except ValueError:
        return str(path)


def preceded_by_dot(source: bytes, node: Node) -> bool:
    index = node.start_byte - 1
    while index >= 0 and source[index:index + 1] in (b" ", b"\t", b"\n", b"\r"):
        index -= 1
    return index >= 0 and source[index:index + 1] == b"."


def in_attribute(node: Node) -> bool:
    parent = node.parent
    while parent is not None:
        if parent.type == "attribute":
            return True
        if parent.type in SCOPE_TYPES:
            return False
        parent = parent.parent
    return False


def scope_of(node: Node) -> Node:
    parent = node.parent
    while parent is not None and parent.type not in SCOPE_TYPES:
        parent = parent.parent
    return parent


def enclosing_type(node: Node) -> Node | None:
    parent = node.parent
    while parent is not None:
        if parent.type in ("class_declaration", "protocol_declaration"):
            return parent
        parent = parent.parent
    return None


@dataclass
class AppIndex:
    """What the app itself declares: type names, other names, and the
    declared types of its types' properties (for ``saved.handle``)."""

    types: set[str] = field(default_factory=set)
    values: set[str] = field(default_factory=set)
    members: dict[str, dict[str, str]] = field(default_factory=dict)
    # (owning type or None, function name) -> declared return type
    returns: dict[tuple[str | None, str], str] = field(default_factory=dict)


def type_name_of(declaration: Node) -> str | None:
    name = declaration.child_by_field_name("name")
    return type_text(name) if name is not None else None


def index_app(files: list[SwiftFile]) -> AppIndex:
    index = AppIndex()
    for swift_file in files:
        for node in walk(swift_file.root):
            if node.type in ("class_declaration", "protocol_declaration", "typealias_declaration"):
                name = type_name_of(node)
                if name and text(node.child_by_field_name("declaration_kind")) != "extension":
                    index.types.add(name)
            elif node.type in ("function_declaration", "protocol_function_declaration", "enum_entry"):
                for name_node in named_children(node, "name"):
                    if name_node.type == "simple_identifier":
                        index.values.add(text(name_node))
                if node.type == "function_declaration" and return_type(node):
                    owner = enclosing_type(node)
                    key = (type_name_of(owner) if owner is not None else None, text(node.child_by_field_name("name")))
                    index.returns[key] = return_type(node)
            elif node.type in ("parameter", "lambda_parameter"):
                for child in node.children:
                    if child.type == "simple_identifier":
                        index.values.add(text(child))
            elif node.type == "simple_identifier":
                parent = node.parent
                field_name = parent.field_name_for_child(parent.children.index(node)) if parent else None
                if field_name == "bound_identifier" or (parent is not None and parent.type == "pattern"):
                    index.values.add(text(node))
            if node.type == "property_declaration":
                owner = enclosing_type(node)
                pattern = node.child_by_field_name("name")
                bound = pattern.child_by_field_name("bound_identifier") if pattern else None
                annotation = next((c for c in node.children if c.type == "type_annotation"), None)
                if owner is not None and bound is not None and annotation is not None and scope_of(node) == owner:
                    owner_name = type_name_of(owner)
                    index.members.setdefault(owner_name, {})[text(bound)] = type_text(
                        annotation.child_by_field_name("name"))
    return index


class FfiChecker:
    """The ``ffi`` rule over one file; see the module docstring."""

    def __init__(self, swift_file: SwiftFile, bindings: Bindings, app: AppIndex):
        self.file = swift_file
        self.bindings = bindings
        self.app = app
        self.problems: list[Problem] = []
        self.checked_member_nodes: set[int] = set()
        self.uses: list[str] = []
        # (scope node id, name) -> declared type
        self.declared: dict[tuple[int, str], str | None] = {}

    # ---- reporting
    def report(self, node: Node, message: str) -> None:
        self.problems.append(problem_at(self.file.display, node, "ffi", message))

    def used(self, node: Node, what: str) -> None:
        row, column = node.start_point
        self.uses.append(f"{self.file.display}:{row + 1}:{column + 1}: {what}")

    # ---- types of names
    def declare(self, scope: Node | None, name: str, type_name: str | None) -> None:
        if scope is not None and type_name:
            self.declared[(scope.id, name)] = type_name

    def lookup(self, node: Node, name: str) -> str | None:
        scope = node
        while scope is not None:
            if scope.type in SCOPE_TYPES and (scope.id, name) in self.declared:
                return self.declared[(scope.id, name)]
            if scope.type == "class_declaration":
                owner = type_name_of(scope)
                member = self.app.members.get(owner, {}).get(name)
                if member:
                    return member
            scope = scope.parent
        return None

    def self_type(self, node: Node) -> str | None:
        owner = enclosing_type(node)
        return type_name_of(owner) if owner is not None else None

    def member_type(self, owner: str | None, member: str) -> str | None:
        ffi_type = self.bindings.lookup(owner)
        if ffi_type is not None:
            if member in ffi_type.fields:
                return ffi_type.fields[member]
            return None
        base = strip_optional(owner)
        return self.app.members.get(base, {}).get(member) if base else None

    def infer(self, expr: Node | None) -> str | None:
        """The type of an expression, where the checker can tell."""
        if expr is None:
            return None
        kind = expr.type
        if kind in ("try_expression", "await_expression"):
            inner = expr.child_by_field_name("expr")
            result = self.infer(inner)
            if kind == "try_expression" and any(c.type == "?" for c in walk(expr.children[0])) and result:
                return result + "?"
            return result
        if kind == "parenthesized_expression":
            return self.infer(expr.named_children[0] if expr.named_children else None)
        if kind == "postfix_expression":
            return strip_optional(self.infer(expr.child_by_field_name("target")))
        if kind == "as_expression":
            return type_text(expr.child_by_field_name("name"))
        if kind == "simple_identifier":
            return self.lookup(expr, text(expr))
        if kind == "self_expression":
            return self.self_type(expr)
        if kind == "navigation_expression":
            target = expr.child_by_field_name("target")
            member = self.suffix_name(expr)
            if target is None or member is None:
                return None
            if target.type == "simple_identifier" and text(target) in self.bindings.types:
                return None
            return self.member_type(self.infer(target), member)
        if kind == "call_expression":
            callee = expr.children[0]
            if callee.type == "simple_identifier":
                name = text(callee)
                if name in self.bindings.types:
                    return name
                if name in self.bindings.functions and name not in self.app.values:
                    return self.bindings.functions[name][0].returns
                return self.app.returns.get((self.self_type(expr), name)) or self.app.returns.get((None, name))
            if callee.type == "navigation_expression":
                target = callee.child_by_field_name("target")
                member = self.suffix_name(callee)
                if target is None or member is None:
                    return None
                if target.type == "simple_identifier" and text(target) in self.bindings.types:
                    signatures = self.bindings.types[text(target)].methods.get(member, [])
                    return signatures[0].returns if signatures else None
                if target.type == "simple_identifier" and text(target) in self.app.types:
                    return self.app.returns.get((text(target), member))
                owner = self.infer(target)
                ffi_type = self.bindings.lookup(owner)
                if ffi_type is not None:
                    return ffi_type.methods[member][0].returns if member in ffi_type.methods else None
                return self.app.returns.get((strip_optional(owner), member))
            return None
        return None

    @staticmethod
    def suffix_name(navigation: Node) -> str | None:
        suffix = navigation.child_by_field_name("suffix")
        if suffix is None:
            return None
        name = suffix.child_by_field_name("suffix")
        return text(name) if name is not None and name.type == "simple_identifier" else None

    # ---- declarations that give names types
    def collect_declarations(self) -> None:
        for node in walk(self.file.root):
            kind = node.type
            if kind == "property_declaration":
                pattern = node.child_by_field_name("name")
                bound = pattern.child_by_field_name("bound_identifier") if pattern else None
                if bound is None:
                    continue
                annotation = next((c for c in node.children if c.type == "type_annotation"), None)
                declared = type_text(annotation.child_by_field_name("name")) if annotation else None
                if declared is None:
                    declared = self.infer(node.child_by_field_name("value"))
                self.declare(scope_of(node), text(bound), declared)
            elif kind == "parameter":
                names = [c for c in named_children(node, "name") if c.type == "simple_identifier"]
                types = [c for c in named_children(node, "name") if c.type != "simple_identifier"]
                if names and types:
                    self.declare(node.parent, text(names[-1]), type_text(types[0]))
            elif kind == "lambda_parameter":
                names = [c for c in named_children(node, "name") if c.type == "simple_identifier"]
                types = [c for c in named_children(node, "name") if c.type != "simple_identifier"]
                lambda_node = node.parent
                while lambda_node is not None and lambda_node.type != "lambda_literal":
                    lambda_node = lambda_node.parent
                if names and types:
                    self.declare(lambda_node, text(names[0]), type_text(types[0]))
            elif kind in ("if_statement", "guard_statement"):
                self.collect_optional_bindings(node)
            elif kind == "for_statement":
                item = node.child_by_field_name("item")
                collection = node.child_by_field_name("collection")
                bound = item.child_by_field_name("bound_identifier") if item else None
                if bound is not None:
                    self.declare(node, text(bound), element_type(self.infer(collection)))
            elif kind == "catch_block":
                pattern = node.child_by_field_name("error")
                if pattern is not None and any(c.type == "as" for c in pattern.children):
                    inner = next((c for c in pattern.children if c.type == "pattern"), None)
                    bound = inner.child_by_field_name("bound_identifier") if inner else None
                    as_type = next((c for c in reversed(pattern.children) if c.is_named and c.type != "pattern"), None)
                    if bound is not None:
                        self.declare(node, text(bound), type_text(as_type))

    def collect_optional_bindings(self, node: Node) -> None:
        children = node.children
        scope = node if node.type == "if_statement" else scope_of(node)
        for i, child in enumerate(children):
            if node.field_name_for_child(i) != "bound_identifier":
                continue
            if i + 2 < len(children) and children[i + 1].type == "=":
                value = children[i + 2]
                self.declare(scope, text(child), strip_optional(self.infer(value)))

    # ---- the checks
    def run(self) -> list[Problem]:
        # Types first: a later declaration can depend on an earlier one.
        for _ in range(2):
            self.collect_declarations()
        for node in walk(self.file.root):
            if node.type == "switch_statement":
                self.check_switch(node)
        for node in walk(self.file.root):
            if node.type == "call_expression":
                self.check_call(node)
            elif node.type == "navigation_expression":
                self.check_navigation(node)
            elif node.type == "catch_block":
                self.check_catch(node)
            elif node.type == "class_declaration":
                self.check_conformance(node)
        self.check_names()
        return self.problems

    def call_labels(self, call: Node) -> list[str | None]:
        labels: list[str | None] = []
        for suffix in call.children[1:]:
            if suffix.type != "call_suffix":
                continue
            for part in suffix.children:
                if part.type == "value_arguments":
                    for argument in part.children:
                        if argument.type == "value_argument":
                            label = argument.child_by_field_name("name")
                            labels.append(text(label) if label is not None else None)
                elif part.type == "lambda_literal":
                    labels.append(None)
        return labels

    def check_signature(self, node: Node, callee: str, signatures: list[Signature], labels) -> None:
        """A call of ``callee`` (``arkitNames``, ``CaptureSession``,
        ``CaptureSession.pushFrame``) with these labels fits a signature."""
        called = "".join(f"{label or '_'}:" for label in labels)
        self.used(node, f"call {callee}({called})")
        if not any(s.accepts(labels) for s in signatures):
            short = callee.split(".")[-1]
            known = ", ".join(s.describe(short) for s in signatures)
            self.report(node, f"`{callee}({called})` does not match the bindings' {known}")

    def check_call(self, call: Node) -> None:
        callee = call.children[0]
        labels = self.call_labels(call)
        if callee.type == "simple_identifier":
            name = text(callee)
            if name in self.app.values or name in self.app.types:
                return
            if name in self.bindings.types:
                ffi_type = self.bindings.types[name]
                if not ffi_type.inits:
                    self.report(callee, f"`{name}` has no public initializer in the bindings")
                else:
                    self.check_signature(callee, name, ffi_type.inits, labels)
            elif name in self.bindings.functions:
                self.check_signature(callee, name, self.bindings.functions[name], labels)
        elif callee.type == "navigation_expression":
            self.check_navigation(callee, labels)

    def check_navigation(self, navigation: Node, labels: list[str | None] | None = None) -> None:
        if navigation.id in self.checked_member_nodes:
            return
        member = self.suffix_name(navigation)
        target = navigation.child_by_field_name("target")
        if member is None or target is None:
            return
        is_call = labels is not None
        if labels is None and navigation.parent is not None and navigation.parent.type == "call_expression" \
                and navigation.parent.children[0] == navigation:
            return  # checked with its labels by check_call
        self.checked_member_nodes.add(navigation.id)
        if target.type == "simple_identifier" and text(target) in self.bindings.types \
                and text(target) not in self.app.values:
            ffi_type = self.bindings.types[text(target)]
            self.check_static_member(navigation, ffi_type, member, labels if is_call else None)
            return
        ffi_type = self.bindings.lookup(self.infer(target))
        if ffi_type is None:
            return
        if not is_call:
            self.used(navigation, f"member {ffi_type.name}.{member}")
        if member in ffi_type.methods:
            if is_call:
                instance = [s for s in ffi_type.methods[member] if not s.static]
                self.check_signature(navigation, f"{ffi_type.name}.{member}", instance or ffi_type.methods[member],
                                     labels)
        elif member in ffi_type.fields:
            if is_call:
                self.report(navigation, f"`{ffi_type.name}.{member}` is a field, not a method")
        else:
            self.report(navigation, f"`{ffi_type.name}` has no member `{member}` in the bindings{self.hint(member)}")

    def check_static_member(self, node: Node, ffi_type: FfiType, member: str, labels) -> None:
        if labels is None:
            self.used(node, f"static member {ffi_type.name}.{member}")
        if member in ffi_type.cases:
            return
        statics = [s for s in ffi_type.methods.get(member, []) if s.static]
        if statics:
            if labels is not None:
                self.check_signature(node, f"{ffi_type.name}.{member}", statics, labels)
            return
        self.report(node, f"`{ffi_type.name}` has no case or static member `{member}` in the bindings"
                          f"{self.hint(member)}")

    def hint(self, member: str) -> str:
        for name in sorted(self.bindings.all_member_names()):
            if name.lower() == member.lower() and name != member:
                return f" (did you mean `{name}`?)"
        return ""

    def check_switch(self, switch: Node) -> None:
        subject = switch.child_by_field_name("expr")
        ffi_type = self.bindings.lookup(self.infer(subject))
        if ffi_type is None or ffi_type.kind != "enum":
            return
        for entry in switch.children:
            if entry.type != "switch_entry":
                continue
            for switch_pattern in entry.children:
                if switch_pattern.type != "switch_pattern":
                    continue
                for pattern in switch_pattern.children:
                    if pattern.type == "pattern":
                        self.check_case_pattern(pattern, ffi_type, entry)

    def check_case_pattern(self, pattern: Node, ffi_type: FfiType, scope: Node) -> None:
        name_node = next((c for c in pattern.children if c.type == "simple_identifier"), None)
        if name_node is None or not preceded_by_dot(self.file.source, name_node):
            return
        self.checked_member_nodes.add(name_node.id)
        case = text(name_node)
        self.used(name_node, f"case {ffi_type.name}.{case}")
        if case not in ffi_type.cases:
            self.report(name_node, f"`{ffi_type.name}` has no case `{case}` in the bindings{self.hint(case)}")
            return
        values = ffi_type.cases[case]
        bindings = [c for c in pattern.children if c.type in ("pattern", "wildcard_pattern")]
        if len(bindings) > len(values):
            self.report(name_node, f"`{ffi_type.name}.{case}` carries {len(values)} value(s), "
                                   f"the pattern binds {len(bindings)}")
            return
        for binding, (_, value_type) in zip(bindings, values):
            bound = binding.child_by_field_name("bound_identifier") or next(
                (c for c in binding.children if c.type == "simple_identifier"), None)
            if bound is not None:
                self.declare(scope, text(bound), value_type)

    def check_catch(self, catch: Node) -> None:
        pattern = catch.child_by_field_name("error")
        if pattern is None:
            return
        parts = pattern.children
        if len(parts) >= 2 and parts[0].type == "user_type" and parts[-1].type == "simple_identifier":
            ffi_type = self.bindings.lookup(type_text(parts[0]))
            if ffi_type is not None:
                self.checked_member_nodes.add(parts[-1].id)
                self.check_static_member(parts[-1], ffi_type, text(parts[-1]), None)

    def check_conformance(self, declaration: Node) -> None:
        body = declaration.child_by_field_name("body")
        if body is None:
            return
        implemented: dict[str, list[tuple[str | None, ...]]] = {}
        for member in body.children:
            if member.type == "function_declaration":
                name = text(member.child_by_field_name("name"))
                implemented.setdefault(name, []).append(tuple(p.label for p in params_of(member)))
        for specifier in declaration.children:
            if specifier.type != "inheritance_specifier":
                continue
            ffi_type = self.bindings.lookup(type_text(specifier.child_by_field_name("inherits_from")))
            if ffi_type is None or ffi_type.kind != "protocol":
                continue
            self.used(specifier, f"conformance to {ffi_type.name}")
            for name, signatures in ffi_type.methods.items():
                wanted = {tuple(p.label for p in s.params) for s in signatures}
                if not wanted & set(implemented.get(name, [])):
                    hint = self.hint_for_requirement(name, implemented)
                    self.report(specifier, f"`{type_name_of(declaration)}` conforms to `{ffi_type.name}` but does not "
                                           f"implement {signatures[0].describe(name)}{hint}")

    @staticmethod
    def hint_for_requirement(name: str, implemented) -> str:
        close = sorted(n for n in implemented if _edit_distance(n.lower(), name.lower()) <= 2)
        return f" (found `{close[0]}`)" if close else ""

    def check_names(self) -> None:
        source = self.file.source
        for node in walk(self.file.root):
            if node.type == "type_identifier":
                parent = node.parent
                if parent is not None and parent.type == "user_type" and parent.children[0] != node:
                    continue  # a nested type such as ARFaceAnchor.BlendShapeLocation
                declares = parent is not None and parent.type in ("class_declaration", "protocol_declaration") \
                    and parent.child_by_field_name("name") == node
                if declares or in_attribute(node):
                    continue
                self.check_root_name(node, text(node))
            elif node.type == "simple_identifier":
                name = text(node)
                if name.startswith("$") or in_attribute(node):
                    continue
                if preceded_by_dot(source, node):
                    self.check_member_spelling(node, name)
                    continue
                parent = node.parent
                if parent is None or parent.type in ("value_argument_label", "navigation_suffix"):
                    continue
                field_name = parent.field_name_for_child(parent.children.index(node))
                if field_name in ("name", "bound_identifier", "external_name") or parent.type in (
                        "pattern", "parameter", "lambda_parameter", "import_declaration", "identifier",
                        "enum_entry", "enum_type_parameters", "tuple_type_item"):
                    continue
                is_call = parent.type == "call_expression" and parent.children[0] == node
                if name[:1].isupper():
                    self.check_root_name(node, name)
                elif is_call and name not in self.app.values and name not in APPLE_FUNCTIONS \
                        and name not in self.bindings.functions:
                    self.report(node, f"unknown function `{name}`: not declared in the app, not in the bindings, "
                                      f"not in APPLE_FUNCTIONS{self.hint(name)}")

    def check_root_name(self, node: Node, name: str) -> None:
        if name in self.app.types or name in self.app.values or name in APPLE_NAMES:
            return
        if name in self.bindings.types or name in self.bindings.functions:
            return
        suggestion = next((t for t in sorted(self.bindings.types) if _edit_distance(t, name) <= 2), None)
        hint = f" (did you mean `{suggestion}`?)" if suggestion else ""
        self.report(node, f"unknown name `{name}`: not declared in the app, not in the bindings, and not in the "
                          f"checker's APPLE_NAMES (add it there if it is Apple's or Swift's){hint}")

    def check_member_spelling(self, node: Node, name: str) -> None:
        if node.id in self.checked_member_nodes:
            return
        parent = node.parent
        if parent is not None and parent.type == "navigation_suffix" and parent.parent is not None \
                and parent.parent.id in self.checked_member_nodes:
            return
        if name in self.app.values or name in self.app.types:
            return
        members = self.bindings.all_member_names()
        if name in members:
            return
        for known in members:
            if known.lower() == name.lower():
                self.report(node, f"`.{name}` is not in the bindings; did you mean `.{known}`?")
                return


def _edit_distance(a: str, b: str) -> int:
    previous = list(range(len(b) + 1))
    for i, char_a in enumerate(a, 1):
        current = [i]
        for j, char_b in enumerate(b, 1):
            current.append(min(previous[j] + 1, current[j - 1] + 1, previous[j - 1] + (char_a != char_b)))
        previous = current
    return previous[-1]


# --------------------------------------------------------------------------
# The rules

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
