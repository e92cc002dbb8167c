"""The zenoh link between real processes: ``csl driver sim`` serving the simulated
HERO, a client in the test process, bad requests, clean shutdown, and the swap of one
driver process for another under the same robot name."""

from __future__ import annotations

import json
import signal
from collections.abc import Iterator

import numpy as np
import pytest

from hero_driver.interface import (
    BAD_REQUEST,
    NO_TARGET,
    OUT_OF_RANGE,
    UNAVAILABLE,
    UNKNOWN_PROCEDURE,
    UNKNOWN_VERB,
    DriverError,
    Pose,
)
from hero_driver.zenoh_link.client import ZenohDriver
from hero_driver.zenoh_link.keys import robot_keys
from tests.hero_driver.test_zenoh_node import ask, error_of
from tests.hero_driver.test_zenoh_support import DriverProcess
from tests.zenoh_rpc.support import free_endpoint, wait_until
from zenoh_rpc.config import open_session

pytestmark = pytest.mark.zenoh

REPLY_S = 10.0
NOTICE_S = 2.0  # the client must notice a vanished driver this fast
START_S = 20.0


@pytest.fixture(scope="module")
def sim() -> Iterator[tuple[str, DriverProcess]]:
    endpoint = free_endpoint()
    with DriverProcess.sim(endpoint, robot="lab1") as process:
        process.ready()
        yield endpoint, process


@pytest.fixture
def client(sim: tuple[str, DriverProcess]) -> Iterator[ZenohDriver]:
    with ZenohDriver("lab1", connect=[sim[0]], discover_s=START_S) as driver:
        assert driver.wait_ready(START_S)
        yield driver


def test_simulated_hero_answers_every_verb(client: ZenohDriver) -> None:
    start = client.reset(seed=1).result(REPLY_S)
    assert start.clock_s == 0 and 0 <= start.battery <= 1
    image = client.camera().result(REPLY_S)
    assert image.pixels.dtype == np.uint8 and image.pixels.ndim == 2
    assert image.inches_per_pixel > 0
    # The lab's soda bottle stands at (120, 45): drive to face it from 30 in away.
    moved = client.move([Pose(60, 45, 0), Pose(80, 45, 0)], face=(120, 45)).result(REPLY_S)
    assert not moved.collided and moved.duration_s > 0
    sensed = client.sense("H-Sweep-5°").result(REPLY_S)
    assert sensed.procedure == "H-Sweep-5°" and set(sensed.values) == {"Width-Degree-5°"}
    assert sensed.distance_in > 6
    refused = error_of(client.grasp("Front-Pinch"))  # contact range only
    assert refused.code in (OUT_OF_RANGE, NO_TARGET)
    assert error_of(client.sense("No-Such-Procedure")).code == UNKNOWN_PROCEDURE
    released = client.release().result(REPLY_S)
    assert released.clock_s >= moved.duration_s + sensed.duration_s
    assert wait_until(lambda: client.state().clock_s == released.clock_s, 2.0)
    assert client.noop().result(REPLY_S) is None


def test_bad_requests_get_error_replies_and_the_node_serves_on(sim: tuple[str, DriverProcess],
                                                               client: ZenohDriver) -> None:
    keys = robot_keys("lab1")
    with open_session(connect=[sim[0]]) as session:
        assert wait_until(lambda: bool(ask(session, keys.rpc("noop"), b'{"v":1}')), START_S)
        bad = {
            "fly": (b'{"v":1}', UNKNOWN_VERB),
            "sense": (b'{"v":1,"procedure":', BAD_REQUEST),
            "move": (b'{"v":1,"waypoints":[{"x_in":"far","y_in":0,"heading_deg":0}]}', BAD_REQUEST),
            "reset": (json.dumps({"v": 7}).encode(), BAD_REQUEST),
            "grasp": (b'{"v":1,"procedure":"Front-Pinch","force":9}', BAD_REQUEST),
        }
        for verb, (payload, code) in bad.items():
            [(kind, reply)] = ask(session, keys.rpc(verb), payload)
            assert (kind, reply["v"], reply["code"]) == ("err", 1, code), verb
            assert reply["message"]
    assert client.noop().result(REPLY_S) is None
    assert client.reset().result(REPLY_S).clock_s == 0


@pytest.mark.slow
def test_the_swap_one_client_two_driver_processes_in_turn() -> None:
    endpoint = free_endpoint()
    with DriverProcess.sim(endpoint, robot="swap") as first:
        first.ready()
        with ZenohDriver("swap", connect=[endpoint], discover_s=START_S) as client:
            assert client.wait_ready(START_S)
            client.move([Pose(60, 30, 0)]).result(REPLY_S)
            assert wait_until(lambda: client.state().pose.x_in > 50, 2.0)

            first.kill()  # no goodbye: the token vanishes with the connection
            assert client.wait_gone(NOTICE_S)
            assert error_of(client.noop()).code == UNAVAILABLE  # at once, not after a timeout
            with pytest.raises(DriverError, match=UNAVAILABLE):
                client.state()

            with DriverProcess.sim(endpoint, robot="swap") as second:
                second.ready()
                assert client.wait_ready(START_S)
                assert client.alive
                assert client.state().pose.x_in == 30  # the new process's own state
                assert client.reset().result(REPLY_S).clock_s == 0
                assert client.move([Pose(45, 30, 0)]).result(REPLY_S).pose.x_in > 40
                assert client.noop().result(REPLY_S) is None


@pytest.mark.parametrize("signum", [signal.SIGTERM, signal.SIGINT])
def test_a_signal_shuts_the_driver_down_cleanly(signum: int) -> None:
    endpoint = free_endpoint()
    with DriverProcess.sim(endpoint, robot="term") as process:
        process.ready()
        with ZenohDriver("term", connect=[endpoint], discover_s=START_S) as client:
            assert client.wait_ready(START_S)
            assert process.stop(signum) == 0
            assert client.wait_gone(NOTICE_S)
        assert "driver term stopped" in process.process.stderr.read()


def test_a_frozen_driver_is_noticed_by_its_lease() -> None:
    """A driver that stops answering without closing its socket (a hung process, a
    pulled cable) is dropped when its zenoh lease runs out."""
    endpoint = free_endpoint()
    with DriverProcess.fake("good", endpoint, robot="frozen") as process:
        process.ready()
        with ZenohDriver("frozen", connect=[endpoint], discover_s=START_S) as client:
            assert client.wait_ready(START_S)
            process.process.send_signal(signal.SIGSTOP)
            try:
                assert client.wait_gone(NOTICE_S)
                assert error_of(client.noop()).code == UNAVAILABLE
            finally:
                process.process.send_signal(signal.SIGCONT)
