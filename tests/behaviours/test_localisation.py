"""Dead reckoning corrected by the overhead camera (behaviours/localisation.py)."""

from __future__ import annotations

from concurrent.futures import Future
from typing import Any

import pytest

from behaviours.localisation import CameraLocalised
from hero_driver.interface import (OUT_OF_RANGE, BlockedMoves, Charger, DriverError, MoveResult, Obstacle, Pose,
                                   RobotState)


def settled(value: object) -> Future[Any]:
    future: Future[Any] = Future()
    if isinstance(value, DriverError):
        future.set_exception(value)
    else:
        future.set_result(value)
    return future


class Reckoning:
    """A driver whose dead reckoning says it stands at (10, 10); it records what it is sent."""

    robot = "r1"

    def __init__(self) -> None:
        self.sent: list[tuple[list[Pose], tuple[float, float] | None]] = []
        self.move_answer: object = None
        self.pose = Pose(10.0, 10.0, 90.0)

    def state(self) -> RobotState:
        return RobotState(self.pose, 0.0, 1.0)

    def move(self, waypoints: list[Pose], face: tuple[float, float] | None = None) -> Future[MoveResult]:
        self.sent.append((list(waypoints), face))
        if isinstance(self.move_answer, MoveResult):
            self.pose = self.move_answer.pose
        return settled(self.move_answer)

    def reset(self, world: str | None = None, seed: int | None = None) -> Future[RobotState]:
        self.pose = Pose(10.0, 10.0, 90.0)
        return settled(self.state())


class WithDock(Reckoning):
    def dock(self) -> Pose | None:
        return Pose(0.0, 5.0, 180.0)

    def charge(self) -> Future[RobotState]:
        return settled(self.state())


def test_a_camera_position_within_the_deadband_changes_nothing() -> None:
    robot = CameraLocalised(Reckoning())
    assert not robot.localise(10.3, 10.35)  # 0.46 in from the reported pose: the camera's own error
    assert robot.offset == (0.0, 0.0) and robot.state().pose == Pose(10.0, 10.0, 90.0)


def test_beyond_it_every_pose_is_shifted_out_and_every_waypoint_back() -> None:
    inner = Reckoning()
    robot = CameraLocalised(inner)
    assert robot.localise(11.5, 9.0)  # 1.80 in away: the robot slipped
    assert robot.offset == (1.5, -1.0)
    assert robot.state().pose == Pose(11.5, 9.0, 90.0)
    inner.move_answer = MoveResult(Pose(18.5, 21.0, 45.0), 12.0, False, True, blocked=Obstacle(20.0, 25.0, 3.0))
    result = robot.move([Pose(15.0, 15.0, 45.0), Pose(20.0, 20.0, 45.0)], face=(30.0, 30.0)).result()
    assert inner.sent == [([Pose(13.5, 16.0, 45.0), Pose(18.5, 21.0, 45.0)], (28.5, 31.0))]
    assert result.pose == Pose(20.0, 20.0, 45.0)  # where the camera will see it
    assert result.blocked == Obstacle(21.5, 24.0, 3.0) and result.duration_s == 12.0
    assert not robot.localise(20.2, 20.0)  # the next image agrees: the offset stays
    assert robot.reset().result().pose == Pose(10.0, 10.0, 90.0) and robot.offset == (0.0, 0.0)


def test_a_refusal_comes_through_as_the_driver_gave_it() -> None:
    inner = Reckoning()
    inner.move_answer = DriverError(OUT_OF_RANGE, "move: nowhere")
    with pytest.raises(DriverError, match="nowhere"):
        CameraLocalised(inner).move([Pose(1.0, 1.0, 0.0)]).result()


def test_optional_features_are_offered_only_when_the_driver_has_them_and_shifted() -> None:
    assert not isinstance(CameraLocalised(Reckoning()), Charger)
    assert not isinstance(CameraLocalised(Reckoning()), BlockedMoves)
    robot = CameraLocalised(WithDock())
    assert isinstance(robot, Charger)
    robot.localise(12.0, 10.0)
    assert robot.dock() == Pose(2.0, 5.0, 180.0)
    assert robot.charge().result().pose == Pose(12.0, 10.0, 90.0)


def test_a_matched_heading_turns_every_pose_out_and_every_waypoint_back() -> None:
    inner = Reckoning()
    inner.pose = Pose(10.0, 0.0, 0.0)
    robot = CameraLocalised(inner)
    # The scan matcher says the robot stands at (0, 10) facing 90°: its dead reckoning
    # turned a quarter turn about the origin (Rot(90°)·(10, 0) = (0, 10)), no shift.
    assert robot.localise(0.0, 10.0, 90.0)
    assert robot.turn_deg == pytest.approx(90.0) and robot.offset == pytest.approx((0.0, 0.0), abs=1e-9)
    seen = robot.state().pose
    assert (seen.x_in, seen.y_in, seen.heading_deg) == pytest.approx((0.0, 10.0, 90.0), abs=1e-9)
    inner.move_answer = MoveResult(Pose(20.0, 0.0, 0.0), 5.0, False, True)
    result = robot.move([Pose(0.0, 20.0, 90.0)], face=(-5.0, 20.0)).result()
    (sent,), face = inner.sent[0]
    # Rot(-90°) back: (0, 20) -> (20, 0) facing 0°; the face point (-5, 20) -> (20, 5)
    assert (sent.x_in, sent.y_in, sent.heading_deg) == pytest.approx((20.0, 0.0, 0.0), abs=1e-9)
    assert face == pytest.approx((20.0, 5.0), abs=1e-9)
    assert (result.pose.x_in, result.pose.y_in, result.pose.heading_deg) == pytest.approx((0.0, 20.0, 90.0), abs=1e-9)
    back = robot.to_driver(robot.to_camera(Pose(3.0, -4.0, 30.0)))
    assert (back.x_in, back.y_in, back.heading_deg) == pytest.approx((3.0, -4.0, 30.0), abs=1e-9)


def test_a_heading_within_the_deadband_changes_nothing_and_the_camera_never_turns() -> None:
    robot = CameraLocalised(Reckoning())
    assert not robot.localise(10.0, 10.0, 90.3)  # 0.3° off: within the half-degree deadband
    assert robot.turn_deg == 0.0
    assert robot.localise(12.0, 10.0)  # no heading given (the camera's): a shift alone
    assert robot.turn_deg == 0.0 and robot.offset == (2.0, 0.0)
