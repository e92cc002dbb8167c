"""A long move driven in legs with a look after each (behaviours.legs): MoveTo on the
fake driver behind the real localisation decorator, with a perception whose legs are
20 in and whose look places the robot where the test says.

The FakeNavigator's geometry (conftest): position (60,0) of the object at (100, 50) is
the pose (160, 50, 180); (24,0) is (124, 50, 180), 36 in farther along the x axis.
"""

from __future__ import annotations

import dataclasses
from typing import Any

from py_trees.common import Status

from behaviours.actions import MoveTo
from behaviours.legs import first_leg, split_leg
from behaviours.localisation import CameraLocalised
from behaviours.services import Services
from hero_driver.interface import Pose as DriverPose  # noqa: I001 (the planner has a Pose too)
from planner import PlanResult, Pose, Scene
from tests.behaviours.conftest import (ROBOT, CountedLooks, FakeDriver, P, blank_scene, get, make_services, moved,
                                       pose_at, put, run, start_object)


class Scans(CountedLooks):
    """A perception whose looks place the robot at the poses it is given, in turn."""

    verb = "scan"
    corrects_heading = True
    stranded = None

    def __init__(self, leg_in: float | None, *seen: Pose, ahead: tuple[float | None, ...] = ()) -> None:
        super().__init__()
        self.leg_in = leg_in
        self.seen = list(seen)
        self.ahead = list(ahead)  # what each look measures straight ahead, in turn (none: nothing measured)
        self.measures_ahead = bool(ahead)

    def scene(self, observation: Any) -> Scene:
        return blank_scene(self.seen.pop(0))

    glance = scene

    def distance_ahead(self, observation: Any) -> float | None:
        return self.ahead.pop(0)

    def next_view(self, robot: Pose) -> Pose | None:
        return None

    def unreachable(self, view: Pose) -> None:
        return None

    def bumped(self, pose: Pose) -> tuple[float, float] | None:
        return None


def in_legs(perception: Scans) -> tuple[Services, FakeDriver]:
    """The session at (60,0) with its first test chosen, the robot standing there; the
    driver behind the localisation decorator; plans straight from start to goal."""
    fake = FakeDriver(pose=DriverPose(140.0, 50.0, 180.0))  # what its encoders say after the first leg
    services = make_services()
    services = dataclasses.replace(services, driver=CameraLocalised(fake), perception=perception)  # type: ignore[arg-type]
    services.navigator.plan = lambda start, goal, **_: PlanResult(  # type: ignore[method-assign]
        (start, goal), "ok", abs(goal.x_in - start.x_in), 0.0, "fake")
    record, step = start_object(services)
    step.test = record.session.decide()
    put("pose", pose_at(services.navigator, P(60, 0)))  # type: ignore[arg-type]
    return services, fake


def test_split_leg_cuts_a_path_at_its_length_along_it_and_keeps_the_rest() -> None:
    path = [Pose(0.0, 0.0, 0.0), Pose(100.0, 0.0, 0.0), Pose(100.0, 100.0, 90.0)]
    leg, rest = split_leg(path, 150.0)
    assert leg == [Pose(0.0, 0.0, 0.0), Pose(100.0, 0.0, 0.0), Pose(100.0, 50.0, 90.0)]
    assert rest == [Pose(100.0, 50.0, 90.0), Pose(100.0, 100.0, 90.0)]
    assert split_leg(path, 200.0) == (path, [])  # exactly as long: whole
    assert split_leg(path, None) == (path, []) and split_leg([], 10.0) == ([], [])
    assert first_leg(path, 60.0) == [Pose(0.0, 0.0, 0.0), Pose(60.0, 0.0, 0.0)]


def test_a_long_move_is_driven_a_leg_at_a_time_and_the_look_between_corrects_the_rest() -> None:
    # the look after the first leg (20 of 36 in) places the robot 3 in north of where the
    # encoders say (140, 50): the correction becomes (0, 3), the pose on the blackboard the
    # corrected one, and the second leg goes from there to the goal, sent in the driver's
    # frame (3 in south), facing the object (100, 50) moved as well
    services, fake = in_legs(Scans(20.0, Pose(140.0, 53.0, 180.0)))
    fake.script("move", moved(DriverPose(140.0, 50.0, 180.0), 30.0), moved(DriverPose(124.0, 47.0, 180.0), 20.0))
    assert run(MoveTo(ROBOT, "test"), services) == Status.SUCCESS
    assert fake.calls == [
        ("move", (DriverPose(160.0, 50.0, 180.0), DriverPose(140.0, 50.0, 180.0)), None),  # no face mid-way
        ("move", (DriverPose(140.0, 50.0, 180.0), DriverPose(124.0, 47.0, 180.0)), (100.0, 47.0))]
    record = get("object")
    assert get("pose") == DriverPose(124.0, 50.0, 180.0) and record.session.position == P(24, 0)
    assert record.ledger.moving_s == 50.0  # both legs (the fake's clock does not run: the scan took no time)
    log = services.log
    assert log.kinds() == ["localised", "move"]
    assert log.of("localised")[0]["offset"] == [0.0, 3.0]
    move = log.of("move")[0]
    assert move["legs"] == 2 and move["seconds"] == 50.0 and move["pose"] == [124.0, 50.0, 180.0]
    assert move["path"] == [[160.0, 50.0, 180.0], [140.0, 50.0, 180.0], [140.0, 53.0, 180.0], [124.0, 50.0, 180.0]]


def test_a_leg_that_collided_ends_the_move_without_a_look() -> None:
    perception = Scans(20.0, Pose(140.0, 53.0, 180.0))
    services, fake = in_legs(perception)
    fake.script("move", moved(DriverPose(150.0, 50.0, 180.0), 12.0, collided=True))
    assert run(MoveTo(ROBOT, "test"), services) == Status.FAILURE
    assert perception.looks == 0 and len(fake.calls) == 1
    assert get("object").ledger.moving_s == 12.0 and get("object").session.awaiting_reselection


def test_a_collided_leg_is_told_to_the_perception_and_a_place_it_keeps_out_is_an_event() -> None:
    """The perception is told the pose the leg stopped at; what it keeps out (here: it
    says (138, 50)) is a ``bumped`` event before the move's; when it keeps nothing,
    no event."""
    for kept in ((138.0, 50.0), None):
        perception = Scans(20.0)
        told: list[Pose] = []
        perception.bumped = lambda pose, kept=kept: told.append(pose) or kept  # type: ignore[method-assign]
        services, fake = in_legs(perception)
        fake.script("move", moved(DriverPose(150.0, 50.0, 180.0), 12.0, collided=True))
        assert run(MoveTo(ROBOT, "test"), services) == Status.FAILURE
        assert [(p.x_in, p.y_in, p.heading_deg) for p in told] == [(150.0, 50.0, 180.0)]
        log = services.log
        if kept is None:
            assert log.kinds() == ["move"]
        else:
            assert log.kinds() == ["bumped", "move"]
            assert log.of("bumped")[0]["at"] == [138.0, 50.0] and log.of("bumped")[0]["pose"] == [150.0, 50.0, 180.0]


def test_a_perception_without_legs_drives_the_move_whole() -> None:
    perception = Scans(None)
    services, fake = in_legs(perception)
    fake.script("move", moved(DriverPose(124.0, 50.0, 180.0), 40.0))
    assert run(MoveTo(ROBOT, "test"), services) == Status.SUCCESS
    assert perception.looks == 0
    assert fake.calls == [("move", (DriverPose(160.0, 50.0, 180.0), DriverPose(124.0, 50.0, 180.0)), (100.0, 50.0))]
    assert "legs" not in services.log.of("move")[0]


def test_the_final_approach_drives_the_difference_the_look_straight_ahead_measures() -> None:
    # the move to (24, 0) ends at (124, 50) facing west (180); the look there finds the
    # object's face 26.5 in from the sonar, 2.5 in farther than wanted: the robot drives
    # 2.5 in on along its heading, to (121.5, 50), facing the object again
    perception = Scans(None, Pose(124.0, 50.0, 180.0), ahead=(26.5,))
    services, fake = in_legs(perception)
    fake.pose = DriverPose(124.0, 50.0, 180.0)  # the encoders agree with the look: no correction of the pose
    fake.script("move", moved(DriverPose(124.0, 50.0, 180.0), 40.0), moved(DriverPose(121.5, 50.0, 180.0), 3.0))
    assert run(MoveTo(ROBOT, "test"), services) == Status.SUCCESS
    assert perception.looks == 1
    last = fake.calls[-1]
    assert [(round(p.x_in, 6), round(p.y_in, 6)) for p in last[1]] == [(124.0, 50.0), (121.5, 50.0)]
    assert last[2] == (100.0, 50.0)
    move = services.log.of("move")[0]
    assert move["approach_in"] == 2.5 and move["seconds"] == 43.0 and move["pose"] == [121.5, 50.0, 180.0]
    assert get("object").session.position == P(24, 0)


def test_a_final_approach_within_the_deadband_or_past_the_bound_is_left_as_it_is() -> None:
    for measured in (24.3, 24.0 + 7.0, None):  # 0.3 in off; 7 in off (the wall behind); nothing measured
        perception = Scans(None, Pose(124.0, 50.0, 180.0), ahead=(measured,))
        perception.measures_ahead = True
        services, fake = in_legs(perception)
        fake.pose = DriverPose(124.0, 50.0, 180.0)
        fake.script("move", moved(DriverPose(124.0, 50.0, 180.0), 40.0))
        assert run(MoveTo(ROBOT, "test"), services) == Status.SUCCESS
        assert perception.looks == 1 and len(fake.calls) == 1
        assert "approach_in" not in services.log.of("move")[0]
