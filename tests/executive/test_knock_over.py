"""A grasp tried as a feature knocks the object over (docs/method.md §5.8, "A grasp that
knocks the object over").

The simulator, noise off, one upright 16 oz tumbler at (60,60) and the library trained
in the simulator (study 1: 14 descriptions, each with its camera appearance). The
tumbler looks 4.14 in across from above; within the camera's 1.6 in per axis that
leaves six candidates: cup-8oz (3.25 in), soda-can-12oz and tennis-can upright
(2.71 in), all three Front-Wrap; tumbler-16oz and tumbler-32oz upright (4.14 in,
Top-Pinch); tumbler-16oz lying (4.51 in, Front-Pinch). Front-Wrap(6,*) halves them
(gain 1 bit for 42.2 s of moving and its 90 s as a feature), so it is tried first. In
the simulator it pushes the tumbler 2.57 in, is tried again (a push may be why it
failed), and knocks it over: the camera now sees 29 pixels, 18.56 in² (29 x 0.64) of
elongation 1.215, the ellipse 5.36 x 4.41 in.

What the fix does: the knocked-over object is known by that new footprint, not by
none. It leaves tumbler-16oz lying (4.51 in: 0.85 and 0.10 off) and open-box upright
facing sideways (6.32 x 4.51: 0.96 and 0.10 off), both Front-Pinch, and tumbler-16oz
and tumbler-32oz upright (1.22 and 0.27 off), Top-Pinch; cup-8oz (2.11 off) and the
rest go. Front-Pinch(6,*) halves the four (gain 1 bit), is tried as a feature and
holds: no sweep is paid on the lying tumbler, and since nothing was measured on it,
nothing is learned. Before the fix the new object had no appearance at all: the whole
library came back, a 45 s H-Sweep was paid at (6,271), and the lying tumbler was
saved with that width and no appearance, a description every later object, upright
tumblers included, matched.

What is not fixed (the strict xfail below): the upright tumbler was never grasped,
so nothing is learned about it, and the next encounter knocks it over again.
"""

from __future__ import annotations

import json
from collections.abc import Iterator
from pathlib import Path

import py_trees
import pytest

from behaviours.records import GraspAttempt
from behaviours.recovery import CheckSideEffects, StartOver
from behaviours.services import Params
from executive.executive import Executive
from experiments.conditions import noise_config
from experiments.floor import play
from hero_driver.sim_driver import SimulatedHero
from learner.appearance import Appearance
from learner.choosing.criteria import DEFAULT_CRITERION, criterion
from learner.service.local import LocalLearner
from planner import Region
from robot_profile.reader import load_profile
from tests.behaviours.conftest import ROBOT, P, image, make_services, region, run, start_object
from tests.executive.floors import trained

FLOOR = {"name": "one upright tumbler", "room": {"width_in": 120, "depth_in": 120}, "furniture": [],
         "robot": {"x_in": 60.0, "y_in": 30.0, "heading_deg": 90.0},
         "objects": [{"id": "tumbler-16oz/upright", "x_in": 60.0, "y_in": 60.0, "yaw_deg": 0.0}]}
KEPT = ("choose", "grasp", "side_effect", "start_over", "sense", "learn")


def _encounter(tmp_path: Path, learner: LocalLearner, seed: int) -> list[dict[str, object]]:
    world = tmp_path / f"floor-{seed}.json"
    world.write_text(json.dumps(FLOOR), encoding="utf-8")
    profile = load_profile()
    hero = SimulatedHero("knock-over", world=world, seed=seed, profile=profile, noise=noise_config("off"))
    executive = Executive(hero, learner, profile=profile, params=Params(), criterion=criterion(DEFAULT_CRITERION))
    play(hero, executive)
    return [e for e in executive.log.events if e["event"] in KEPT]


def _what(events: list[dict[str, object]]) -> list[tuple[object, ...]]:
    out: list[tuple[object, ...]] = []
    for e in events:
        kind = e["event"]
        if kind == "choose":
            out.append((kind, e["test"]))
        elif kind == "grasp":
            out.append((kind, e["grasp"], e["as_feature"], e["success"]))
        elif kind == "side_effect":
            out.append((kind, e["effect"]))
        elif kind == "sense":
            out.append((kind, e["procedure"]))
        else:
            out.append((kind,))
    return out


@pytest.fixture
def learner(tmp_path: Path):  # noqa: ANN201
    service = LocalLearner(tmp_path / "library.sqlite", seed_library=list(trained()))
    yield service
    service.close()


def test_the_knocked_over_tumbler_is_known_by_its_new_footprint(tmp_path: Path, learner: LocalLearner) -> None:
    events = _encounter(tmp_path, learner, seed=0)
    assert _what(events) == [
        ("choose", "Front-Wrap(6,*)"), ("grasp", "Front-Wrap", True, False), ("side_effect", "pushed"), ("start_over",),
        ("choose", "Front-Wrap(6,*)"), ("grasp", "Front-Wrap", True, False), ("side_effect", "changed"),
        ("start_over",),
        ("choose", "Front-Pinch(6,*)"), ("grasp", "Front-Pinch", True, True), ("learn",)]
    choose_after = [e for e in events if e["event"] == "choose"][2]
    assert choose_after["gain"] == 1.0  # four candidates, two Front-Pinch and two Top-Pinch
    assert [e for e in events if e["event"] == "side_effect"][1]["pixels"] == 29
    assert sum(e["seconds"] for e in events if e["event"] == "grasp") == 60.0 + 60.0 + 45.0  # and no sensing
    learn = events[-1]
    assert learn["id"] is None and learn["reason"] == "nothing was measured and no grasp failed: nothing to learn"
    assert len(learner.library().descriptions) == 14  # nothing saved without its appearance


@pytest.mark.xfail(strict=True, reason="the upright tumbler is never grasped, so nothing about it is learned "
                                       "(docs/method.md §5.8, a grasp that knocks the object over)")
def test_the_next_upright_tumbler_is_not_knocked_over_again(tmp_path: Path, learner: LocalLearner) -> None:
    first = _encounter(tmp_path, learner, seed=0)
    assert ("side_effect", "changed") in _what(first)
    second = _encounter(tmp_path, learner, seed=1)
    assert ("side_effect", "changed") not in _what(second)


# -- the two behaviours alone (the fakes of tests/behaviours: the object at (100,50), 200 pixels)

LYING = Region(((96.0, 48.0), (104.0, 48.0), (104.0, 52.0), (96.0, 52.0)), (101.0, 51.0), 300, 0.0, False,
               8.0, 4.0, area_in2=24.0, elongation=2.0)  # 50% more pixels, 1.4 in off: changed


@pytest.fixture
def board() -> Iterator[None]:
    py_trees.blackboard.Blackboard.clear()
    yield
    py_trees.blackboard.Blackboard.clear()


def _knocked(seen: tuple[Region, ...]):  # noqa: ANN202
    services = make_services()
    record, step = start_object(services)
    record.session.appearance = Appearance(False, 16.0, 1.0)  # as the camera first saw it
    record.session.record({"Width-Degree-1°": 18.0}, P(24, 0))
    step.attempt = GraspAttempt("Front-Pinch", P(6, 0), success=False)
    services.driver.script("camera", image())  # type: ignore[attr-defined]
    services.navigator.see(*seen)  # type: ignore[attr-defined]
    assert run(CheckSideEffects(ROBOT), services) == py_trees.common.Status.SUCCESS
    assert step.side_effect == "changed"
    assert run(StartOver(ROBOT), services) == py_trees.common.Status.SUCCESS
    return record


@pytest.mark.usefixtures("board")
def test_a_changed_object_starts_over_with_the_footprint_seen_after_the_grasp() -> None:
    record = _knocked((LYING,))
    assert record.session.appearance == Appearance(False, 24.0, 2.0)  # the new one, not the first
    assert record.session.measurements == {}  # the width was the original's


@pytest.mark.usefixtures("board")
def test_a_lost_object_starts_over_with_no_footprint() -> None:
    record = _knocked((region(120, 50),))  # 20 in away: not it
    assert record.session.appearance is None and record.session.measurements == {}
