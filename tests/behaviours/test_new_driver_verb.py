"""A verb added to the driver's verb table reaches every driver decorator without
editing any of them (docs/conventions.md, "Adding a driver verb", followed here for
the in-process part): ``turn_to`` faces a world point and answers the state. Stacked
as the executive stacks them (busy-retry over the camera's frame over recording), a
``turn_to`` is sent again while the robot finishes one that timed out, its point goes
in and its pose comes out shifted by the camera's offset, and its answer is recorded.
"""

from __future__ import annotations

import threading
from collections.abc import Iterator
from concurrent.futures import Future
from typing import Any

import pytest

from behaviours.localisation import CameraLocalised
from behaviours.overdue import OverdueRobot
from recording.driver import RecordingDriver
from hero_driver import interface
from hero_driver.interface import BUSY, TIMEOUT, DriverError, DriverVerb, Pose, RobotState

# Step 1 of the recipe: the verb's row (in hero_driver/interface.py's DRIVER_VERBS).
TURN_TO = DriverVerb("turn_to", RobotState, ("point",), poses_in=("point",), poses_out=("pose",))
FACING = RobotState(Pose(10.0, 10.0, 45.0), 12.0, 0.9)  # what the driver answers, in its own frame


@pytest.fixture(autouse=True)
def turn_to_in_the_table(monkeypatch: pytest.MonkeyPatch) -> Iterator[None]:
    monkeypatch.setitem(interface.VERB_BY_NAME, "turn_to", TURN_TO)
    yield


class Turning:
    """Step 2: a driver that has the verb; its dead reckoning says it stands at (10, 10).
    ``turn_to`` answers from a script of error codes and states, in order."""

    robot = "r1"

    def __init__(self, *answers: object) -> None:
        self.answers = list(answers)
        self.points: list[tuple[float, float]] = []
        self.lock = threading.Lock()

    def state(self) -> RobotState:
        return RobotState(Pose(10.0, 10.0, 90.0), 0.0, 1.0)

    def turn_to(self, point: tuple[float, float]) -> Future[RobotState]:
        with self.lock:
            self.points.append(point)
            answer = self.answers.pop(0)
        future: Future[RobotState] = Future()
        if isinstance(answer, str):
            future.set_exception(DriverError(answer, f"turn_to: {answer}"))
        else:
            future.set_result(answer)  # type: ignore[arg-type]
        return future


class Recorder:
    """Keeps the states the recording draws."""

    def __init__(self) -> None:
        self.states: list[RobotState] = []

    def state(self, state: RobotState) -> None:
        self.states.append(state)


def test_a_new_verb_gets_busy_retry_the_cameras_frame_and_recording() -> None:
    inner, recorder = Turning(TIMEOUT, BUSY, BUSY, FACING), Recorder()
    localised = CameraLocalised(RecordingDriver(inner, recorder))  # type: ignore[arg-type]
    robot: Any = OverdueRobot(localised, wait_s=60.0, retry_s=0.01)
    assert localised.localise(11.5, 9.0) and localised.offset == (1.5, -1.0)  # the robot slipped

    with pytest.raises(DriverError, match="timeout"):
        robot.turn_to((30.0, 30.0)).result(timeout=5.0)  # unanswered: the robot may still be turning
    turned = robot.turn_to((40.0, 20.0)).result(timeout=5.0)  # busy twice, then taken

    assert inner.points == [(28.5, 31.0), (38.5, 21.0), (38.5, 21.0), (38.5, 21.0)]  # into the driver's frame
    assert turned == RobotState(Pose(11.5, 9.0, 45.0), 12.0, 0.9)  # out in the camera's
    assert recorder.states == [FACING]  # the answer, as the driver gave it; refusals are not drawn
    assert robot.overdue is None


def test_without_its_row_a_method_passes_through_untouched(monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.delitem(interface.VERB_BY_NAME, "turn_to")
    inner = Turning(FACING)
    robot: Any = CameraLocalised(inner)  # type: ignore[arg-type]
    robot.offset = (1.5, -1.0)
    assert robot.turn_to((40.0, 20.0)).result() == FACING and inner.points == [(40.0, 20.0)]
