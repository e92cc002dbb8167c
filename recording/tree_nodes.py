"""The behaviour tree as data: every node of one tick with a stable id, its parent, kind,
status and feedback, and the blackboard keys that changed since the tick before, for the
``/behaviour_tree/nodes`` channel (docs/recording.md). The text channel
(``/behaviour_tree/status``) shows the tree to a person; this one lets a tool draw it,
colour it by status and follow the blackboard. No Foxglove import.

A node's id is its place in a depth-first walk from the root (the root 0, each node
before its children, children in order), never py_trees' uuid: one node has one id in
every tick and every run of the same tree. (A path of names would name each ancestor again
in every node and its parent, and the tree is sent whole every tick.)
"""

from __future__ import annotations

import dataclasses
import enum
import json
import math
import numbers
from collections.abc import Iterator, Mapping
from typing import Any

import py_trees

MAX_DEPTH = 5
"""Containers deeper than this in a blackboard value are named, not walked: a record's
region polygon is walked to its points (depth 4 under the ``objects`` list); the learner's
trees inside a recognition session are not copied into every message."""
MAX_ITEMS = 64
"""Items of a list shown before the rest are counted instead (a region's outline, a path)."""

STATUSES = tuple(status.value for status in py_trees.common.Status)
FAMILIES = ("Sequence", "Selector", "Parallel", "Composite", "Decorator", "Action")

SCHEMA: dict[str, Any] = {
    "title": "csl.BehaviourTreeNodes", "type": "object",
    "description": "One tick of the behaviour tree: every node (depth first, the root first) and the "
                   "blackboard keys that changed since the tick before (every key at the first tick).",
    "properties": {
        "tick": {"type": "integer", "minimum": 1},
        "nodes": {"type": "array", "minItems": 1, "items": {
            "type": "object",
            "properties": {
                "id": {"type": "integer", "minimum": 0,
                       "description": "the node's place in a depth-first walk: the root 0, each node before its "
                                      "children; nodes[i] has id i"},
                "parent": {"type": ["integer", "null"], "minimum": 0,
                           "description": "the parent's id; null for the root"},
                "name": {"type": "string"},
                "kind": {"type": "string", "description": "the node's class (py_trees' or the executive's)"},
                "family": {"enum": list(FAMILIES), "description": "what py_trees makes of it (Action: a leaf)"},
                "status": {"enum": list(STATUSES)},
                "feedback": {"type": "string", "description": "the node's feedback message"}},
            "required": ["id", "parent", "name", "kind", "family", "status", "feedback"],
            "additionalProperties": False}},
        "blackboard": {"type": "array", "items": {
            "type": "object",
            "properties": {
                "key": {"type": "string", "description": "the key's absolute name, e.g. /csl/r1/step"},
                "value": {"description": "the value as JSON: a dataclass as an object of its fields, a set as "
                                         "a sorted list, what JSON has no form for as '<ClassName>'"},
                "removed": {"type": "boolean", "description": "true when the key is gone (value null)"}},
            "required": ["key", "value"], "additionalProperties": False}}},
    "required": ["tick", "nodes", "blackboard"], "additionalProperties": False}


def family(node: py_trees.behaviour.Behaviour) -> str:
    """What py_trees makes of ``node``, whatever our class is called."""
    for kind in (py_trees.composites.Sequence, py_trees.composites.Selector, py_trees.composites.Parallel,
                 py_trees.composites.Composite, py_trees.decorators.Decorator):
        if isinstance(node, kind):
            return kind.__name__
    return "Action"


def walk(root: py_trees.behaviour.Behaviour) -> Iterator[tuple[int, int | None, py_trees.behaviour.Behaviour]]:
    """Every node depth first, the root first, with its id and its parent's id."""
    stack: list[tuple[int | None, py_trees.behaviour.Behaviour]] = [(None, root)]
    node_id = 0
    while stack:
        parent, node = stack.pop()
        yield node_id, parent, node
        stack.extend((node_id, child) for child in reversed(node.children))
        node_id += 1


def tree_nodes(root: py_trees.behaviour.Behaviour) -> list[dict[str, Any]]:
    """The nodes of the tree under ``root`` as the schema's ``nodes``."""
    return [{"id": node_id, "parent": parent, "name": node.name, "kind": type(node).__name__,
             "family": family(node), "status": node.status.value, "feedback": node.feedback_message}
            for node_id, parent, node in walk(root)]


def json_value(value: object, depth: int = 0) -> Any:
    """``value`` as JSON can hold it, the same for equal values in every run: no
    addresses or ids (an object JSON has no form for is ``<ClassName>``), sets sorted,
    numbers JSON cannot write (NaN, infinities) as text."""
    if value is None or isinstance(value, (bool, str)):
        return value
    if isinstance(value, enum.Enum):
        return json_value(value.value, depth)
    if isinstance(value, numbers.Integral):
        return int(value)
    if isinstance(value, numbers.Real):
        number = float(value)
        return number if math.isfinite(number) else str(number)
    name = f"<{type(value).__name__}>"
    if depth >= MAX_DEPTH:
        return name
    if dataclasses.is_dataclass(value) and not isinstance(value, type):
        return {f.name: json_value(getattr(value, f.name), depth + 1) for f in dataclasses.fields(value) if f.repr}
    if isinstance(value, Mapping):
        return {k if isinstance(k, str) else json.dumps(json_value(k, depth + 1)): json_value(v, depth + 1)
                for k, v in value.items()}
    if isinstance(value, (set, frozenset)):
        items = sorted((json_value(item, depth + 1) for item in value), key=_text)
    elif isinstance(value, (list, tuple)):
        items = [json_value(item, depth + 1) for item in value[:MAX_ITEMS]]
    else:
        return name
    if len(value) > MAX_ITEMS:
        items = items[:MAX_ITEMS] + [f"... {len(value) - MAX_ITEMS} more"]
    return items


def _text(rendered: Any) -> str:
    return json.dumps(rendered, sort_keys=True, ensure_ascii=False, allow_nan=False)


class BlackboardChanges:
    """What changed on py_trees' blackboard since it was last asked, by comparing each
    key's JSON form: a value replaced and a value changed in place (a record's outcome
    set) are both seen; a value written again unchanged is not."""

    def __init__(self, prefix: str = "") -> None:
        """``prefix``: only keys under it (one robot's namespace, ``/csl/r1/``); all when empty."""
        self.prefix = prefix
        self._last: dict[str, str] = {}

    def since_last(self) -> list[dict[str, Any]]:
        """The keys that changed (all of them the first time), in key order."""
        now = {key: json_value(value) for key, value in list(py_trees.blackboard.Blackboard.storage.items())
               if key.startswith(self.prefix)}
        texts = {key: _text(value) for key, value in now.items()}
        changed: list[dict[str, Any]] = [{"key": key, "value": now[key]} for key in sorted(now)
                                         if self._last.get(key) != texts[key]]
        changed += [{"key": key, "value": None, "removed": True} for key in sorted(set(self._last) - set(now))]
        changed.sort(key=lambda entry: entry["key"])
        self._last = texts
        return changed


def tree_message(tick: int, root: py_trees.behaviour.Behaviour, blackboard: BlackboardChanges) -> dict[str, Any]:
    """One tick for the ``/behaviour_tree/nodes`` channel."""
    return {"tick": tick, "nodes": tree_nodes(root), "blackboard": blackboard.since_last()}
