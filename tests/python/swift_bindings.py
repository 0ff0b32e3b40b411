"""The public surface of the UniFFI-generated Swift bindings of the core, read
for ``swift_checks.py``: types with their methods, initializers, fields and
enum cases, and free functions; UniFFI's plumbing left out."""

from __future__ import annotations

import re
from dataclasses import dataclass, field
from pathlib import Path

from tree_sitter import Node

from swift_syntax import named_children, parse, strip_optional, text, type_text, walk

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
