"""One place that turns endpoint lists into a :class:`zenoh.Config`.

The driver link runs in peer mode with multicast scouting off: a driver node listens
on explicit endpoints and clients connect to them, so nothing is discovered by
accident on a shared network and tests on 127.0.0.1 can run side by side on their
own ports. The lease is short so that a driver that vanishes without closing its
socket (power cut, cable pulled) is noticed in about a second, and reconnection is
retried quickly so that a restarted driver is picked up again within a fraction of a
second.
"""

from __future__ import annotations

import json
from collections.abc import Sequence

import zenoh

DEFAULT_ENDPOINT = "tcp/127.0.0.1:7447"
LEASE_MS = 1000  # a silent peer is dropped after this; keep-alives go 4x as often
RETRY_PERIOD_MS = (100, 500)  # first and longest wait between reconnection attempts


def check_endpoint(endpoint: str) -> str:
    """Return ``endpoint`` if it looks like a zenoh locator (``proto/address``)."""
    protocol, _, address = endpoint.partition("/")
    if not protocol or not address or not protocol.isalnum():
        raise ValueError(f"endpoint {endpoint!r} must look like tcp/HOST:PORT")
    _, colon, port = address.rpartition(":")
    if protocol in ("tcp", "udp", "tls", "quic") and (not colon or not port.isdigit() or not 0 < int(port) < 65536):
        raise ValueError(f"endpoint {endpoint!r}: the port must be a number from 1 to 65535")
    return endpoint


def make_config(listen: Sequence[str] = (), connect: Sequence[str] = ()) -> zenoh.Config:
    """A peer-mode config listening on ``listen`` and connecting to ``connect``.

    An empty ``listen`` really listens nowhere (zenoh's peer default would open a
    random port on every interface).
    """
    config = zenoh.Config()
    config.insert_json5("mode", '"peer"')
    config.insert_json5("scouting/multicast/enabled", "false")
    # Nothing to wait for without multicast: open returns at once.
    config.insert_json5("scouting/delay", "0")
    config.insert_json5("listen/endpoints", json.dumps([check_endpoint(e) for e in listen]))
    config.insert_json5("connect/endpoints", json.dumps([check_endpoint(e) for e in connect]))
    first_ms, longest_ms = RETRY_PERIOD_MS
    config.insert_json5(
        "connect/retry",
        json.dumps({"period_init_ms": first_ms, "period_max_ms": longest_ms,
                    "period_increase_factor": 2}),
    )
    config.insert_json5("transport/link/tx/lease", str(LEASE_MS))
    return config


def open_session(listen: Sequence[str] = (), connect: Sequence[str] = ()) -> zenoh.Session:
    """Open a session with :func:`make_config`; OSError with a one-line reason when an
    endpoint cannot be used (port taken, unknown protocol)."""
    try:
        return zenoh.open(make_config(listen=listen, connect=connect))
    except zenoh.ZError as exc:
        reason = str(exc).split(" at /")[0]  # drop zenoh's source locations
        raise OSError(f"zenoh session on {', '.join([*listen, *connect])}: {reason}") from None
