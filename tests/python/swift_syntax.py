"""The Swift syntax tree as the checks of ``swift_checks.py`` read it: parsing
with tree-sitter-swift, walking, node text, the scopes names are declared in,
types written as text, and the ``Problem`` every rule reports."""

from __future__ import annotations

import re
from dataclasses import dataclass

import tree_sitter_swift
from tree_sitter import Language, Node, Parser

SWIFT = Language(tree_sitter_swift.language())


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
