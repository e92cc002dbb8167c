"""The blocked_moves feature over zenoh: the codec carries ``blocked``, ``safety_in``
and ``wait`` both ways, the zenoh client exposes them, and ``csl driver check``'s
blocked-moves check passes the simulator and fails a mutant that claims the feature
but drives into people."""

from __future__ import annotations

import json

import pytest
import zenoh

from hero_driver.interface import UNKNOWN_VERB, BlockedMoves, DriverError, Hello, MoveResult, Obstacle, Pose
from hero_driver.sim_driver import SimulatedHero
from hero_driver.zenoh_link.client import ZenohDriver
from hero_driver.zenoh_link.codec import CodecError, WaitRequest
from hero_driver.zenoh_link.conformance import Procedures, run_checks
from hero_driver.zenoh_link.node import DriverNode
from hero_driver.zenoh_link.verbs import BY_NAME
from hero_driver.zenoh_link.versions import BLOCKED_MOVES, Greeting, greeting

HERE = Pose(23.9, 21.1, 16.4)


def test_a_blocked_move_reply_round_trips_and_an_unblocked_one_has_no_field() -> None:
    move = BY_NAME["move"]
    blocked = MoveResult(HERE, 16.4, False, False, Obstacle(40.0, 38.9, 9.0))
    body = move.encode_result(blocked)
    assert json.loads(body)["blocked"] == {"x_in": 40.0, "y_in": 38.9, "radius_in": 9.0}
    assert move.decode_result(body) == blocked
    assert "blocked" not in json.loads(move.encode_result(MoveResult(HERE, 1.0, False, True)))


def test_hello_carries_safety_in_exactly_with_the_feature() -> None:
    hello = BY_NAME["hello"]
    served = greeting(None, None, 6.0)
    assert served == Greeting(Hello((1,), (BLOCKED_MOVES,)), None, None, 6.0)
    assert hello.decode_result(hello.encode_result(served)) == served
    with pytest.raises(CodecError, match="safety_in"):
        hello.decode_result(b'{"v": 1, "versions": [1], "features": ["blocked_moves"]}')
    with pytest.raises(CodecError, match="safety_in"):
        hello.decode_result(b'{"v": 1, "versions": [1], "features": [], "safety_in": 6}')


@pytest.mark.parametrize("seconds", [-1.0, 3601.0, float("nan")])
def test_wait_refuses_seconds_out_of_bounds(seconds: float) -> None:
    with pytest.raises(CodecError, match="seconds"):
        BY_NAME["wait"].encode_request(WaitRequest(seconds))


def test_a_simulator_offers_the_feature_unless_it_ignores_movers() -> None:
    assert SimulatedHero(world="lab").safety_in() == 6.0  # the stop is the driver's: no movers, still on
    assert SimulatedHero(world="crossing").safety_in() == 6.0
    assert SimulatedHero(world="crossing", stop_for_movers=False).safety_in() is None


class IgnoresMovers(SimulatedHero):
    """Claims blocked_moves but drives into people (the bumper stops it on contact)."""

    def __init__(self, robot: str) -> None:
        super().__init__(robot, world="lab", stop_for_movers=False)

    def safety_in(self) -> float | None:
        return 6.0


def _check(driver: SimulatedHero, server: zenoh.Session, endpoint: str) -> dict[str, object]:
    with DriverNode(driver, server):
        results = run_checks(driver.robot, [endpoint], timeout_s=5.0, procedures=Procedures.from_profile())
    return {r.name: r for r in results}


@pytest.mark.slow
@pytest.mark.zenoh
def test_the_simulator_passes_the_blocked_moves_check(server: zenoh.Session, endpoint: str) -> None:
    results = _check(SimulatedHero("bm"), server, endpoint)
    assert all(r.passed for r in results.values()), [r for r in results.values() if not r.passed]
    assert results["blocked-moves"].detail.startswith("stopped short at")


@pytest.mark.slow
@pytest.mark.zenoh
def test_a_driver_that_ignores_movers_fails_it(server: zenoh.Session, endpoint: str) -> None:
    driver = IgnoresMovers("ig")
    assert isinstance(driver, BlockedMoves)
    results = _check(driver, server, endpoint)
    assert {name for name, r in results.items() if not r.passed} == {"blocked-moves"}
    assert "collided" in results["blocked-moves"].detail


@pytest.mark.zenoh
def test_the_zenoh_client_offers_the_feature_its_driver_offers(server: zenoh.Session, endpoint: str) -> None:
    with DriverNode(SimulatedHero("zc", world="crossing"), server), \
            ZenohDriver("zc", connect=[endpoint], discover_s=5.0) as client:
        assert client.wait_ready(5.0) and isinstance(client, BlockedMoves)
        assert client.safety_in() == 6.0
        assert client.wait(2.0).result(5.0).clock_s == pytest.approx(2.0)
        moved = client.move([Pose(200.0, 90.0, 0.0)]).result(5.0)
        assert moved.blocked is not None and not moved.collided and moved.pose.x_in < 100.0 - 18.0


@pytest.mark.zenoh
def test_a_driver_without_the_feature_answers_wait_unknown_verb(server: zenoh.Session, endpoint: str) -> None:
    with DriverNode(SimulatedHero("nf", world="lab", stop_for_movers=False), server), \
            ZenohDriver("nf", connect=[endpoint], discover_s=5.0) as client:
        assert client.wait_ready(5.0) and client.safety_in() is None
        with pytest.raises(DriverError) as err:
            client.wait(1.0).result(5.0)
        assert err.value.code == UNKNOWN_VERB
