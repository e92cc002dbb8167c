"""Dead reckoning corrected by the overhead camera, a whole episode in the simulator
(docs/executive.md, "Where the robot is"): on a floor of the experiment's noisy
execution episodes where the `paper` preset's drift grows past the 6 in procedures'
range tolerance, the driver refuses procedures for range when the executive trusts its
dead reckoning, and none when the camera corrects it: all eight objects are then
handled right, one fewer without. Without the camera a refused procedure is not
re-approached (the same plan from the same believed pose would end where the robot
stands): the refusal counts as the verb failing."""

from __future__ import annotations

from functools import cache
from pathlib import Path

from behaviours.services import Params
from executive.executive import Executive
from executive.experiment.conditions import EXECUTION_NOISE, noise_config
from executive.experiment.study_training import run_training
from executive.experiment.episodes import play_and_judge
from executive.experiment.worlds import write_floor
from executive.report import rows
from hero_driver.interface import OUT_OF_RANGE
from hero_driver.sim_driver import SimulatedHero
from learner.description import ObjectDescription
from learner.service.local import LocalLearner
from robot_profile import load_profile

FLOOR_SEED = 24_000  # the experiment's floor of seed 24: drift past 1.5 in, one object lost trusting it


@cache
def trained() -> tuple[ObjectDescription, ...]:
    return tuple(run_training(load_profile()).descriptions)


def episode(tmp_path: Path, localise: bool) -> tuple[list[dict[str, object]], list[bool]]:
    """The floor's events and, per record, whether its object was handled right."""
    folder = tmp_path / ("on" if localise else "off")
    folder.mkdir()
    world = write_floor(folder, "test", FLOOR_SEED)
    hero = SimulatedHero("r1", world=world, seed=FLOOR_SEED, noise=noise_config(EXECUTION_NOISE))
    learner = LocalLearner(folder / "library.sqlite", seed_library=list(trained()))
    executive = Executive(hero, learner, params=Params(localise=localise))
    try:
        result, truths = play_and_judge(hero, executive)
    finally:
        learner.close()
    return list(executive.log.events), [bool(r.correct) for r in rows(result.objects, truths)]


def refused_for_range(events: list[dict[str, object]]) -> int:
    return sum(e["event"] == "driver_error" and e.get("code") == OUT_OF_RANGE for e in events)


def test_the_camera_keeps_the_robot_within_the_procedures_range(tmp_path: Path) -> None:
    trusting, before = episode(tmp_path, localise=False)
    corrected, after = episode(tmp_path, localise=True)
    # measured 9 (the robot more than 1.5 in off the 6 in it meant to stand at); the count
    # moves with the recoveries, which try more or fewer grasps there
    assert refused_for_range(trusting) >= 5
    assert refused_for_range(corrected) == 0
    assert any(e["event"] == "localised" for e in corrected)
    assert sum(after) == len(after) == 8 and sum(before) < 8  # measured: 7 of 8 handled right trusting it
    assert not any(e["event"] == "reapproach" for e in trusting)  # nothing corrected the pose it would plan from

