"""Discriminate on an object nothing was sensed on: the one value is worth a move
(docs/method.md §5.8, the appearance's grasp chosen without a test, failing).

The four hand-made descriptions (tests/learner/fixtures.py), the robot at (24,90) after
the box's Front-Pinch failed cleanly with nothing measured. The box has two features:
Height(6,*) by D-Scan-0.3 (84 s), reached at (6,90), 18 in away: 36 s + 84 s = 120 s;
Width-Degree-1°(24,0) by H-Sweep-1°, reached at (24,0), a quarter turn round a 24 in
circle, 24 x sqrt(2) = 33.94 in: 67.88 s + 100 s = 167.88 s. The height is driven to,
then sensed; a second wrong prediction on the object adds no second move.
"""

from __future__ import annotations

from py_trees.common import Status

from behaviours.records import GraspAttempt
from behaviours.recovery import Discriminate
from hero_driver.interface import SenseResult
from tests.behaviours.conftest import REGION, ROBOT, P, moved, pose_at, run, setup, start_object, tick


def _failed_with_nothing_sensed(services, grasp: str = "Front-Pinch", at=P(24, 90)):  # noqa: ANN001, ANN202
    record, step = start_object(services)
    record.session.position = at
    record.session.grasp_failed(grasp, side_effects=False)
    step.attempt = GraspAttempt(grasp, at, success=False)
    return record, step


def test_nothing_sensed_the_cheapest_discriminating_test_is_driven_to(services, driver, nav, log) -> None:  # noqa: ANN001
    record, step = _failed_with_nothing_sensed(services)
    there = pose_at(nav, P(6, 90))
    driver.script("move", moved(there, seconds=36.5))
    driver.script("sense", SenseResult("D-Scan-0.3", {"Height": 3.0, "Depth": 2.0, "Top-Hole?": 0.0}, 84.0, 6.0))
    assert run(Discriminate(ROBOT), services) == Status.SUCCESS
    assert driver.verbs() == ["move", "sense"]
    assert driver.calls[0][1] == (there,)  # the fake planner's one-waypoint path to (6,90)
    assert record.ledger.moving_s == 36.5 and record.ledger.sensing_s == 84.0
    assert record.session.position == P(6, 90)
    assert record.session.measurements[("Height", P(6, 90))] == 3.0  # 3 in, outside the box's 9 +- 0.5
    move, sense = [e for e in log.events if e["event"] in ("move", "discriminate")]
    assert move["to"] == [6, 90] and move["seconds"] == 36.5 and not move["collided"]
    assert sense["procedure"] == "D-Scan-0.3" and sense["told_apart"] is True


def test_a_value_had_already_is_not_worth_a_move(services, driver) -> None:  # noqa: ANN001
    record, step = _failed_with_nothing_sensed(services)
    record.session.record({"Width-Degree-1°": 8.0}, P(24, 0))  # the cup's width: the box's is 18
    assert run(Discriminate(ROBOT), services) == Status.SUCCESS
    assert driver.calls == []  # told apart already by the width


def test_one_move_for_a_value_per_object(services, driver) -> None:  # noqa: ANN001
    """The D-Scan gives nothing at (6,90); Top-Pinch (the tumbler) fails next: its own
    features would need another move, which is not made."""
    record, step = _failed_with_nothing_sensed(services)
    driver.script("move", moved(pose_at(services.navigator, P(6, 90)), seconds=36.0))
    driver.script("sense", SenseResult("D-Scan-0.3", {"Height": None, "Depth": None, "Top-Hole?": None}, 84.0, 6.0))
    behaviour = setup(Discriminate(ROBOT), services)
    assert tick(behaviour) == Status.SUCCESS
    assert driver.verbs() == ["move", "sense"]
    record.session.position = P(24, 90)
    record.session.grasp_failed("Top-Pinch", side_effects=False)
    step.attempt = GraspAttempt("Top-Pinch", P(24, 90), success=False)
    assert tick(behaviour) == Status.SUCCESS
    assert driver.verbs() == ["move", "sense"]


def test_a_collided_move_gives_the_value_up(services, driver) -> None:  # noqa: ANN001
    record, step = _failed_with_nothing_sensed(services)
    driver.script("move", moved(pose_at(services.navigator, P(10, 90)), seconds=20.0, collided=True))
    assert run(Discriminate(ROBOT), services) == Status.SUCCESS
    assert driver.verbs() == ["move"] and record.ledger.moving_s == 20.0 and not record.session.measurements


def test_no_path_to_the_value_gives_it_up(services, driver, nav, log) -> None:  # noqa: ANN001
    record, step = _failed_with_nothing_sensed(services)
    nav.block(REGION, P(6, 90))
    assert run(Discriminate(ROBOT), services) == Status.SUCCESS
    assert driver.calls == [] and [e["event"] for e in log.events] == ["no_path"]


def test_an_implausible_discriminating_value_is_an_event_and_not_recorded(services, driver, log) -> None:  # noqa: ANN001
    """A deaf sonar whose driver writes "no echo" as -1: the width sweep's -1 degrees lies
    outside the feature's span [0, 180]. Failed at (24,0), the sweep there (100 s) is
    cheaper than the height at (6,0) (36 s + 84 s). The value is not recorded (a later test would believe
    it), the sweep is not asked again on this object, and the time it took is charged."""
    record, step = _failed_with_nothing_sensed(services, at=P(24, 0))  # where the box's width is swept
    driver.script("sense", SenseResult("H-Sweep-1°", {"Width-Degree-1°": -1.0}, 100.0, 6.0))
    behaviour = setup(Discriminate(ROBOT), services)
    assert tick(behaviour) == Status.SUCCESS
    assert driver.verbs() == ["sense"] and driver.calls[0][1] == "H-Sweep-1°"
    assert record.session.measurements == {} and record.ledger.sensing_s == 100.0
    implausible, discriminate = [e for e in log.events if e["event"] in ("implausible", "discriminate")]
    assert implausible["feature"] == "Width-Degree-1°" and implausible["value"] == -1.0
    assert implausible["why"] == "outside the feature's span [0, 180] deg"
    assert discriminate["implausible"] == ["Width-Degree-1°"] and discriminate["told_apart"] is False
