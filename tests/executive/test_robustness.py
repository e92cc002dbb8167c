"""The executive when the world is unkind: every sonar reading lost, aggressive nearest
neighbour, and the books balanced against the robot's own clock."""

from __future__ import annotations

import json
import tempfile
from pathlib import Path

import pytest

from behaviours.services import Params
from executive.defaults import EXAMPLE_LIBRARY
from executive.executive import Executive
from hero_driver.sim_driver import SimulatedHero
from learner.library.format import read_library_json
from learner.service.local import LocalLearner
from tests.executive.scenarios import DEAF_SONAR, one, run


@pytest.mark.parametrize("params", [Params(), Params(nearest_after=1)], ids=["default", "nearest-after-1"])
def test_a_deaf_sonar_ends_the_object_instead_of_looping(params: Params) -> None:
    scenario = run(one("soda-can-12oz/lying"), 1, params=params, noise=DEAF_SONAR, max_ticks=5000)
    assert scenario.result.status == "SUCCESS"  # the episode ends: no behaviour RUNNING forever
    (obj,) = scenario.result.objects
    assert obj.steps < params.max_steps  # not worn down to the step budget by a livelock
    discriminations = [e for e in scenario.executive.log.events if e["event"] == "discriminate"]
    assert len(discriminations) <= len({e.get("procedure") for e in discriminations}) + 1
    learned = [e for e in scenario.executive.log.events if e["event"] == "learn"]
    # never a description of nothing: with no value sensed, only a lesson (a grasp failed
    # first) is kept, by the camera's appearance (tests/behaviours/test_actions.py)
    assert all(e["id"] is None or e["features"] > 0 or e["wrong"] for e in learned)


@pytest.mark.slow
def test_the_ledger_balances_with_the_robots_clock() -> None:
    """Every robot second the simulator spent is on some object's ledger, once."""
    hero = SimulatedHero("clock", world="lab", seed=3)
    learner = LocalLearner(Path(tempfile.mkdtemp()) / "lib.sqlite", seed_library=read_library_json(EXAMPLE_LIBRARY))
    executive = Executive(hero, learner)
    result = executive.run()
    executive.shutdown()
    booked = sum(o.ledger.robot_s for o in result.objects)
    assert booked == pytest.approx(hero.state().clock_s, abs=1e-6)
    for line in executive.log.events:  # strict JSON throughout (no Infinity for a move with no path)
        json.dumps(line, allow_nan=False)
