"""Snapshot tests of the executive's behaviour tree, worlds and libraries (docs/snapshot-testing.md).

``Scenario`` (or ``one_object``) describes an episode by keyword arguments, ``run()``
plays it on the seeded simulator and returns a ``ScenarioResult`` whose
``transcript()`` a snapshot pins; ``tree_display`` gives a tree's shape as text. The
pytest plugin (:mod:`csl_testing.plugin`, loaded by its entry point) provides the
``csl_scenario`` and ``csl_snapshot`` fixtures.

The names are loaded on first use: the plugin is imported by every pytest run in an
environment where this package is installed, and should not make those runs import
the simulator, the planner and OMPL.
"""

from __future__ import annotations

from importlib import import_module
from typing import TYPE_CHECKING

if TYPE_CHECKING:
    from behaviours.services import Params
    from csl_testing.display import tree_display
    from csl_testing.inputs import BARE_ROOM, STEADY_NOISE, ObjectEntry
    from csl_testing.scenario import (DriverFactory, Scenario, ScenarioFactory, ScenarioResult, one_object,
                                      simulated_hero)
    from csl_testing.transcript import encounters

_HOMES = {
    "Params": "behaviours.services",  # a Scenario's ``params``: the executive's settings
    "tree_display": "csl_testing.display",
    "BARE_ROOM": "csl_testing.inputs", "STEADY_NOISE": "csl_testing.inputs", "ObjectEntry": "csl_testing.inputs",
    "DriverFactory": "csl_testing.scenario", "Scenario": "csl_testing.scenario",
    "ScenarioFactory": "csl_testing.scenario",
    "ScenarioResult": "csl_testing.scenario", "one_object": "csl_testing.scenario",
    "simulated_hero": "csl_testing.scenario",
    "encounters": "csl_testing.transcript",
}

__all__ = sorted(_HOMES)


def __getattr__(name: str) -> object:
    home = _HOMES.get(name)
    if home is None:
        raise AttributeError(f"module 'csl_testing' has no attribute {name!r}")
    return getattr(import_module(home), name)
