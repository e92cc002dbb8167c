"""behaviours.overdue: after a timeout, a verb refused ``busy`` waits for the robot;
without one, ``busy`` is someone else driving and fails as before."""

from __future__ import annotations

import threading
from concurrent.futures import Future
from typing import Any

import pytest

from behaviours.overdue import OverdueRobot
from hero_driver.interface import BUSY, NO_TARGET, TIMEOUT, DriverError, GraspResult, Pose, RobotState, SenseResult


class ScriptedDriver:
    """Answers each verb from a script of results or error codes, in order, and counts
    the calls; futures are settled at once, as the in-process simulator's are."""

    robot = "r1"

    def __init__(self, *answers: object) -> None:
        self.answers = list(answers)
        self.calls: list[tuple[str, Any]] = []
        self.lock = threading.Lock()

    def _answer(self, verb: str, argument: Any) -> Future[Any]:
        with self.lock:
            self.calls.append((verb, argument))
            answer = self.answers.pop(0)
        future: Future[Any] = Future()
        if isinstance(answer, str):
            future.set_exception(DriverError(answer, f"{verb}: {answer}"))
        else:
            future.set_result(answer)
        return future

    def state(self) -> RobotState:
        return RobotState(Pose(0.0, 0.0, 0.0), 0.0, 1.0)

    def sense(self, procedure: str) -> Future[SenseResult]:
        return self._answer("sense", procedure)

    def grasp(self, procedure: str) -> Future[GraspResult]:
        return self._answer("grasp", procedure)

    def close(self) -> None:
        pass


SENSED = SenseResult("H-Sweep-5°", {"Width-Degree-5°": 30.0}, 45.0, 20.0)
GRASPED = GraspResult("Front-Pinch", True, 20.0)


class Clock:
    def __init__(self) -> None:
        self.now = 0.0

    def __call__(self) -> float:
        return self.now


def test_a_busy_robot_after_a_timeout_is_waited_for_and_the_same_verb_sent_again() -> None:
    inner = ScriptedDriver(TIMEOUT, BUSY, BUSY, GRASPED)
    robot = OverdueRobot(inner, wait_s=60.0, retry_s=0.01)
    with pytest.raises(DriverError, match="sense"):
        robot.sense("H-Sweep-5°").result()
    assert robot.overdue == "sense"
    assert robot.grasp("Front-Pinch").result(timeout=5) == GRASPED
    assert inner.calls == [("sense", "H-Sweep-5°")] + [("grasp", "Front-Pinch")] * 3
    assert robot.overdue is None  # the robot took a verb: a later busy is someone else's


def test_busy_with_nothing_overdue_fails_at_once() -> None:
    inner = ScriptedDriver(BUSY)
    robot = OverdueRobot(inner, wait_s=60.0, retry_s=0.01)
    future = robot.grasp("Front-Pinch")
    assert future.done()
    with pytest.raises(DriverError) as raised:
        future.result()
    assert raised.value.code == BUSY and len(inner.calls) == 1


def test_an_answer_or_any_other_error_clears_the_overdue_verb() -> None:
    inner = ScriptedDriver(TIMEOUT, NO_TARGET, BUSY)
    robot = OverdueRobot(inner, wait_s=60.0, retry_s=0.01)
    robot.sense("H-Sweep-5°")
    robot.sense("H-Sweep-5°")  # no_target: the robot answered
    assert robot.overdue is None
    with pytest.raises(DriverError, match="busy"):
        robot.grasp("Front-Pinch").result(timeout=1)


def test_a_robot_busy_past_the_wait_fails_the_verb_as_unanswered_and_the_next_at_once() -> None:
    clock = Clock()
    inner = ScriptedDriver(TIMEOUT, BUSY, BUSY)
    robot = OverdueRobot(inner, wait_s=30.0, clock=clock, retry_s=0.01)
    robot.sense("H-Sweep-5°")
    clock.now = 30.0  # the wait is over when the robot is first asked again
    with pytest.raises(DriverError) as raised:
        robot.grasp("Front-Pinch").result(timeout=1)
    assert raised.value.code == TIMEOUT
    assert raised.value.message == "grasp: the robot was still busy 30 s after sense went unanswered"
    with pytest.raises(DriverError, match="still busy"):
        robot.grasp("Front-Pinch").result(timeout=1)
    assert len(inner.calls) == 3  # one try each: no waiting once the wait is spent


def test_a_cancelled_verb_is_not_sent_again() -> None:
    inner = ScriptedDriver(TIMEOUT, BUSY, GRASPED)
    robot = OverdueRobot(inner, wait_s=60.0, retry_s=0.2)
    robot.sense("H-Sweep-5°")
    future = robot.grasp("Front-Pinch")
    assert future.cancel()  # the behaviour was pre-empted while the robot was busy
    threading.Event().wait(0.4)
    assert inner.calls == [("sense", "H-Sweep-5°"), ("grasp", "Front-Pinch")]


def test_what_the_driver_offers_beyond_the_verbs_is_the_drivers() -> None:
    inner = ScriptedDriver()
    robot = OverdueRobot(inner, wait_s=1.0)
    assert robot.robot == "r1" and robot.state() == inner.state()
    assert not hasattr(robot, "charge") and not hasattr(robot, "dock")  # no battery feature: none here
