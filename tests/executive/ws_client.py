"""A Foxglove WebSocket client for the tests that watch the live view: the ``websockets``
package's client offering both names of the protocol, read one whole message at a time
(the server's ``serverInfo`` and ``advertise`` as text, message data as bytes)."""

from __future__ import annotations

import json
from contextlib import ExitStack

from websockets.exceptions import ConnectionClosed
from websockets.sync.client import connect

SUBPROTOCOLS = ["foxglove.sdk.v1", "foxglove.websocket.v1"]
MESSAGE_DATA = 0x01  # server binary opcode: subscription id (u32), log time (u64), payload


class FoxgloveClient:
    def __init__(self, port: int, host: str = "127.0.0.1", timeout_s: float = 10.0) -> None:
        self.timeout_s = timeout_s
        self._open = ExitStack()  # websockets would have its connection used as a context manager
        offered: list = SUBPROTOCOLS  # websockets types them as its Subprotocol, a str
        self._ws = self._open.enter_context(connect(f"ws://{host}:{port}", subprotocols=offered,
                                                    open_timeout=timeout_s, max_size=None))
        self.protocol = self._ws.subprotocol or ""

    def send_json(self, message: dict) -> None:
        self._ws.send(json.dumps(message))

    def receive(self) -> str | bytes:
        """The next whole text (str) or binary (bytes) message."""
        try:
            return self._ws.recv(self.timeout_s)
        except ConnectionClosed as exc:
            raise ConnectionError("the server closed the WebSocket") from exc

    def close(self) -> None:
        self._open.close()
