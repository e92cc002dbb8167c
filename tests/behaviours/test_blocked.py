"""The blocked-move branch (behaviours.blocked), behaviour by behaviour against a fake
driver with the blocked_moves feature, then the whole branch: re-planned around the
obstacle, waited and retried, given up after the bound, off.

Geometry (conftest's FakeNavigator): the object at (100, 50); the session at (60, 0)
chooses the width test at (24, 0), so the robot drives from (160, 50) to (124, 50).
"""

from __future__ import annotations

from concurrent.futures import Future
from dataclasses import dataclass

import pytest
from py_trees.common import Status

from behaviours.actions import BLOCKED, Blockage, MoveTo
from behaviours.blocked import (Blocked, LookAgain, UntilPast, WaitForMover, around_movers, blocked_moves_on,
                                branch_off_notice)
from behaviours.services import Params
from hero_driver.interface import BlockedMoves, MoveResult, Obstacle, Pose as DriverPose, RobotState
from planner import PlanResult, Pose
from tests.behaviours.conftest import (ROBOT, FakeDriver, FakeNavigator, get, image, make_services, moved,
                                       pose_at, put, run, start_object)
from tests.learner.fixtures import P

PERSON = Obstacle(140.0, 60.0, 9.0)
STOPPED = DriverPose(150.0, 50.0, 180.0)  # 10 in short of where it started, the person ahead
THERE = DriverPose(124.0, 50.0, 180.0)


class BlockingDriver(FakeDriver):
    """A FakeDriver with the blocked_moves feature: a safety distance and a wait verb."""

    def __init__(self, safety: float | None = 6.0) -> None:
        super().__init__()
        self.safety, self.clock_s = safety, 0.0

    def state(self) -> RobotState:
        return RobotState(self.pose, self.clock_s, 1.0)

    def safety_in(self) -> float | None:
        return self.safety

    def wait(self, seconds: float) -> Future[RobotState]:
        return self._answer("wait", seconds)


@dataclass
class _Map:
    inflation_in: float


class AvoidingNavigator(FakeNavigator):
    """A FakeNavigator that records the discs drawn in and refuses plans through them."""

    def __init__(self) -> None:
        super().__init__()
        self.drawn: list[tuple[tuple[float, float, float], ...]] = []
        self.vision_map = _Map(inflation_in=10.7)
        self.around: bool = True  # whether a path around a drawn disc exists

    def avoid(self, discs: tuple[tuple[float, float, float], ...]) -> None:
        self.drawn.append(tuple(discs))

    def plan(self, start: Pose, goal: Pose, *, optimise: bool = False, spacing_in: float | None = None):  # noqa: ANN201
        if self.drawn and self.drawn[-1] and not self.around:
            self.plans.append((start, goal))
            return PlanResult(None, "goal in an obstacle", float("inf"), float("inf"), "fake")
        return super().plan(start, goal, optimise=optimise, spacing_in=spacing_in)


def blocked(pose: DriverPose = STOPPED, obstacle: Obstacle = PERSON) -> MoveResult:
    return MoveResult(pose, 25.0, False, False, obstacle)


def _services(params: Params = Params(), safety: float | None = 6.0):  # noqa: ANN202
    driver, nav = BlockingDriver(safety), AvoidingNavigator()
    services = make_services(params=params, driver=driver, navigator=nav)
    record, step = start_object(services)
    step.test = record.session.decide()
    put("pose", pose_at(nav, P(60, 0)))
    return services, driver, nav, record


def _branch() -> object:
    return around_movers(ROBOT, MoveTo(ROBOT, "test"), MoveTo(ROBOT, "test", "around", role="around"),
                         MoveTo(ROBOT, "test", "again", role="retry"))


def test_the_sim_and_fake_drivers_offer_the_feature_and_plain_ones_do_not() -> None:
    assert blocked_moves_on(BlockingDriver()) and isinstance(BlockingDriver(), BlockedMoves)
    assert not blocked_moves_on(BlockingDriver(safety=None)) and not blocked_moves_on(FakeDriver())


def test_a_blocked_move_in_the_branch_fails_with_the_obstacle_and_leaves_the_test_usable() -> None:
    services, driver, nav, record = _services()
    driver.script("move", blocked())
    move = MoveTo(ROBOT, "test")
    move.in_branch = True
    assert run(move, services) == Status.FAILURE
    assert get(BLOCKED) == Blockage(PERSON, 0) and get("pose") == STOPPED
    assert not record.session.awaiting_reselection and record.ledger.moving_s == 25.0
    assert services.log.events[0]["blocked"] == [140.0, 60.0, 9.0]  # type: ignore[attr-defined]


@pytest.mark.parametrize("in_branch, tries", [(False, 3), (True, 0)])
def test_outside_the_branch_or_with_it_off_a_blocked_move_is_a_collision(in_branch: bool, tries: int) -> None:
    services, driver, nav, record = _services(Params(blocked_tries=tries))
    driver.script("move", blocked())
    move = MoveTo(ROBOT, "test")
    move.in_branch = in_branch
    assert run(move, services) == Status.FAILURE
    assert get(BLOCKED) is None and record.session.awaiting_reselection  # unusable, as a collision


def test_blocked_spends_a_round_and_gives_up_the_object_after_the_bound() -> None:
    services, driver, nav, record = _services(Params(blocked_tries=2))
    put(BLOCKED, Blockage(PERSON, 1))
    assert run(Blocked(ROBOT), services) == Status.SUCCESS and get(BLOCKED) == Blockage(PERSON, 2)
    assert run(Blocked(ROBOT), services) == Status.FAILURE
    assert get(BLOCKED) is None and record.outcome == "failed" and record in services.given_up
    [gave_up] = services.log.events  # type: ignore[attr-defined]
    assert gave_up["event"] == "gave_up" and "moving obstacle kept blocking the way (2 rounds" in gave_up["reason"]


def test_blocked_fails_quietly_when_nothing_blocked() -> None:
    services, *_ = _services()
    put(BLOCKED, None)
    assert run(Blocked(ROBOT), services) == Status.FAILURE and services.log.events == []  # type: ignore[attr-defined]


def test_look_again_observes_and_draws_the_obstacle_wider_but_clear_of_the_robot() -> None:
    services, driver, nav, record = _services()
    nav.see()
    driver.script("camera", image())
    put(BLOCKED, Blockage(PERSON, 1))
    put("pose", STOPPED)
    assert run(LookAgain(ROBOT), services) == Status.SUCCESS
    # the robot 14.1 in from the person: min(9 + 3, 14.14 - 10.7 - 1) = 2.44 in
    [[(x, y, r)]] = nav.drawn
    assert (x, y) == (140.0, 60.0) and r == pytest.approx(14.1421 - 11.7, abs=1e-3)
    assert nav.observed == 1


def test_wait_for_mover_waits_charges_moving_time_and_clears_the_map() -> None:
    services, driver, nav, record = _services(Params(blocked_wait_s=15.0))
    driver.script("wait", RobotState(STOPPED, 15.0, 1.0))
    assert run(WaitForMover(ROBOT), services) == Status.SUCCESS
    assert driver.calls == [("wait", 15.0)] and record.ledger.moving_s == 15.0 and nav.drawn == [()]


def test_wait_for_mover_without_the_feature_fails_without_a_verb() -> None:
    services, driver, nav, record = _services(safety=None)
    assert run(WaitForMover(ROBOT), services) == Status.FAILURE and driver.calls == []


def test_the_branch_re_plans_around_the_obstacle() -> None:
    services, driver, nav, record = _services()
    nav.see()
    driver.script("move", blocked(), moved(THERE, 80.0)).script("camera", image())
    assert run(_branch(), services) == Status.SUCCESS
    assert driver.verbs() == ["move", "camera", "move"] and record.session.position == P(24, 0)
    assert get(BLOCKED) is None and len(nav.drawn) == 1


def test_the_branch_waits_and_retries_when_no_path_goes_around() -> None:
    services, driver, nav, record = _services()
    nav.around = False
    nav.see()
    driver.script("move", blocked(), moved(THERE, 80.0)).script("camera", image())
    driver.script("wait", RobotState(STOPPED, 20.0, 1.0))
    assert run(_branch(), services) == Status.SUCCESS
    assert driver.verbs() == ["move", "camera", "wait", "move"] and record.session.position == P(24, 0)
    assert not record.session.awaiting_reselection  # the test stayed usable through it all


def test_the_branch_gives_the_object_up_after_its_rounds_and_the_run_goes_on() -> None:
    services, driver, nav, record = _services(Params(blocked_tries=2))
    nav.around = False
    nav.see().see()
    driver.script("move", blocked(), blocked(), blocked()).script("camera", image(), image())
    driver.script("wait", RobotState(STOPPED, 20.0, 1.0), RobotState(STOPPED, 40.0, 1.0))
    assert run(_branch(), services, max_ticks=20) == Status.FAILURE
    assert driver.verbs() == ["move", "camera", "wait", "move", "camera", "wait", "move"]
    assert record.outcome == "failed" and services.log.events[-1]["event"] == "gave_up"  # type: ignore[attr-defined]


def test_until_past_stops_when_the_rounds_fail_for_another_reason() -> None:
    services, driver, nav, record = _services()
    put(BLOCKED, None)
    decorator = UntilPast(Blocked(ROBOT), ROBOT)
    assert run(decorator, services) == Status.FAILURE


def test_around_movers_checks_its_moves() -> None:
    with pytest.raises(ValueError, match="roles first, around and retry"):
        around_movers(ROBOT, MoveTo(ROBOT, "test"), MoveTo(ROBOT, "grasp", role="around"),
                      MoveTo(ROBOT, "test", role="retry"))


def test_the_notice_names_the_driver_only_when_the_feature_is_missing() -> None:
    assert branch_off_notice(BlockingDriver(), 3) is None and branch_off_notice(FakeDriver(), 0) is None
    assert branch_off_notice(FakeDriver(), 3) == (
        "blocked moves: driver r1 has no blocked_moves feature: the blocked-move branch is off "
        "(a move into a person or cart ends collided)")
