"""The episode loop: StartObject ("RememberAppearance"), ForEachObject, UntilHandled."""

from __future__ import annotations

from dataclasses import replace

import py_trees
import pytest
from py_trees.common import Status

from behaviours.base import CslBehaviour
from behaviours.loop import ForEachObject, StartObject, UntilHandled
from behaviours.records import Step
from behaviours.services import Params
from learner.appearance import Appearance
from tests.behaviours.conftest import (REGION, ROBOT, WIDTH, P, four_objects, fresh_board, get, make_services, pose_at,
                                       put, region, run, setup, start_object, tick)


# -- StartObject -----------------------------------------------------------------------------


def test_start_object_opens_a_session_from_where_the_robot_stands(services, nav, log) -> None:  # noqa: ANN001
    fresh_board()
    other = region(30, 40)
    put("objects", [REGION, other])
    put("pose", pose_at(nav, P(60, 90)))  # (100, 110), facing the object
    assert run(StartObject(ROBOT), services) == Status.SUCCESS
    record = get("object")
    assert get("objects") == [other] and get("results") == [record]
    assert (record.index, record.region, record.first_region, record.pixels_before) == (0, REGION, REGION, 200)
    assert record.estimator.region == REGION and record.outcome is None and record.steps == 0
    session = record.session
    assert session.position == P(60, 90) and session.depth == 0 and not session.orientation_free
    assert session.max_alternatives == 3
    assert get("step") == Step() and get("step") is not None
    assert record.ledger.computing_s == 0.25  # two clock readings around opening it
    assert log.events == [{"event": "object", "object": 0, "behaviour": "RememberAppearance",
                           "centroid": [100.0, 50.0], "pixels": 200, "start": [60, 90]}]
    first = session.decide()  # priced from (60,90): 2 s x |(24,0) - (60,90)| = 2 x 64.62 s
    assert str(first.test) == WIDTH and first.move_cost == pytest.approx(2 * (60**2 + 24**2) ** 0.5)


def test_start_object_without_a_move_asks_the_driver_where_it_is(driver) -> None:  # noqa: ANN001
    """The robot at (0,0) is 111.8 in from (100,50), bearing atan2(-50,-100) = 206.6°."""
    services = make_services(driver=driver, params=Params(max_alternatives=2))
    fresh_board()
    put("objects", [region(100, 50, round_=True)])
    assert run(StartObject(ROBOT), services) == Status.SUCCESS
    session = get("object").session
    assert session.position == P(111.8, 206.6)
    assert session.orientation_free and session.max_alternatives == 2


def test_start_object_numbers_objects_in_turn(services) -> None:  # noqa: ANN001
    fresh_board()
    put("objects", [REGION, region(30, 40)])
    behaviour = setup(StartObject(ROBOT), services)
    assert tick(behaviour) == Status.SUCCESS
    first = get("object")
    assert tick(behaviour) == Status.SUCCESS
    second = get("object")
    assert (first.index, second.index) == (0, 1) and get("results") == [first, second]
    assert first.session.matrix is second.session.matrix  # one library matrix per episode


def test_each_object_draws_its_chances_from_the_episode_seed_plus_its_index() -> None:
    """A cost-blind criterion breaks ties at random: object i of an episode with seed s
    draws from seed s + i, so objects differ and a rerun repeats."""
    import numpy as np

    from behaviours.services import Params
    from tests.behaviours.conftest import make_services

    fresh_board()
    put("objects", [REGION, region(30, 40)])
    behaviour = setup(StartObject(ROBOT), make_services(params=Params(seed=7)))
    states = []
    for _ in range(2):
        assert tick(behaviour) == Status.SUCCESS
        states.append(get("object").session.ctx.rng.bit_generator.state)
    assert states == [np.random.default_rng(7).bit_generator.state, np.random.default_rng(8).bit_generator.state]


def test_start_object_fails_when_no_object_is_left(services, log) -> None:  # noqa: ANN001
    fresh_board()
    assert run(StartObject(ROBOT), services) == Status.FAILURE
    assert get("object") is None and log.events == []


# -- ForEachObject ---------------------------------------------------------------------------


def test_for_each_object_loops_while_objects_remain(services) -> None:  # noqa: ANN001
    fresh_board()
    put("objects", [REGION, region(30, 40), region(30, -40)])
    loop = setup(ForEachObject(StartObject(ROBOT), ROBOT), services)
    statuses = []
    for _ in range(5):
        loop.tick_once()
        statuses.append(loop.status)
        if loop.status != Status.RUNNING:
            break
    assert statuses == [Status.RUNNING, Status.RUNNING, Status.SUCCESS]
    assert [r.index for r in get("results")] == [0, 1, 2] and get("objects") == []


def test_for_each_object_goes_on_after_an_object_fails(services) -> None:  # noqa: ANN001
    fresh_board()
    put("objects", [REGION, region(30, 40)])
    child = py_trees.composites.Sequence("per object", memory=True, children=[
        StartObject(ROBOT), py_trees.behaviours.Failure("fails")])
    loop = setup(ForEachObject(child, ROBOT), services)
    assert tick(loop) == Status.SUCCESS
    assert len(get("results")) == 2


def test_for_each_object_waits_for_a_running_child(services) -> None:  # noqa: ANN001
    fresh_board()
    put("objects", [REGION])
    child = py_trees.behaviours.Running("busy")
    loop = ForEachObject(child, ROBOT)
    loop.tick_once()
    assert loop.status == Status.RUNNING and get("objects") == [REGION]


def test_for_each_object_with_nothing_located_succeeds(services) -> None:  # noqa: ANN001
    fresh_board()
    assert run(ForEachObject(StartObject(ROBOT), ROBOT), services) == Status.SUCCESS
    assert get("results") == []


# -- UntilHandled ----------------------------------------------------------------------------


class Probe(CslBehaviour):
    """A recognition step that remembers the Step it was given, marks it, and reports
    ``outcomes`` in turn (a string finishes the object with that outcome)."""

    def __init__(self, *outcomes: Status | str) -> None:
        super().__init__("Probe", ROBOT)
        self.outcomes = list(outcomes)
        self.seen: list[Step] = []
        self.entered_marked: list[bool] = []

    def update(self) -> Status:
        self.seen.append(self.step)
        self.entered_marked.append(self.step.no_alternative)
        self.step.no_alternative = True  # must not leak into the next step
        outcome = self.outcomes.pop(0)
        if isinstance(outcome, str):
            self.obj.finish(outcome, "Front-Wrap" if outcome == "grasped" else None, P(6, 0))
            return Status.SUCCESS
        return outcome


def test_until_handled_replaces_the_step_each_step(services, log) -> None:  # noqa: ANN001
    record, first = start_object(services)
    probe = Probe(Status.FAILURE, Status.FAILURE, "grasped")
    assert run(UntilHandled(probe, ROBOT), services) == Status.SUCCESS
    assert probe.seen[0] is first and len({id(s) for s in probe.seen}) == 3
    assert probe.entered_marked == [False, False, False]  # nothing leaks from the step before
    assert record.steps == 3 and record.outcome == "grasped" and log.events == []
    assert get("step") is probe.seen[-1]  # the handled step is kept for reading


def test_until_handled_gives_up_at_max_steps(log) -> None:  # noqa: ANN001
    services = make_services(params=Params(max_steps=3))
    record, _ = start_object(services)
    probe = Probe(Status.FAILURE, Status.FAILURE, Status.FAILURE, Status.FAILURE)
    assert run(UntilHandled(probe, ROBOT), services) == Status.FAILURE
    assert len(probe.seen) == 3 and record.steps == 3 and record.outcome == "failed"
    assert services.log.events == [{"event": "gave_up", "object": 0, "behaviour": "UntilHandled", "reason": "3 steps"}]


def test_until_handled_fails_an_object_given_up_on(services, log) -> None:  # noqa: ANN001
    record, _ = start_object(services)
    assert run(UntilHandled(Probe("failed"), ROBOT), services) == Status.FAILURE
    assert record.outcome == "failed" and record.steps == 1 and log.events == []


def test_until_handled_succeeds_for_an_object_left_where_it_is(services) -> None:  # noqa: ANN001
    record, _ = start_object(services)
    assert run(UntilHandled(Probe("left"), ROBOT), services) == Status.SUCCESS


def test_until_handled_waits_for_a_running_step(services) -> None:  # noqa: ANN001
    record, first = start_object(services)
    until = setup(UntilHandled(Probe(Status.RUNNING, Status.RUNNING, "grasped"), ROBOT), services)
    until.tick_once()
    until.tick_once()
    assert until.status == Status.RUNNING and record.steps == 0 and get("step") is first
    assert tick(until) == Status.SUCCESS and record.steps == 1


def test_until_handled_needs_its_services(services) -> None:  # noqa: ANN001
    start_object(services)
    with pytest.raises((RuntimeError, AssertionError), match="ticked before setup"):
        UntilHandled(py_trees.behaviours.Failure("step"), ROBOT).tick_once()


def test_until_handled_ticked_without_setup_raises_runtime_error(services) -> None:  # noqa: ANN001
    start_object(services)
    with pytest.raises(RuntimeError, match="ticked before setup"):
        UntilHandled(py_trees.behaviours.Failure("step"), ROBOT).tick_once()


def test_until_handled_setup_without_services_raises_a_clear_error() -> None:
    with pytest.raises(RuntimeError, match="needs services"):
        UntilHandled(py_trees.behaviours.Failure("step"), ROBOT).setup()


SEEING = Params()  # the appearance is on by default


def test_the_appearance_is_on_by_default() -> None:
    assert Params().use_appearance


def test_start_object_hands_the_camera_appearance_to_the_session() -> None:
    """The region measured 13.44 in^2 at elongation 2.333 (6.32 x 2.71 in): the cup recorded
    round at 8.32 in^2 (3.25 in across, 3.07 in off on the major axis) is ruled out for free;
    descriptions recorded without an appearance stay."""
    library = four_objects()
    library[0] = replace(library[0], appearance=Appearance(True, 8.32, 1.0))
    services = make_services(descriptions=library, params=SEEING)
    fresh_board()
    put("objects", [replace(REGION, area_in2=13.44, elongation=2.333)])
    assert run(StartObject(ROBOT), services) == Status.SUCCESS
    session = get("object").session
    assert session.appearance == Appearance(False, 13.44, 2.333)
    assert session.candidates == ("box", "closed", "tumbler")
    (event,) = services.log.events
    assert event["appearance"] == {"round": False, "area_in2": 13.44, "elongation": 2.333}
    assert event["ruled_out"] == 1 and "appearance_ignored" not in event


def test_a_region_drawn_without_pixel_measures_has_no_appearance() -> None:
    fresh_board()
    put("objects", [REGION])
    assert run(StartObject(ROBOT), make_services(params=SEEING)) == Status.SUCCESS
    assert get("object").session.appearance is None


def test_without_the_switch_the_appearance_is_kept_but_rules_nothing_out() -> None:
    library = four_objects()
    library[0] = replace(library[0], appearance=Appearance(True, 8.32, 1.0))
    services = make_services(descriptions=library, params=Params(use_appearance=False))  # --no-appearance
    fresh_board()
    put("objects", [replace(REGION, area_in2=13.44, elongation=2.333)])
    assert run(StartObject(ROBOT), services) == Status.SUCCESS
    session = get("object").session
    assert session.appearance == Appearance(False, 13.44, 2.333) and not session.use_appearance
    assert session.candidates == ("box", "closed", "cup", "tumbler")
    (event,) = services.log.events
    assert "appearance" not in event and "ruled_out" not in event
