"""The Foxglove WebSocket protocol under both its names, decided from a client's opening
handshake.

The protocol was published as ``foxglove.websocket.v1`` (the ws-protocol spec, the
Foxglove and Lichtblick builds of its time, ``foxglove_bridge`` before 3.0); the Foxglove
SDK's server names the same protocol ``foxglove.sdk.v1`` and answers any client that
does not offer that name with HTTP 400. No version of the SDK and no option of its
server accepts the first name, so the live view reads each client's opening handshake
itself (:mod:`recording.live_server`) and this module says what to do with it: pass it
on, pass it on under the SDK's name and give the client back the name it asked for, or
refuse it with a reason. Pure functions on the HTTP heads, so each case is tested
without a socket.
"""

from __future__ import annotations

import struct
from dataclasses import dataclass

SDK = "foxglove.sdk.v1"
"""The name the Foxglove SDK's server accepts (newer SDKs also accept later
``foxglove.sdk.*`` revisions, which a client offering them gets unchanged)."""
SPEC = "foxglove.websocket.v1"
"""The name in the published ws-protocol spec: the same messages as :data:`SDK`."""
ACCEPTED = (SDK, SPEC)
HEAD_LIMIT = 16384
"""Bytes an opening handshake may take (a browser's is under 2 KiB): past it the client
is refused rather than read without end."""
_PROTOCOL_HEADER = b"sec-websocket-protocol"
_END = b"\r\n\r\n"


@dataclass(frozen=True)
class Opening:
    """What to do with one client's opening handshake: ``request`` is the head to send
    on to the SDK's server (None: refuse the client, for ``reason``); ``renamed``: the
    client asked for :data:`SPEC`, so the server's answer must name it again."""

    offered: tuple[str, ...]
    request: bytes | None
    renamed: bool = False
    reason: str = ""


def offered(head: bytes) -> tuple[str, ...]:
    """The subprotocols a request offers, in its order (every ``Sec-WebSocket-Protocol``
    header, each a comma-separated list; header names are case-insensitive)."""
    names: list[str] = []
    for line in head.split(b"\r\n")[1:]:
        field, colon, value = line.partition(b":")
        if colon and field.strip().lower() == _PROTOCOL_HEADER:
            names += [name.strip() for name in value.decode("latin-1").split(",") if name.strip()]
    return tuple(names)


def opening(head: bytes) -> Opening:
    """Pass a client offering an SDK name on unchanged (the SDK chooses among them);
    one offering only :data:`SPEC` under :data:`SDK`; refuse any other."""
    names = offered(head)
    if not head.endswith(_END) or len(head) > HEAD_LIMIT:
        return Opening(names, None, reason=f"its opening handshake is not an HTTP head of at most {HEAD_LIMIT} bytes")
    if any(name.startswith("foxglove.sdk.") for name in names):
        return Opening(names, head)
    if SPEC in names:
        lines = [line for line in head[:-len(_END)].split(b"\r\n")
                 if line.partition(b":")[0].strip().lower() != _PROTOCOL_HEADER]
        return Opening(names, b"\r\n".join([*lines, f"Sec-WebSocket-Protocol: {SDK}".encode()]) + _END, renamed=True)
    said = ", ".join(names) if names else "no subprotocol"
    return Opening(names, None, reason=f"it offered {said}; this server speaks {SDK} or {SPEC} "
                                       "(the Foxglove WebSocket protocol, docs/recording.md)")


def answer(response: bytes, renamed: bool) -> bytes:
    """The SDK server's response head as the client is to see it: with ``renamed``, its
    ``Sec-WebSocket-Protocol: foxglove.sdk.v1`` names :data:`SPEC` instead (a client
    must get back a name it offered, or it fails the connection)."""
    if not renamed:
        return response
    def named(line: bytes) -> bytes:
        field, _, value = line.partition(b":")
        if field.strip().lower() == _PROTOCOL_HEADER and value.strip() == SDK.encode():
            return f"Sec-WebSocket-Protocol: {SPEC}".encode()
        return line

    return b"\r\n".join(named(line) for line in response.split(b"\r\n"))


def accepted(response: bytes) -> bool:
    """Whether a response head switches protocols (HTTP 101)."""
    status = response.split(b"\r\n", 1)[0].split()
    return len(status) >= 2 and status[1] == b"101"


def refusal(reason: str) -> bytes:
    """An HTTP 400 whose body says why (a client shows it, or at least its status)."""
    body = f"csl live view: refused: {reason}\n".encode()
    return (b"HTTP/1.1 400 Bad Request\r\nContent-Type: text/plain; charset=utf-8\r\n"
            + f"Content-Length: {len(body)}\r\nConnection: close\r\n\r\n".encode() + body)


GOING_AWAY = 1001
"""The close code sent when the episode ends (RFC 6455: the server is going away)."""
EPISODE_OVER = "the episode is over"


def close_frame(code: int = GOING_AWAY, reason: str = EPISODE_OVER) -> bytes:
    """A server's (unmasked) close frame with a status code and reason: the SDK's own
    carries neither, which a client reports as 1005, no status received."""
    payload = struct.pack(">H", code) + reason.encode()
    if len(payload) > 125:
        raise ValueError("a close frame's payload is at most 125 bytes")
    return bytes([0x88, len(payload)]) + payload
