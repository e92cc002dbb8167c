"""The behaviour tree's status as py_trees displays it, for a terminal (``--show-status``)
and for a recording (no colour codes there). No Foxglove import."""

from __future__ import annotations

import re

import py_trees

_ANSI = re.compile(r"\x1b\[[0-9;]*m")


def status_tree(root: py_trees.behaviour.Behaviour, *, colour: bool = False) -> str:
    """py_trees' unicode tree with every behaviour's status and feedback message.

    py_trees colours the status marks when its stdout was a terminal at import; a pipe,
    a file or a recording gets them removed here."""
    text = py_trees.display.unicode_tree(root, show_status=True)
    return text if colour else _ANSI.sub("", text)
