"""The app's Swift files as ``swift_checks.py`` reads them: loading, where a
node stands (its scope, its enclosing type, an attribute, after a dot), and
the index of the types and members the app declares itself."""

from __future__ import annotations

from dataclasses import dataclass, field
from pathlib import Path

from tree_sitter import Node

from swift_syntax import SCOPE_TYPES, named_children, parse, text, type_text, walk
from swift_bindings import return_type

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
