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
