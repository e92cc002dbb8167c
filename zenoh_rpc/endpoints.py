"""Endpoint syntax and the default endpoints of our two services.

The defaults are one decision, made here: the driver node listens on port 7447
(zenoh's registered port, which a driver on a robot's own computer is expected to
use) and the learner service on 7448, the next one. Two services, two ports, so a
simulated robot and a shared library can both run on one machine (a laptop, CI)
without either being told where to go; a client must still be pointed at the one
it wants, because each listens on its own endpoint and neither scouts.
"""

from __future__ import annotations

DRIVER_ENDPOINT = "tcp/127.0.0.1:7447"
LEARNER_ENDPOINT = "tcp/127.0.0.1:7448"

LISTEN_KEY = "listen/endpoints"
CONNECT_KEY = "connect/endpoints"
"""Where a zenoh config holds a session's endpoints: a user's zenoh config file that
sets one of them wins over our flags (docs/security.md)."""

_PORTED = ("tcp", "udp", "tls", "quic")


def check_endpoint(endpoint: str) -> str:
    """Return ``endpoint`` if it looks like a zenoh locator (``proto/address``).

    Checked before zenoh sees it, so a typo on a command line is a one-line error
    naming the endpoint rather than zenoh's parse failure deep in session start-up.
    """
    protocol, _, address = endpoint.partition("/")
    if not protocol or not address or not protocol.isalnum():
        raise ValueError(f"endpoint {endpoint!r} must look like tcp/HOST:PORT")
    _, colon, port = address.rpartition(":")
    if protocol in _PORTED and (not colon or not port.isdigit() or not 0 < int(port) < 65536):
        raise ValueError(f"endpoint {endpoint!r}: the port must be a number from 1 to 65535")
    return endpoint
