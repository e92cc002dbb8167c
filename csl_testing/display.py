"""A behaviour tree's shape as text, for a snapshot that fails when a branch is added,
removed or moved."""

from __future__ import annotations

import re

import py_trees

from executive.behaviour_tree import build_tree

_ESCAPE = re.compile(r"\x1b\[[0-9;]*m")


def tree_display(root: py_trees.behaviour.Behaviour | None = None, robot: str = "r1") -> str:
    """``py_trees.display.unicode_tree`` of ``root`` (None: the executive's tree for
    ``robot``), without colour codes: py_trees colours its text when stdout is a
    terminal, and a snapshot must not depend on where pytest runs."""
    tree = build_tree(robot) if root is None else root
    return _ESCAPE.sub("", py_trees.display.unicode_tree(tree))
