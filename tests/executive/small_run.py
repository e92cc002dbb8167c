"""A smaller ``csl experiment paper --quick`` for the tests that read its page.

Those tests check that the page and its CSV hold together (every study's section and
columns, rates that are rates, one row per object of every episode, no policy cheaper
than the optimum), not its numbers: the run's layout is the same with fewer objects on
each floor, the sweeps at their two ends, shorter chains and a smaller optimum search,
at a fraction of the quick run's cost. Every study still runs, in both conditions where
it has two, through the command line and a pool of spawned workers as a user's run does.

:func:`shrink` makes the parent's plan small; the workers lay their floors out with
:func:`few_members` because :func:`install_few_members` is their initializer (a spawned
worker imports this module afresh, so the parent's patches do not reach it).
"""

from __future__ import annotations

import pytest

from experiments import study, worlds
from experiments.config import ExperimentConfig
from experiments.worker import Libraries, install_worker
from learner.position import Position
from robot_profile import RobotProfile

_EVERY_MEMBER = worlds.set_members
EVERY = 3  # every third object of a set: 3 of the 8 unseen, 5 of the 14 of Table 3


def few_members(object_set: str) -> list[str]:
    """Every EVERY-th object of ``object_set`` (its ids are sorted, so the pick spreads
    over boxes, bottles and tumblers)."""
    return _EVERY_MEMBER(object_set)[::EVERY]


def install_few_members(libraries: Libraries, profile: RobotProfile) -> None:
    """The pool's initializer for the small run: the worker's floors hold few_members,
    as the parent's plan expects; then the run's own initializer."""
    worlds.set_members = few_members
    install_worker(libraries, profile)


def shrink(patch: pytest.MonkeyPatch) -> None:
    """Make the next ``csl experiment paper --quick`` run in this process the small one."""
    patch.setattr(worlds, "set_members", few_members)
    patch.setattr(study, "install_worker", install_few_members)
    patch.setattr(ExperimentConfig, "cost_multipliers", property(lambda _config: [0.25, 4.0]))
    patch.setattr(ExperimentConfig, "chain_length", property(lambda _config: 2))
    patch.setattr(ExperimentConfig, "start_poses", property(lambda _config: [Position(24.0, 0.0)]))
    patch.setattr(ExperimentConfig, "shipped_descriptions", property(lambda _config: 8))
    patch.setattr(ExperimentConfig, "synthetic_objects", property(lambda _config: 6))
