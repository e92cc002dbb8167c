"""The behaviour tree on its own, for ``csl bt`` and the shape snapshot.

Built around the in-process simulator and a throw-away library: constructing the tree
only wires services into behaviours, nothing is ticked.
"""

from __future__ import annotations

import tempfile
from pathlib import Path

import py_trees

from behaviours.context import Params
from executive import defaults
from executive.executive import Executive
from hero_driver.sim_driver import SimulatedHero
from learner.knowledge import load_knowledge
from learner.service.local import LocalLearner


def shape_tree(params: Params = Params()) -> py_trees.behaviour.Behaviour:
    """The executive's tree, as every episode builds it."""
    with tempfile.TemporaryDirectory() as tmp:
        learner = LocalLearner(Path(tmp) / "library.sqlite")
        executive = Executive(SimulatedHero("bt"), learner, load_knowledge(defaults.KNOWLEDGE),
                              profile=defaults.KNOWLEDGE, params=params)
        learner.close()
    return executive.root


def outline(root: py_trees.behaviour.Behaviour) -> str:
    """The tree drawn with box-drawing connectors, each node with py_trees' symbol for
    its kind ({-} sequence, {o} selector, -^- decorator, --> behaviour)."""
    symbols = py_trees.display.unicode_symbols
    lines = [f"{_symbol(root, symbols)} {root.name}"]

    def walk(node: py_trees.behaviour.Behaviour, prefix: str) -> None:
        for i, child in enumerate(node.children):
            last = i == len(node.children) - 1
            lines.append(f"{prefix}{'└── ' if last else '├── '}{_symbol(child, symbols)} {child.name}")
            walk(child, prefix + ("    " if last else "│   "))

    walk(root, "")
    return "\n".join(lines) + "\n"


def _symbol(node: py_trees.behaviour.Behaviour, symbols: dict) -> str:
    memory = getattr(node, "memory", False)
    if isinstance(node, py_trees.composites.Sequence):
        return symbols["sequence_with_memory" if memory else "sequence_without_memory"]
    if isinstance(node, py_trees.composites.Selector):
        return symbols["selector_with_memory" if memory else "selector_without_memory"]
    if isinstance(node, py_trees.decorators.Decorator):
        return symbols["decorator"]
    return symbols["behaviour"]
