"""The live view: the same channels served by the Foxglove SDK's WebSocket server, seen
by a WebSocket client as Foxglove would see them."""

from __future__ import annotations

import json
import struct
import threading
from pathlib import Path

import pytest

from recording import topics
from tests.executive.test_recording import record_episode
from tests.executive.ws_client import MESSAGE_DATA, FoxgloveClient


@pytest.mark.slow
def test_a_client_sees_every_channel_and_the_episode_as_it_runs(tmp_path: Path) -> None:
    ready = threading.Event()
    seen: dict[str, object] = {}

    def watch(port: int) -> None:
        client = FoxgloveClient(port)
        seen["protocol"] = client.protocol
        channels: dict[str, dict] = {}
        while len(channels) < len(topics.ALL):
            message = client.receive()
            if isinstance(message, str) and json.loads(message)["op"] == "advertise":
                channels.update({c["topic"]: c for c in json.loads(message)["channels"]})
        seen["channels"] = channels
        wanted = {1: topics.STATUS.name, 2: topics.EVENTS.name, 3: topics.PATHS.name}
        client.send_json({"op": "subscribe", "subscriptions": [
            {"id": sub, "channelId": channels[topic]["id"]} for sub, topic in wanted.items()]})
        received: dict[str, list[tuple[int, bytes]]] = {topic: [] for topic in wanted.values()}
        ready.set()
        while True:
            message = client.receive()
            if isinstance(message, bytes) and message[0] == MESSAGE_DATA:
                sub, log_time = struct.unpack_from("<IQ", message, 1)
                received[wanted[sub]].append((log_time, message[13:]))
                if wanted[sub] == topics.EVENTS.name and json.loads(message[13:])["event"] == "episode_end":
                    break
        seen["received"] = received
        client.close()

    watcher: list[threading.Thread] = []

    def start_watching(recording) -> None:  # noqa: ANN001
        assert recording.live_port  # the free port the server took for 0
        watcher.append(threading.Thread(target=watch, args=(recording.live_port,), daemon=True))
        watcher[0].start()
        assert recording.wait_for_viewer(10.0), "the client's subscribe reaches the server's listener"
        assert ready.wait(10.0)

    result, log, recording = record_episode(tmp_path, live_port=0, before_run=start_watching)
    watcher[0].join(30.0)
    recording.close()
    assert not watcher[0].is_alive()
    assert seen["protocol"] in ("foxglove.sdk.v1", "foxglove.websocket.v1")
    channels = seen["channels"]
    assert {topic: (c["schemaName"], c["encoding"]) for topic, c in channels.items()} == {  # type: ignore[union-attr]
        t.name: (t.schema, "json" if t.schema.startswith("csl.") else "protobuf") for t in topics.ALL}
    received = seen["received"]
    events = [json.loads(data) for _, data in received[topics.EVENTS.name]]  # type: ignore[index]
    assert events == log.events
    statuses = [json.loads(data) for _, data in received[topics.STATUS.name]]  # type: ignore[index]
    assert [s["tick"] for s in statuses] == list(range(1, result.ticks + 1))
    assert "{-} retrieve objects [" in statuses[0]["tree"]
    moves = [e for e in log.events if e["event"] == "move"]
    assert len(received[topics.PATHS.name]) == len(moves) > 0  # type: ignore[index]


def test_csl_run_live_waits_for_a_client_then_serves_the_episode(tmp_path: Path, capsys) -> None:  # noqa: ANN001
    from tests.executive.test_recording_cli import _run_args

    args = _run_args(tmp_path, live=True, live_port=0, live_pace=0.0)
    status: list[int] = []
    runner = threading.Thread(target=lambda: status.append(args.handler(args)), daemon=True)
    runner.start()
    err = ""
    for _ in range(2400):  # the address is printed before the wait for a client (the library
        err += capsys.readouterr().err  # is trained first: slow on a loaded machine)
        if "live view at ws://127.0.0.1:" in err or not runner.is_alive():
            break
        runner.join(0.05)
    assert "live view at ws://127.0.0.1:" in err, f"no address printed (status {status}): {err}"
    port = int(err.split("live view at ws://127.0.0.1:")[1].split()[0])
    assert not status, f"nothing runs before a client subscribes: {err}"
    client = FoxgloveClient(port)
    channels: dict[str, int] = {}
    while topics.EVENTS.name not in channels:
        message = client.receive()
        if isinstance(message, str) and json.loads(message)["op"] == "advertise":
            channels.update({c["topic"]: c["id"] for c in json.loads(message)["channels"]})
    client.send_json({"op": "subscribe", "subscriptions": [{"id": 7, "channelId": channels[topics.EVENTS.name]}]})
    kinds = []
    while not kinds or kinds[-1] != "episode_end":
        message = client.receive()
        if isinstance(message, bytes) and message[0] == MESSAGE_DATA:
            kinds.append(json.loads(message[13:])["event"])
    client.close()
    runner.join(30.0)
    assert status == [0]
    assert kinds[0] == "located" and kinds.count("learn") >= 1
