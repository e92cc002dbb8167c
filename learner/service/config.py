"""The zenoh configuration of the learner service and its clients.

Peer mode with multicast scouting off: the service listens on explicit endpoints and
robots connect to them, so nothing on a shared network is joined by accident and
tests on 127.0.0.1 run side by side on their own ports. The lease is short so that a
service killed without closing its socket stops being routed to within about a
second. A client opens its session only once it is connected: a robot pointed at a
service that is not there is told so within its timeout instead of waiting forever.
"""

from __future__ import annotations

import json
from collections.abc import Sequence

import zenoh

DEFAULT_ENDPOINT = "tcp/127.0.0.1:7448"
LEASE_MS = 1000  # a silent peer is dropped after this
RETRY_PERIOD_MS = (100, 500)  # first and longest wait between connection attempts


def check_endpoint(endpoint: str) -> str:
    """Return ``endpoint`` if it looks like a zenoh locator (``proto/address``)."""
    protocol, _, address = endpoint.partition("/")
    if not protocol or not address or not protocol.isalnum():
        raise ValueError(f"endpoint {endpoint!r} must look like tcp/HOST:PORT")
    _, colon, port = address.rpartition(":")
    if protocol in ("tcp", "udp", "tls", "quic") and (not colon or not port.isdigit() or not 0 < int(port) < 65536):
        raise ValueError(f"endpoint {endpoint!r}: the port must be a number from 1 to 65535")
    return endpoint


def make_config(listen: Sequence[str] = (), connect: Sequence[str] = (),
                connect_timeout_s: float | None = None) -> zenoh.Config:
    """A peer-mode config listening on ``listen`` and connecting to ``connect``.

    An empty ``listen`` listens nowhere (zenoh's peer default would open a random
    port on every interface). With ``connect_timeout_s``, opening the session waits
    until one ``connect`` endpoint is reached and fails after that many seconds.
    """
    config = zenoh.Config()
    config.insert_json5("mode", '"peer"')
    config.insert_json5("scouting/multicast/enabled", "false")
    config.insert_json5("scouting/delay", "0")  # nothing to wait for without multicast
    config.insert_json5("listen/endpoints", json.dumps([check_endpoint(e) for e in listen]))
    config.insert_json5("connect/endpoints", json.dumps([check_endpoint(e) for e in connect]))
    first_ms, longest_ms = RETRY_PERIOD_MS
    config.insert_json5("connect/retry", json.dumps(
        {"period_init_ms": first_ms, "period_max_ms": longest_ms, "period_increase_factor": 2}))
    if connect_timeout_s is not None:
        config.insert_json5("connect/timeout_ms", str(max(1, round(connect_timeout_s * 1000))))
        config.insert_json5("connect/exit_on_failure", "true")
    config.insert_json5("transport/link/tx/lease", str(LEASE_MS))
    return config


def open_session(listen: Sequence[str] = (), connect: Sequence[str] = (),
                 connect_timeout_s: float | None = None) -> zenoh.Session:
    """Open a session with :func:`make_config`.

    Raises ConnectionError (an OSError) with a one-line reason when an endpoint cannot
    be listened on or, with ``connect_timeout_s``, none can be reached in time.
    """
    try:
        return zenoh.open(make_config(listen, connect, connect_timeout_s))
    except zenoh.ZError as exc:
        reason = str(exc).split(" at /")[0]  # drop zenoh's source location
        raise ConnectionError(f"zenoh session on {', '.join([*listen, *connect])}: {reason}") from None
