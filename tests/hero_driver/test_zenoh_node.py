"""The driver node and the client in one process (two zenoh sessions over TCP on
127.0.0.1): serialisation, timeouts, error replies and closing, with fake drivers
whose timing the test controls."""

from __future__ import annotations

import json
import threading
from concurrent.futures import Future

import pytest
import zenoh

from hero_driver.interface import (
    BAD_REQUEST,
    BUSY,
    INTERNAL,
    NO_TARGET,
    TIMEOUT,
    UNAVAILABLE,
    UNKNOWN_VERB,
    Driver,
    DriverError,
    GraspResult,
    Pose,
)
from hero_driver.zenoh_link.client import VerbTimeouts, ZenohDriver
from hero_driver.zenoh_link.codec import MoveRequest
from hero_driver.zenoh_link.keys import robot_keys
from hero_driver.zenoh_link.node import DriverNode
from hero_driver.zenoh_link.verbs import BY_NAME
from tests.hero_driver.test_zenoh_support import BrokenHero, FakeHero, SlowHero
from tests.zenoh_rpc.support import wait_until
from zenoh_rpc.config import open_session

pytestmark = pytest.mark.zenoh

REPLY_S = 5.0


def served(driver: Driver, server: zenoh.Session, endpoint: str,
           timeouts: VerbTimeouts = VerbTimeouts()) -> tuple[DriverNode, ZenohDriver]:
    node = DriverNode(driver, server)
    client = ZenohDriver(driver.robot, connect=[endpoint], timeouts=timeouts, discover_s=5.0)
    assert client.wait_ready(5.0)
    return node, client


def error_of(future: object) -> DriverError:
    with pytest.raises(DriverError) as caught:
        future.result(REPLY_S)  # type: ignore[attr-defined]
    return caught.value


def test_fake_hero_implements_the_driver_protocol() -> None:
    assert isinstance(FakeHero(), Driver)


def test_every_verb_round_trips(server: zenoh.Session, endpoint: str) -> None:
    node, client = served(FakeHero(), server, endpoint)
    with node, client:
        assert isinstance(client, Driver)
        moved = client.move([Pose(50, 40, 0), Pose(120, 40, 90)], face=(120, 80)).result(REPLY_S)
        assert moved.pose == Pose(120, 40, 90) and moved.centred
        sensed = client.sense("H-Sweep-5°").result(REPLY_S)
        assert sensed.values == {"Width-Degree-5°": 31.5}
        assert error_of(client.grasp("Front-Pinch")).code == NO_TARGET
        assert client.camera().result(REPLY_S).pixels.shape == (24, 32)
        assert client.release().result(REPLY_S).pose == Pose(120, 40, 90)
        assert client.reset(world="lab", seed=3).result(REPLY_S).clock_s == 0
        assert client.noop().result(REPLY_S) is None
        assert wait_until(lambda: client.state().pose == Pose(30, 30, 0), 2.0)


def test_a_second_verb_while_one_runs_is_refused_busy(server: zenoh.Session, endpoint: str) -> None:
    hero = SlowHero()
    node, client = served(hero, server, endpoint)
    with node, client:
        moving = client.move([Pose(40, 30, 0)])
        assert wait_until(lambda: hero.moving is not None, 2.0)
        assert error_of(client.sense("H-Sweep-5°")).code == BUSY
        assert client.noop().result(REPLY_S) is None  # the health ping is never busy
        assert not moving.done()
        hero.finish_move()
        assert moving.result(REPLY_S).pose == Pose(40, 30, 0)
        assert error_of(client.sense("H-Sweep-5°")).code == NO_TARGET  # free again


def test_a_verb_past_its_timeout_fails_with_timeout(server: zenoh.Session, endpoint: str) -> None:
    hero = SlowHero()
    node, client = served(hero, server, endpoint, VerbTimeouts(move_s=0.3))
    with node, client:
        error = error_of(client.move([Pose(40, 30, 0)]))
        assert error.code == TIMEOUT and "0.3 s" in error.message
        hero.finish_move()  # the late reply is dropped; the node serves on
        assert client.noop().result(REPLY_S) is None


def test_driver_faults_become_error_replies_and_the_node_serves_on(server: zenoh.Session,
                                                                   endpoint: str) -> None:
    node, client = served(BrokenHero(), server, endpoint)
    with node, client:
        crashed = error_of(client.sense("No-Such-Procedure"))
        assert crashed.code == INTERNAL and "KeyError" in crashed.message
        malformed = error_of(client.sense("H-Sweep-5°"))
        assert malformed.code == INTERNAL and "values.Width-Degree-5°" in malformed.message
        assert client.noop().result(REPLY_S) is None


class InventiveHero(FakeHero):
    """Refuses a grasp with an error code the protocol does not have."""

    def grasp(self, procedure: str) -> Future[GraspResult]:
        raise DriverError("on_fire", "the gripper is smoking")


def test_an_unknown_error_code_from_the_driver_arrives_as_internal(server: zenoh.Session,
                                                                   endpoint: str) -> None:
    node, client = served(InventiveHero(), server, endpoint)
    with node, client:
        error = error_of(client.grasp("Front-Pinch"))
        assert error.code == INTERNAL and "'on_fire'" in error.message


def test_bad_arguments_fail_the_future_without_sending(server: zenoh.Session, endpoint: str) -> None:
    node, client = served(FakeHero(), server, endpoint)
    with node, client:
        assert error_of(client.move([])).code == BAD_REQUEST
        assert error_of(client.move([Pose(1, 2, 3)], face=(1.0, float("nan")))).code == BAD_REQUEST
        assert error_of(client.sense(42)).code == BAD_REQUEST  # type: ignore[arg-type]


def ask(session: zenoh.Session, key: str, payload: bytes, timeout_s: float = REPLY_S) -> list[tuple[str, dict]]:
    """Raw query: every reply as ("ok" | "err", body)."""
    replies: list[tuple[str, dict]] = []
    finished = threading.Event()

    def on_reply(reply: zenoh.Reply) -> None:
        if reply.ok is not None:
            replies.append(("ok", json.loads(reply.ok.payload.to_bytes())))
        else:
            replies.append(("err", json.loads(reply.err.payload.to_bytes())))

    session.get(key, zenoh.handlers.Callback(on_reply, finished.set), payload=payload, timeout=timeout_s)
    assert finished.wait(timeout_s + 1)
    return replies


def test_unknown_verbs_and_wildcards_never_run_a_verb(server: zenoh.Session, endpoint: str) -> None:
    hero = FakeHero()
    keys = robot_keys("r1")
    with DriverNode(hero, server), open_session(connect=[endpoint]) as session:
        assert wait_until(lambda: bool(ask(session, keys.rpc("noop"), b'{"v":1}')), 5.0)
        [(kind, reply)] = ask(session, keys.rpc("fly"), b'{"v":1}')
        assert (kind, reply["code"], reply["v"]) == ("err", UNKNOWN_VERB, 1)
        [(kind, reply)] = ask(session, keys.rpc("move/now"), b'{"v":1}')
        assert reply["code"] == UNKNOWN_VERB
        wildcard = ask(session, keys.rpc("*"), BY_NAME["move"].encode_request(MoveRequest((Pose(99, 99, 0),))))
        assert [(k, r["code"]) for k, r in wildcard] == [("err", BAD_REQUEST)]
        assert hero.pose == Pose(30, 30, 0)  # nothing moved


def test_closing_the_node_makes_the_client_unavailable(server: zenoh.Session, endpoint: str) -> None:
    node, client = served(SlowHero(), server, endpoint)
    with client:
        moving = client.move([Pose(40, 30, 0)])
        node.close()
        assert client.wait_gone(2.0)
        assert error_of(moving).code == UNAVAILABLE
        assert error_of(client.noop()).code == UNAVAILABLE
        with pytest.raises(DriverError, match=UNAVAILABLE):
            client.state()
    assert error_of(client.noop()).code == UNAVAILABLE  # closed client
