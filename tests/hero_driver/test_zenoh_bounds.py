"""The driver bounds everything: request size and waypoint count are
capped before the robot sees them, and a robot verb that overruns its bound is
cancelled and answered ``timeout``, leaving the robot free for the next verb."""

from __future__ import annotations

import json

import pytest
import zenoh

from hero_driver.interface import BAD_REQUEST, NO_TARGET, TIMEOUT, UNAVAILABLE, Pose, SenseResult
from hero_driver.zenoh_link.client import VerbTimeouts, ZenohDriver
from hero_driver.zenoh_link.codec import MAX_REQUEST_BYTES, MAX_WAYPOINTS, MoveRequest
from hero_driver.zenoh_link.keys import robot_keys
from hero_driver.zenoh_link.node import DriverNode, verb_bounds
from hero_driver.zenoh_link.verbs import BY_NAME, VERBS
from tests.hero_driver.test_zenoh_node import ask, error_of
from tests.hero_driver.test_zenoh_support import FakeHero, HangingHero
from tests.zenoh_rpc.support import wait_until
from zenoh_rpc.config import open_session

REPLY_S = 5.0


# ------------------------------------------------------------------------- the bounds


def test_every_robot_verb_has_a_bound_shorter_than_its_client_timeout() -> None:
    for verb in VERBS:
        if verb.touches_robot:
            assert verb.bound_s is not None and 0 < verb.bound_s < verb.timeout_s, verb.name
        else:
            assert verb.bound_s is None, verb.name


@pytest.mark.parametrize(("overrides", "message"), [
    ({"noop": 1.0}, "'noop' is not a robot verb"),
    ({"fly": 1.0}, "'fly' is not a robot verb"),
    ({"sense": 0.0}, "sense must be a positive number of seconds"),
    ({"sense": float("nan")}, "sense must be a positive number of seconds"),
    ({"move": float("inf")}, "move must be a positive number of seconds"),
])
def test_bad_bounds_are_refused_naming_the_verb(overrides: dict[str, float], message: str) -> None:
    with pytest.raises(ValueError, match=message):
        verb_bounds(overrides)


def test_overrides_replace_only_their_verb() -> None:
    bounds = verb_bounds({"sense": 0.5})
    assert bounds["sense"] == 0.5 and bounds["move"] == BY_NAME["move"].bound_s


# --------------------------------------------------------------------- the caps (codec)


def test_the_largest_move_allowed_fits_under_the_size_cap() -> None:
    """MAX_WAYPOINTS poses whose numbers take JSON's longest double form."""
    longest = -1.2345678901234567e-300
    request = MoveRequest(tuple(Pose(longest, longest, longest) for _ in range(MAX_WAYPOINTS)), (longest, longest))
    payload = BY_NAME["move"].encode_request(request)
    assert len(payload) <= MAX_REQUEST_BYTES
    assert len(BY_NAME["move"].decode_request(payload).waypoints) == MAX_WAYPOINTS


def test_one_waypoint_too_many_is_refused_by_the_client_before_sending() -> None:
    request = MoveRequest(tuple(Pose(1.0, 1.0, 0.0) for _ in range(MAX_WAYPOINTS + 1)))
    with pytest.raises(ValueError, match="waypoints: 1001 poses, more than the 1000"):
        BY_NAME["move"].encode_request(request)


# ------------------------------------------------------------------ over the wire


@pytest.mark.zenoh
def test_a_million_waypoint_move_is_bad_request_and_the_robot_stays(server: zenoh.Session, endpoint: str) -> None:
    hero = FakeHero()
    with DriverNode(hero, server), open_session(connect=[endpoint], connect_timeout_s=5.0) as session:
        waypoint = b'{"x_in":1e308,"y_in":1e308,"heading_deg":0}'
        body = b'{"v":1,"waypoints":[' + b",".join([waypoint] * 1_000_000) + b"]}"
        assert len(body) > 40_000_000
        [(kind, reply)] = ask(session, robot_keys("r1").rpc("move"), body, timeout_s=30.0)
        assert kind == "err" and reply["code"] == BAD_REQUEST
        assert reply["message"] == f"message: {len(body)} bytes, more than the {MAX_REQUEST_BYTES} a request may have"
        assert hero.pose == Pose(30.0, 30.0, 0.0) and hero.clock_s == 0.0
        [(kind, _)] = ask(session, robot_keys("r1").rpc("move"),
                          json.dumps({"v": 1, "waypoints": [{"x_in": 50, "y_in": 40, "heading_deg": 0}]}).encode(),
                          timeout_s=30.0)
        assert kind == "ok" and hero.pose == Pose(50.0, 40.0, 0.0)


@pytest.mark.zenoh
@pytest.mark.parametrize("running", [False, True], ids=["cancellable", "not-cancellable"])
def test_a_hung_verb_is_cancelled_answered_timeout_and_the_next_verb_served(
        server: zenoh.Session, endpoint: str, running: bool) -> None:
    hero = HangingHero(running=running)
    node = DriverNode(hero, server, bounds={"sense": 0.3})
    with node, ZenohDriver("r1", connect=[endpoint], discover_s=5.0) as client:
        assert client.wait_ready(5.0)
        error = error_of(client.sense("H-Sweep-5°"))
        assert error.code == TIMEOUT
        assert error.message == "sense: overran the driver's bound of 0.3 s; cancelled"
        assert hero.hung is not None and hero.hung.cancelled() is not running
        # the robot is free: the next verbs are served, not refused busy
        assert error_of(client.sense("H-Sweep-5°")).code == NO_TARGET
        assert client.move([Pose(120, 40, 0)]).result(REPLY_S).pose == Pose(120, 40, 0)
        if running:  # the driver finishes after all: the late result is dropped, the node serves on
            hero.hung.set_result(SenseResult("H-Sweep-5°", {"Width-Degree-5°": 1.0}, 1.0, 20.0))
        assert client.sense("H-Sweep-5°").result(REPLY_S).values == {"Width-Degree-5°": 31.5}


@pytest.mark.zenoh
def test_closing_with_a_verb_under_way_cancels_its_bound(server: zenoh.Session, endpoint: str) -> None:
    hero = HangingHero()
    node = DriverNode(hero, server, bounds={"sense": 0.2})
    with ZenohDriver("r1", connect=[endpoint], discover_s=5.0,
                     timeouts=VerbTimeouts(sense_s=5.0)) as client:
        assert client.wait_ready(5.0)
        pending = client.sense("H-Sweep-5°")
        assert wait_until(lambda: hero.hung is not None, 2.0)
        node.close()
        # the client learns from the token, not from a reply on a closed node
        assert error_of(pending).code == UNAVAILABLE
