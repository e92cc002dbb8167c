"""A state publication nothing asked of the robot explains is refused, not believed
(hero_driver/zenoh_link/state_check.py; docs/security.md): the rules by hand, then a
real node and client on 127.0.0.1 with a forger publishing on the robot's state key."""

from __future__ import annotations

import json
import logging
import time

import pytest
import zenoh

from hero_driver.interface import Pose, RobotState
from hero_driver.sim_driver import SimulatedHero
from hero_driver.zenoh_link.client import ZenohDriver
from hero_driver.zenoh_link.node import DriverNode
from hero_driver.zenoh_link.state_check import SETTLING_STATES, StateCheck


def _state(x: float = 30.0, y: float = 30.0, heading: float = 0.0, clock: float = 10.0,
           battery: float = 0.8) -> RobotState:
    return RobotState(Pose(x, y, heading), clock, battery)


def test_the_first_state_and_a_still_robot_are_believed() -> None:
    check = StateCheck()
    assert check.judge(_state()) == ""
    assert check.judge(_state(x=31.5, clock=11.0, battery=0.79)) == ""  # odometry settling, the clock running


def test_a_pose_jump_no_move_explains_is_refused_and_the_last_state_kept() -> None:
    check = StateCheck()
    check.judge(_state())
    assert check.judge(_state(x=130.0, y=130.0, heading=90.0)) == (
        "the pose moved 141.4 in and turned 90.0 deg, to (130.0, 130.0, 90.0 deg), with no move, reset or charge "
        "under way")
    assert check.last == _state()


def test_a_move_under_way_or_just_answered_explains_a_new_pose_once() -> None:
    check = StateCheck()
    check.judge(_state())
    check.started("move")
    assert check.judge(_state(x=60.0)) == ""  # published while the move runs
    check.finished("move")
    assert check.judge(_state(x=80.0)) == ""  # the move's last pose, published after its reply
    assert check.judge(_state(x=20.0)) != ""  # nothing since explains another


def test_publications_made_during_a_move_may_arrive_after_its_reply_and_before_its_last_pose() -> None:
    """The soak's false alarm (BENCHMARKS.md, "A soak"): on a loaded machine a state
    published while the move ran arrived after its reply, was believed, and the
    publication of the move's last pose was then refused, and every one after it."""
    check = StateCheck()
    check.judge(_state())
    check.started("move")
    assert check.judge(_state(x=45.0)) == ""
    check.finished("move", Pose(80.0, 30.0, 0.0))  # the reply: the base stopped at x = 80
    assert check.judge(_state(x=60.0)) == ""  # published mid-move, delivered late
    assert check.judge(_state(x=80.0)) == ""  # the last pose, at last
    assert check.judge(_state(x=80.5)) == ""  # standing still
    assert check.judge(_state(x=20.0)) != ""  # the move is over: nothing explains another


def test_a_reply_pose_never_published_opens_no_lasting_hole() -> None:
    check = StateCheck()
    check.judge(_state())
    check.started("move")
    check.finished("move", Pose(80.0, 30.0, 0.0))
    for i in range(SETTLING_STATES - 1):
        assert check.judge(_state(x=40.0 + i)) == ""  # wandering towards it: still the move's
    assert check.judge(_state(x=50.0)) == ""  # the last one the allowance covers
    assert check.judge(_state(x=120.0)) != ""


def test_the_battery_rises_only_with_a_charge() -> None:
    check = StateCheck()
    check.judge(_state(battery=0.3))
    assert check.judge(_state(battery=0.9)) == "the battery rose from 0.300 to 0.900 with no charge"
    check.started("charge")
    check.finished("charge")
    assert check.judge(_state(battery=0.9)) == ""


def test_a_publication_older_than_the_state_believed_is_stale_unless_a_reset_explains_it() -> None:
    """A sense's reply at clock 55 s is believed (a reply always is: the client sets
    ``last``); the driver's publication from before the sense, at 10 s with the fuller
    battery of then, arrives after it. Judged, it would be "the battery rose"; it is
    stale. After a reset the clock starts again, and an earlier clock is not stale."""
    check = StateCheck()
    check.judge(_state(clock=10.0, battery=0.80))
    check.last = _state(clock=55.0, battery=0.79)
    late = _state(clock=10.0, battery=0.80)
    assert check.stale(late) and check.judge(late) != ""
    assert not check.stale(_state(clock=55.0, battery=0.79)) and not check.stale(_state(clock=60.0))
    check.started("reset")
    assert not check.stale(_state(clock=0.0, battery=1.0)) and check.judge(_state(clock=0.0, battery=1.0)) == ""


def test_a_new_driver_starts_a_new_story() -> None:
    check = StateCheck()
    check.judge(_state())
    check.forget()
    assert check.judge(_state(x=200.0)) == ""


@pytest.mark.zenoh
def test_a_forged_state_on_the_robots_key_never_becomes_the_clients_state(
        server: zenoh.Session, endpoint: str, caplog: pytest.LogCaptureFixture) -> None:
    hero = SimulatedHero("forged")
    with DriverNode(hero, server), ZenohDriver("forged", connect=[endpoint], discover_s=5.0) as client:
        assert client.wait_ready(5.0)
        real = client.state()
        # the forger publishes through the driver's own session (one the client is linked to)
        forged = {"v": 1, "pose": {"x_in": 999.0, "y_in": 999.0, "heading_deg": 90.0}, "clock_s": real.clock_s,
                  "battery": 0.02}
        with caplog.at_level(logging.WARNING, logger="hero_driver.zenoh_link.client"):
            for _ in range(10):
                server.put("hero/forged/state", json.dumps(forged).encode())
                time.sleep(0.05)
                assert client.state().pose != Pose(999.0, 999.0, 90.0)
            moved = client.move([Pose(real.pose.x_in + 20.0, real.pose.y_in, 0.0)]).result(timeout=10)
        time.sleep(0.5)  # the driver's own publications of the new pose are believed
        assert client.state().pose == moved.pose and client.state().battery > 0.5
    assert client.refused_states >= 5  # the forger's, not the driver's
    assert "forged: state publication refused: the pose moved" in caplog.text
