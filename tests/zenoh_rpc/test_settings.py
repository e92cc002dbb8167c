"""Endpoints, key spaces and session configuration: the values both services rely on."""

from __future__ import annotations

import json
import socket

import pytest

from tests.zenoh_rpc.support import free_endpoint
from zenoh_rpc.config import make_config, open_session
from zenoh_rpc.endpoints import DRIVER_ENDPOINT, LEARNER_ENDPOINT, check_endpoint
from zenoh_rpc.keys import KeySpace


def test_the_two_services_default_to_neighbouring_ports_on_one_machine() -> None:
    assert (DRIVER_ENDPOINT, LEARNER_ENDPOINT) == ("tcp/127.0.0.1:7447", "tcp/127.0.0.1:7448")


@pytest.mark.parametrize("endpoint", ["tcp/127.0.0.1:7447", "tcp/0.0.0.0:1", "udp/10.0.0.2:65535",
                                      "serial/dev/ttyUSB0"])
def test_locators_pass_unchanged(endpoint: str) -> None:
    assert check_endpoint(endpoint) == endpoint


@pytest.mark.parametrize(("endpoint", "message"), [
    ("7448", "must look like tcp/HOST:PORT"),
    ("localhost", "must look like tcp/HOST:PORT"),
    ("tc-p/host:1", "must look like tcp/HOST:PORT"),
    ("tcp/127.0.0.1", "the port must be a number from 1 to 65535"),
    ("tcp/127.0.0.1:0", "the port must be a number from 1 to 65535"),
    ("quic/127.0.0.1:65536", "the port must be a number from 1 to 65535"),
])
def test_malformed_endpoints_are_refused_naming_them(endpoint: str, message: str) -> None:
    with pytest.raises(ValueError, match=message) as caught:
        check_endpoint(endpoint)
    assert repr(endpoint) in str(caught.value)


def test_a_key_space_derives_every_key_from_prefix_and_name() -> None:
    keys = KeySpace("csl/learner", "lab-2.b", "learner name")
    assert keys.alive == "csl/learner/lab-2.b/alive"
    assert keys.state == "csl/learner/lab-2.b/state"
    assert keys.rpc("learn") == "csl/learner/lab-2.b/rpc/learn"
    assert keys.rpc_all == "csl/learner/lab-2.b/rpc/**"


@pytest.mark.parametrize("name", ["", "r*", "a/b", "$*", "r 1", 7])
def test_a_name_that_is_not_one_key_chunk_is_refused(name: object) -> None:
    with pytest.raises(ValueError, match=r"^robot name .* must be letters, digits, '_', '-' or '\.' \(one key chunk\)$"):
        KeySpace("hero", name, "robot name")  # type: ignore[arg-type]


def test_the_config_is_peer_mode_without_scouting_with_a_one_second_lease() -> None:
    config = make_config(listen=["tcp/127.0.0.1:7000"], connect=["tcp/127.0.0.1:7001"])
    assert json.loads(config.get_json("mode")) == "peer"
    assert json.loads(config.get_json("scouting/multicast/enabled")) is False
    assert json.loads(config.get_json("listen/endpoints")) == ["tcp/127.0.0.1:7000"]
    assert json.loads(config.get_json("connect/endpoints")) == ["tcp/127.0.0.1:7001"]
    assert json.loads(config.get_json("transport/link/tx/lease")) == 1000
    assert json.loads(config.get_json("transport/unicast/open_timeout")) == 1000  # close waits on it (SIGSTOP)
    assert json.loads(config.get_json("connect/retry")) == {
        "period_init_ms": 100, "period_max_ms": 500, "period_increase_factor": 2.0}


def test_a_connect_timeout_is_rounded_to_milliseconds_and_fails_the_open() -> None:
    config = make_config(connect=["tcp/127.0.0.1:7001"], connect_timeout_s=0.2504)
    assert json.loads(config.get_json("connect/timeout_ms")) == 250
    assert json.loads(config.get_json("connect/exit_on_failure")) is True


def test_a_bad_endpoint_is_refused_before_zenoh_sees_it() -> None:
    with pytest.raises(ValueError, match="'nowhere' must look like"):
        make_config(listen=["nowhere"])


@pytest.mark.zenoh
def test_a_taken_port_is_a_one_line_connection_error() -> None:
    endpoint = free_endpoint()
    with socket.socket(socket.AF_INET, socket.SOCK_STREAM) as squatter:
        squatter.bind(("127.0.0.1", int(endpoint.rsplit(":", 1)[1])))
        squatter.listen()
        with pytest.raises(ConnectionError) as caught:
            open_session(listen=[endpoint])
    text = str(caught.value)
    assert text.startswith(f"zenoh session on {endpoint}: ") and "\n" not in text and " at /" not in text


@pytest.mark.zenoh
def test_nothing_to_connect_to_fails_within_the_connect_timeout() -> None:
    with pytest.raises(ConnectionError, match="zenoh session on tcp/127.0.0.1:"):
        open_session(connect=[free_endpoint()], connect_timeout_s=0.3)


def test_a_server_receives_no_message_beyond_its_cap_and_a_client_keeps_zenohs_gigabyte() -> None:
    """A server's sessions drop anything larger than its request cap plus the headers'
    room as zenoh reassembles it; a client, which receives whole libraries and images,
    keeps zenoh's default."""
    assert json.loads(make_config(max_message_bytes=320 * 1024).get_json("transport/link/rx/max_message_size")) \
        == 320 * 1024
    assert json.loads(make_config().get_json("transport/link/rx/max_message_size")) == 1 << 30
