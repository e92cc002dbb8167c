"""``--zenoh-config FILE`` and ``CSL_ZENOH_CONFIG``: how every command that opens a
zenoh session is given the user's zenoh config file (docs/security.md).

Shared by ``csl driver`` and the executive's commands; it imports nothing of either,
so the driver side stays usable on a robot's own computer.
"""

from __future__ import annotations

import argparse
import ipaddress
import json
import os
from pathlib import Path
from typing import TYPE_CHECKING

from zenoh_rpc.endpoints import CONNECT_KEY, LISTEN_KEY

if TYPE_CHECKING:  # zenoh itself is imported only by a command that opens a session
    from zenoh_rpc.config import UserConfig

CONFIG_ENV = "CSL_ZENOH_CONFIG"


def add_zenoh_config_option(parser: argparse.ArgumentParser) -> None:
    """Add ``--zenoh-config FILE`` to a command that opens a zenoh session."""
    parser.add_argument(
        "--zenoh-config", type=Path, default=None, metavar="FILE",
        help=f"zenoh's own config file (JSON5) for user/password authentication, TLS and access "
             f"control; it wins over this command's zenoh settings wherever it sets one "
             f"(docs/security.md; default: ${CONFIG_ENV}, else none)")


def user_config(given: Path | None) -> UserConfig | None:
    """The file given with ``--zenoh-config``, else the one named by ``CSL_ZENOH_CONFIG``
    (empty counts as unset), read and checked now; None when neither names one.

    Raises ValueError naming the file and where it came from when zenoh cannot use it.
    """
    from zenoh_rpc.config import UserConfig

    if given is not None:
        return UserConfig(given, "--zenoh-config")
    named = os.environ.get(CONFIG_ENV, "")
    return UserConfig(Path(named), CONFIG_ENV) if named else None


def endpoint_of(flag: str, given: str | None, default: str, key: str, user: UserConfig | None) -> str:
    """The endpoint for ``flag`` (``given``, else ``default``).

    The user's file wins over our endpoints, so a flag typed on the command line that
    the file overrides would be silently ignored: that is refused with one line.
    """
    if given is not None and user is not None and user.sets(key):
        raise ValueError(f"{flag} {given}: {user.origin} {user.path} sets {key}, which wins over "
                         f"{flag}; give the endpoint in one place only")
    return given or default


def where(endpoint: str, key: str, user: UserConfig | None) -> str:
    """Where a session really listens or connects, for a command's one-line report."""
    if user is not None and user.sets(key):
        return f"the {key} of {user.path}"
    return endpoint


def reached_at(listen: str, user: UserConfig | None) -> str:
    """Where a node serving on ``listen`` is reached, for the line a serving command
    (``csl driver sim``, ``csl learner serve``) prints once serving: ``on`` the endpoint
    it listens on (ours, or the user's file's). A session the user's file puts in client
    mode listens nowhere, whatever ``listen`` says (everything goes through a router,
    docs/security.md): it is reached through the router it connected to, which is what
    the line must say."""
    if user is None or json.loads(user.load().get_json("mode")) != "client":
        return f"on {where(listen, LISTEN_KEY, user)}"
    routers = json.loads(user.load().get_json(CONNECT_KEY)) or ["a router found by scouting"]
    return (f"as a zenoh client connected to {' or '.join(routers)} (client mode, set by {user.path}: "
            f"it listens on nothing)")


AUTH_KEYS = ("transport/auth/usrpwd/user", "transport/auth/usrpwd/dictionary_file")
SECURE_SCHEMES = ("tls", "quic")


def open_listen_warning(listen: str, user: UserConfig | None) -> str | None:
    """The warning a serving command prints when it listens where others can reach it
    with nothing to keep them out: an endpoint on another address than loopback, no
    password in the user's zenoh file, and not TLS. None when it is loopback or secured.

    A warning rather than a refusal (docs/security.md, "Listening beyond this
    computer"): a lab network may be trusted, and a refusal would only teach a flag;
    but nobody should open a robot to the network without being told so."""
    scheme, _, address = listen.partition("/")
    host = address.rsplit(":", 1)[0].strip("[]")
    if host == "localhost" or _loopback(host):
        return None
    if scheme in SECURE_SCHEMES or (user is not None and any(user.sets(key) for key in AUTH_KEYS)):
        return None
    return (f"warning: listening on {listen} with no password and no TLS: anyone who can reach this address can "
            "use this service; see docs/security.md")


def _loopback(host: str) -> bool:
    """An address of this computer only (127.0.0.0/8, ::1); a name other than
    localhost may resolve anywhere, so it is not."""
    try:
        return ipaddress.ip_address(host).is_loopback
    except ValueError:
        return False
