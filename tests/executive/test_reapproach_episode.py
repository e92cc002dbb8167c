"""A refusal for range is not a failed grasp, a whole episode in the simulator
(docs/executive.md, "A refusal for range is not a failed verb"): on a floor of the
unseen test objects at 3x the `paper` noise, the drift of single moves leaves the robot
more than the range tolerance off a grasp position although the camera corrects it
before every verb. Counting those refusals as failed grasps (``reapproach_tries`` 0,
the old way) drops a right grasp and leaves an object wrong; re-approaching handles all
eight."""

from __future__ import annotations

from functools import cache
from pathlib import Path

from behaviours.services import Params
from executive.executive import Executive
from executive.experiment.conditions import noise_config
from executive.experiment.episodes import play_and_judge
from executive.experiment.study_training import run_training
from executive.experiment.worlds import write_floor
from executive.report import rows
from hero_driver.interface import OUT_OF_RANGE
from hero_driver.sim_driver import SimulatedHero
from learner.description import ObjectDescription
from learner.service.local import LocalLearner
from robot_profile import load_profile

FLOOR_SEED = 13_000  # the floor of the experiment's seed 13; measured: 9 refusals the old way, 1 re-approaching


@cache
def trained() -> tuple[ObjectDescription, ...]:
    return tuple(run_training(load_profile()).descriptions)


def episode(tmp_path: Path, tries: int) -> tuple[list[dict[str, object]], list[bool]]:
    """The floor's events and, per record, whether its object was handled right."""
    folder = tmp_path / f"tries-{tries}"
    folder.mkdir()
    world = write_floor(folder, "test", FLOOR_SEED)
    hero = SimulatedHero("r1", world=world, seed=FLOOR_SEED, noise=noise_config("paper", 3.0))
    learner = LocalLearner(folder / "library.sqlite", seed_library=list(trained()))
    executive = Executive(hero, learner, params=Params(reapproach_tries=tries))
    try:
        result, truths = play_and_judge(hero, executive)
    finally:
        learner.close()
    return list(executive.log.events), [bool(r.correct) for r in rows(result.objects, truths)]


def refusals(events: list[dict[str, object]]) -> list[int]:
    """The index of every event that is a refusal for range."""
    return [i for i, e in enumerate(events) if e["event"] == "driver_error" and e.get("code") == OUT_OF_RANGE]


def test_a_grasp_refused_for_range_is_re_approached_not_dropped(tmp_path: Path) -> None:
    old_events, old = episode(tmp_path, tries=0)
    new_events, new = episode(tmp_path, tries=2)
    # the old way: the refused grasps dropped one by one (measured: 9 refusals, 7 of 8 right)
    assert len(refusals(old_events)) >= 5 and sum(old) < len(old)
    assert not any(e["event"] == "reapproach" for e in old_events)
    # re-approaching: each refusal is followed by its re-approach, and no grasp is dropped
    # for one (the next drop_grasp of that object follows a grasp that was tried and slipped)
    assert 1 <= len(refusals(new_events)) < len(refusals(old_events))
    for i in refusals(new_events):
        assert new_events[i + 1]["event"] == "reapproach"
        assert new_events[i + 1]["object"] == new_events[i]["object"]
    assert sum(new) == len(new) == 8
