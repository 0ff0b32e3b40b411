"""The ``ffi`` rule of ``swift_checks.py``: every name the app takes from the
core exists, spelled so, in the bindings (the rule is described there), with
the Apple and Swift names the app may use besides the core's."""

from __future__ import annotations

from tree_sitter import Node

from swift_syntax import Problem, SCOPE_TYPES, element_type, named_children, problem_at, strip_optional, text, type_text, walk
from swift_bindings import Bindings, FfiType, Signature, params_of
from swift_app import AppIndex, SwiftFile, enclosing_type, in_attribute, preceded_by_dot, scope_of, type_name_of

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
    NSCondition NSLock NSLocalizedDescriptionKey NSNumber NSObject NSString
    Notification NotificationCenter ProcessInfo Thread URL UUID UTType

    ARAnchor ARConfiguration ARError ARFaceAnchor ARFaceGeometry
    ARFaceTrackingConfiguration ARFrame ARSCNFaceGeometry ARSCNView
    ARSCNViewDelegate ARSession ARSessionDelegate ARSessionObserver ARKit
    ARTrackable

    SCNCamera SCNGeometry SCNGeometryElement SCNGeometrySource SCNLight
    SCNMaterial SCNMorpher SCNNode SCNScene SCNSceneRenderer SCNTransaction SCNMatrix4MakeTranslation SCNVector3
    SCNView SceneKit

    CGFloat CGPoint CGRect CGSize UIActivityViewController UIApplication
    UIBackgroundTaskIdentifier UIColor UIView UIViewController
    UIViewControllerRepresentable UIViewRepresentable UIKit

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
