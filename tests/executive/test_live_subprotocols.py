"""The live view for every Foxglove: a client offering either name of the Foxglove
WebSocket protocol (``foxglove.sdk.v1``, ``foxglove.websocket.v1``) connects and is
advertised the channels; any other is refused with a reason, on both sides; every
viewer gets a close frame saying the episode is over. Real WebSocket clients (the
``websockets`` package) on 127.0.0.1, no zenoh."""

from __future__ import annotations

import json
import logging
import socket
import struct
import threading
from collections.abc import Iterator
from pathlib import Path

import pytest
from websockets.exceptions import ConnectionClosedOK, InvalidStatus
from websockets.sync.client import ClientConnection, connect

from recording import handshake, topics

RECEIVE_S = 30.0  # a bound on a wait that would otherwise hang a broken test, not a timing assertion
REQUEST = (b"GET / HTTP/1.1\r\nHost: 127.0.0.1:8765\r\nUpgrade: websocket\r\nConnection: Upgrade\r\n"
           b"Sec-WebSocket-Key: dGhlIHNhbXBsZSBub25jZQ==\r\nSec-WebSocket-Version: 13\r\n")


def _request(*protocol_lines: str) -> bytes:
    return REQUEST + b"".join(f"{line}\r\n".encode() for line in protocol_lines) + b"\r\n"


# -- the handshake, decided without a socket -------------------------------------------

def test_the_offered_subprotocols_are_read_from_every_header_in_order() -> None:
    head = _request("Sec-WebSocket-Protocol: foxglove.sdk.v1 , foxglove.websocket.v1",
                    "sec-websocket-protocol:mqtt")
    assert handshake.offered(head) == ("foxglove.sdk.v1", "foxglove.websocket.v1", "mqtt")
    assert handshake.offered(_request()) == ()


@pytest.mark.parametrize("line", [
    "Sec-WebSocket-Protocol: foxglove.sdk.v1",
    "Sec-WebSocket-Protocol: foxglove.websocket.v1, foxglove.sdk.v1",
    "Sec-WebSocket-Protocol: foxglove.sdk.v1.1",  # a later SDK revision: the SDK decides
])
def test_a_client_offering_an_sdk_name_is_passed_on_unchanged(line: str) -> None:
    head = _request(line)
    assert handshake.opening(head) == handshake.Opening(handshake.offered(head), head)


def test_a_client_offering_only_the_spec_name_is_passed_on_under_the_sdk_name() -> None:
    opened = handshake.opening(_request("Sec-WebSocket-Protocol: mqtt, foxglove.websocket.v1", "Origin: x"))
    assert opened.renamed and opened.offered == ("mqtt", "foxglove.websocket.v1")
    assert opened.request == REQUEST + b"Origin: x\r\nSec-WebSocket-Protocol: foxglove.sdk.v1\r\n\r\n"


def test_the_sdk_answer_names_the_spec_name_again_for_a_renamed_client() -> None:
    response = (b"HTTP/1.1 101 Switching Protocols\r\nConnection: Upgrade\r\nUpgrade: websocket\r\n"
                b"sec-websocket-protocol: foxglove.sdk.v1\r\n"
                b"Sec-WebSocket-Accept: s3pPLMBiTxaQ9kYGzzhZRbK+xOo=\r\n\r\n")
    assert handshake.answer(response, renamed=True) == response.replace(
        b"sec-websocket-protocol: foxglove.sdk.v1", b"Sec-WebSocket-Protocol: foxglove.websocket.v1")
    assert handshake.answer(response, renamed=False) == response
    assert handshake.accepted(response)
    assert not handshake.accepted(b"HTTP/1.1 400 Bad Request\r\n\r\n") and not handshake.accepted(b"")


@pytest.mark.parametrize(("lines", "said"), [
    ((), "it offered no subprotocol;"),
    (("Sec-WebSocket-Protocol: mqtt, foxglove.websocket.v2",), "it offered mqtt, foxglove.websocket.v2;"),
])
def test_any_other_client_is_refused_with_the_names_that_work(lines: tuple[str, ...], said: str) -> None:
    opened = handshake.opening(_request(*lines))
    assert opened.request is None
    assert opened.reason.startswith(said)
    assert "foxglove.sdk.v1 or foxglove.websocket.v1" in opened.reason
    body = f"csl live view: refused: {opened.reason}\n".encode()
    assert handshake.refusal(opened.reason) == (
        b"HTTP/1.1 400 Bad Request\r\nContent-Type: text/plain; charset=utf-8\r\n"
        + f"Content-Length: {len(body)}\r\nConnection: close\r\n\r\n".encode() + body)


def test_an_unfinished_or_oversized_head_is_refused() -> None:
    assert handshake.opening(_request("Sec-WebSocket-Protocol: foxglove.sdk.v1")[:-2]).request is None
    huge = _request("Sec-WebSocket-Protocol: foxglove.sdk.v1", "X-Pad: " + "a" * handshake.HEAD_LIMIT)
    assert handshake.opening(huge).request is None


def test_the_close_frame_carries_going_away_and_the_reason() -> None:
    # FIN + close opcode; unmasked; 2 bytes of code + 19 of reason; 1001 = 0x03E9
    assert handshake.close_frame() == b"\x88\x15\x03\xe9the episode is over"
    with pytest.raises(ValueError):
        handshake.close_frame(reason="x" * 124)


# -- a recording's live view, through real WebSocket clients ----------------------------

@pytest.fixture
def live(tmp_path: Path) -> Iterator[object]:
    from recording.session import Recording
    from robot_profile import load_profile

    recording = Recording(load_profile().robot.geometry, live_port=0)
    try:
        yield recording
    finally:
        recording.close()


def _client(port: int, *offered: str) -> ClientConnection:
    return connect(f"ws://127.0.0.1:{port}", subprotocols=list(offered),  # type: ignore[arg-type]
                   open_timeout=RECEIVE_S, max_size=None)


def _advertised(client: ClientConnection, wanted: int) -> dict[str, dict]:
    """The channels the server advertises, by topic (serverInfo comes first)."""
    info = json.loads(client.recv(RECEIVE_S))
    assert info["op"] == "serverInfo" and info["name"] == "csl-executive"
    channels: dict[str, dict] = {}
    while len(channels) < wanted:
        message = json.loads(client.recv(RECEIVE_S))
        assert message["op"] == "advertise"
        channels.update({channel["topic"]: channel for channel in message["channels"]})
    return channels


@pytest.mark.parametrize("offered", ["foxglove.sdk.v1", "foxglove.websocket.v1"])
def test_a_client_offering_either_name_is_advertised_every_channel(live, offered: str) -> None:  # noqa: ANN001
    with _client(live.live_port, offered) as client:
        assert client.subprotocol == offered
        channels = _advertised(client, len(topics.ALL))
    assert {topic: c["schemaName"] for topic, c in channels.items()} == {t.name: t.schema for t in topics.ALL}


def test_a_client_offering_both_names_gets_the_sdk_name(live) -> None:  # noqa: ANN001
    with _client(live.live_port, "foxglove.websocket.v1", "foxglove.sdk.v1") as client:
        assert client.subprotocol == "foxglove.sdk.v1"
        assert set(_advertised(client, len(topics.ALL))) == {t.name for t in topics.ALL}


def test_a_client_offering_neither_is_told_why_and_so_is_our_log(live, caplog) -> None:  # noqa: ANN001
    with caplog.at_level(logging.WARNING, logger="recording.live_server"):
        with pytest.raises(InvalidStatus) as refused:
            _client(live.live_port, "foxglove.websocket.v2")
        with _client(live.live_port, "foxglove.sdk.v1") as client:  # a refusal harms nobody else
            assert client.subprotocol == "foxglove.sdk.v1"
    assert refused.value.response.status_code == 400
    assert refused.value.response.body.decode().startswith(
        "csl live view: refused: it offered foxglove.websocket.v2; this server speaks foxglove.sdk.v1 or "
        "foxglove.websocket.v1")
    [line] = [r.getMessage() for r in caplog.records if r.name == "recording.live_server"]
    assert line.startswith("live view: refused a client at 127.0.0.1:")
    assert line.endswith("it offered foxglove.websocket.v2; this server speaks foxglove.sdk.v1 or "
                         "foxglove.websocket.v1 (the Foxglove WebSocket protocol, docs/recording.md)")


@pytest.mark.parametrize("offered", ["foxglove.sdk.v1", "foxglove.websocket.v1"])
def test_every_viewer_gets_a_close_frame_when_the_recording_closes(live, offered: str) -> None:  # noqa: ANN001
    port = live.live_port
    with _client(port, offered) as first, _client(port, offered) as second:
        for client in (first, second):
            _advertised(client, len(topics.ALL))
        live.close()
        for client in (first, second):
            with pytest.raises(ConnectionClosedOK) as closed:
                while True:
                    client.recv(RECEIVE_S)
            assert closed.value.rcvd is not None
            assert (closed.value.rcvd.code, closed.value.rcvd.reason) == (1001, "the episode is over")
    with pytest.raises(ConnectionRefusedError):  # and no one else is let in
        socket.create_connection(("127.0.0.1", port), timeout=RECEIVE_S)


def test_a_port_in_use_is_refused_with_the_systems_reason() -> None:
    from recording.session import Recording
    from robot_profile import load_profile

    with socket.create_server(("127.0.0.1", 0)) as taken:
        with pytest.raises(RuntimeError, match="Address already in use"):
            Recording(load_profile().robot.geometry, live_port=taken.getsockname()[1])


# -- the relay passes every frame through unchanged --------------------------------------

class _Subscribed:
    def __init__(self) -> None:
        self.event = threading.Event()

    def on_subscribe(self, client: object, channel: object) -> None:
        self.event.set()

    def on_unsubscribe(self, client: object, channel: object) -> None:
        pass


@pytest.mark.parametrize("offered", ["foxglove.sdk.v1", "foxglove.websocket.v1"])
def test_messages_of_every_frame_length_arrive_whole(offered: str) -> None:
    import foxglove

    from recording.live_server import LiveServer

    context = foxglove.Context()
    channel = foxglove.Channel("/sizes", message_encoding="json", context=context)
    subscribed = _Subscribed()
    server = LiveServer(context, host="127.0.0.1", port=0, name="csl-executive", server_listener=subscribed)
    try:
        with _client(server.port, offered) as client:
            [advertised] = _advertised(client, 1).values()
            client.send(json.dumps({"op": "subscribe", "subscriptions": [{"id": 5, "channelId": advertised["id"]}]}))
            assert subscribed.event.wait(RECEIVE_S)
            # payloads under 126 bytes, of a 16-bit length and of a 64-bit length (RFC 6455 5.2)
            sent = [{"n": n, "pad": "x" * n} for n in (10, 300, 70_000, 1_000_000)]
            for message in sent:
                channel.log(message, log_time=7)
            received = []
            for _ in sent:
                data = client.recv(RECEIVE_S)
                assert isinstance(data, bytes) and data[0] == 0x01  # message data
                assert struct.unpack_from("<IQ", data, 1) == (5, 7)
                received.append(json.loads(data[13:]))
            assert received == sent
    finally:
        server.stop()


# -- csl run --live, start to end --------------------------------------------------------

@pytest.mark.slow
def test_csl_run_live_ends_each_viewer_with_a_close_frame_after_the_episode(tmp_path: Path,
                                                                           capsys) -> None:  # noqa: ANN001
    from tests.executive.test_recording_cli import _run_args

    args = _run_args(tmp_path, live=True, live_port=0, live_pace=0.0)
    status: list[int] = []
    runner = threading.Thread(target=lambda: status.append(args.handler(args)), daemon=True)
    runner.start()
    err = ""
    while "live view at ws://127.0.0.1:" not in err and runner.is_alive():  # printed before the wait for
        err += capsys.readouterr().err  # a client (the library is trained first: slow on a loaded machine)
        runner.join(0.05)
    assert "live view at ws://127.0.0.1:" in err, f"no address printed (status {status}): {err}"
    port = int(err.split("live view at ws://127.0.0.1:")[1].split()[0])
    with _client(port, "foxglove.websocket.v1") as client:  # as an older Foxglove or Lichtblick would
        events = _advertised(client, len(topics.ALL))[topics.EVENTS.name]
        client.send(json.dumps({"op": "subscribe", "subscriptions": [{"id": 1, "channelId": events["id"]}]}))
        kinds = []
        with pytest.raises(ConnectionClosedOK) as closed:
            while True:
                data = client.recv(RECEIVE_S)
                if isinstance(data, bytes) and data[0] == 0x01:
                    kinds.append(json.loads(data[13:])["event"])
    runner.join(RECEIVE_S)
    assert status == [0]
    assert kinds[0] == "located" and kinds[-1] == "episode_end"
    assert closed.value.rcvd is not None
    assert (closed.value.rcvd.code, closed.value.rcvd.reason) == (1001, "the episode is over")
