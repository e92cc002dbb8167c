"""One place that turns endpoint lists into a :class:`zenoh.Config` and a session.

Peer mode with multicast scouting off: a server listens on explicit endpoints and
clients connect to them, so nothing is discovered by accident on a shared network
and tests on 127.0.0.1 run side by side on their own ports. The lease is short so
that a peer that vanishes without closing its socket (power cut, cable pulled, a
killed process) is noticed in about a second, and reconnection is retried quickly
so that a restarted server is picked up again within a fraction of a second.
"""

from __future__ import annotations

import json
from collections.abc import Sequence

import zenoh

from zenoh_rpc.endpoints import check_endpoint

LEASE_MS = 1000  # a silent peer is dropped after this; keep-alives go 4x as often
RETRY_PERIOD_MS = (100, 500)  # first and longest wait between connection attempts


def make_config(listen: Sequence[str] = (), connect: Sequence[str] = (),
                connect_timeout_s: float | None = None) -> zenoh.Config:
    """A peer-mode config listening on ``listen`` and connecting to ``connect``.

    An empty ``listen`` really listens nowhere (zenoh's peer default would open a
    random port on every interface). With ``connect_timeout_s``, opening the session
    waits until one ``connect`` endpoint is reached and fails after that many
    seconds: a client that must not wait forever for a server that is not there.
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

    Raises ConnectionError (an OSError) with a one-line reason when an endpoint
    cannot be listened on (port taken, unknown protocol) or, with
    ``connect_timeout_s``, none can be reached in time: command lines report it as
    one line, and zenoh's source locations would only bury the reason.
    """
    try:
        return zenoh.open(make_config(listen, connect, connect_timeout_s))
    except zenoh.ZError as exc:
        reason = str(exc).split(" at /")[0]
        raise ConnectionError(f"zenoh session on {', '.join([*listen, *connect])}: {reason}") from None
