"""One place that turns endpoint lists into a :class:`zenoh.Config` and a session.

Peer mode with multicast scouting off: a server listens on explicit endpoints and
clients connect to them, so nothing is discovered by accident on a shared network
and tests on 127.0.0.1 run side by side on their own ports. The lease is short so
that a peer that vanishes without closing its socket (power cut, cable pulled, a
killed process) is noticed in about a second, and reconnection is retried quickly
so that a restarted server is picked up again within a fraction of a second. A
connection handshake is bounded by a second too: a peer that accepts TCP but never
answers (a frozen process, SIGSTOP) would otherwise hold every ``close`` of this
session for zenoh's default ten seconds, and end it in an error.

Security is zenoh's own: a user's zenoh config file (:class:`UserConfig`, given as
``--zenoh-config`` or ``CSL_ZENOH_CONFIG``) turns on user/password authentication,
TLS and access control, and our settings are laid on top of it only where the file
leaves zenoh's default in place (:data:`OUR_SETTINGS`; docs/security.md).
"""

from __future__ import annotations

import json
import logging
import re
from collections.abc import Sequence
from dataclasses import dataclass, field
from pathlib import Path

import zenoh

from zenoh_rpc.endpoints import CONNECT_KEY, LISTEN_KEY, check_endpoint

log = logging.getLogger(__name__)

LEASE_MS = 1000  # a silent peer is dropped after this; keep-alives go 4x as often
RETRY_PERIOD_MS = (100, 500)  # first and longest wait between connection attempts
OPEN_TIMEOUT_MS = 1000  # a handshake with a peer that accepts but never answers (SIGSTOP) gives up after this

OUR_SETTINGS = ("mode", "scouting/multicast/enabled", "scouting/delay", LISTEN_KEY, CONNECT_KEY,
                "connect/retry", "connect/timeout_ms", "connect/exit_on_failure",
                "transport/link/tx/lease", "transport/unicast/open_timeout", "transport/link/rx/max_message_size")
"""Every key :func:`make_config` sets; a user's file that sets one keeps its own value."""

_ZENOH_DEFAULTS = zenoh.Config()
_SERDE_MESSAGE = re.compile(
    r'JSON error: Message \{ msg: "(.*)", location: Some\(Location \{ line: (\d+), column: (\d+) \}\) \}')


@dataclass(frozen=True)
class UserConfig:
    """A zenoh config file (JSON5, JSON or YAML, as :meth:`zenoh.Config.from_file` reads)
    that the user gave to turn on zenoh's own security, read and checked at once.

    ``origin`` says where the path came from (``--zenoh-config``, ``CSL_ZENOH_CONFIG``)
    so that an error names both. Raises ValueError, one line naming the file, when
    the file cannot be read or zenoh refuses its contents.
    """

    path: Path
    origin: str = "--zenoh-config"
    _parsed: zenoh.Config = field(init=False, repr=False, compare=False)  # read once, asked by sets()

    def __post_init__(self) -> None:
        object.__setattr__(self, "_parsed", self.load())

    def load(self) -> zenoh.Config:
        """A fresh :class:`zenoh.Config` from the file (zenoh consumes one per session)."""
        try:
            return zenoh.Config.from_file(str(self.path))
        except zenoh.ZError as exc:
            raise ValueError(f"{self.origin} {self.path}: {_one_line(str(exc))}") from None

    def sets(self, key: str) -> bool:
        """True when the file gives ``key`` a value other than zenoh's own default.

        zenoh fills every key the file leaves out with its default, so a value equal
        to the default cannot be told from no value: writing zenoh's default lease
        (10000 ms) in the file is the same as leaving it out.
        """
        return _sets(self._parsed, key)


def make_config(listen: Sequence[str] = (), connect: Sequence[str] = (),
                connect_timeout_s: float | None = None, user: UserConfig | None = None,
                max_message_bytes: int | None = None) -> zenoh.Config:
    """A peer-mode config listening on ``listen`` and connecting to ``connect``.

    An empty ``listen`` really listens nowhere (zenoh's peer default would open a
    random port on every interface). With ``connect_timeout_s``, opening the session
    waits until one ``connect`` endpoint is reached and fails after that many
    seconds: a client that must not wait forever for a server that is not there.
    With ``user``, the config starts from the user's file and each of our settings
    is applied only where the file does not set that key (:meth:`UserConfig.sets`).
    With ``max_message_bytes`` (a server's: its largest request and room for zenoh's
    own headers), zenoh drops any larger message it receives as it reassembles it,
    before the whole is held: a service that refused an oversized request only after
    zenoh had built it grew by the request's size for each one at once (once, 4 x
    100 MB took the learner from 53 to 265 MB, and it kept 219 MB).
    """
    ours = {
        "mode": '"peer"',
        "scouting/multicast/enabled": "false",
        "scouting/delay": "0",  # nothing to wait for without multicast
        LISTEN_KEY: json.dumps([check_endpoint(e) for e in listen]),
        CONNECT_KEY: json.dumps([check_endpoint(e) for e in connect]),
        "connect/retry": json.dumps({"period_init_ms": RETRY_PERIOD_MS[0], "period_max_ms": RETRY_PERIOD_MS[1],
                                     "period_increase_factor": 2}),
        "transport/link/tx/lease": str(LEASE_MS),
        "transport/unicast/open_timeout": str(OPEN_TIMEOUT_MS),
    }
    if max_message_bytes is not None:
        ours["transport/link/rx/max_message_size"] = str(max_message_bytes)
    if connect_timeout_s is not None:
        ours["connect/timeout_ms"] = str(max(1, round(connect_timeout_s * 1000)))
        ours["connect/exit_on_failure"] = "true"
    config = zenoh.Config() if user is None else user.load()
    for key, value in ours.items():
        if not _sets(config, key):
            config.insert_json5(key, value)
    return config


def _sets(config: zenoh.Config, key: str) -> bool:
    return config.get_json(key) != _ZENOH_DEFAULTS.get_json(key)


def open_session(listen: Sequence[str] = (), connect: Sequence[str] = (),
                 connect_timeout_s: float | None = None, user: UserConfig | None = None,
                 max_message_bytes: int | None = None) -> zenoh.Session:
    """Open a session with :func:`make_config`.

    Raises ConnectionError (an OSError) with a one-line reason when an endpoint
    cannot be listened on (port taken, unknown protocol), the user's file names
    something zenoh cannot use (a missing password dictionary or certificate) or,
    with ``connect_timeout_s``, no endpoint can be reached in time: command lines
    report it as one line, and zenoh's source locations would only bury the reason.
    """
    config = make_config(listen, connect, connect_timeout_s, user, max_message_bytes)
    try:
        return zenoh.open(config)
    except zenoh.ZError as exc:
        where = ", ".join([*listen, *connect]) if user is None else f"{', '.join([*listen, *connect])} ({user.path})"
        raise ConnectionError(f"zenoh session on {where}: {_one_line(str(exc))}") from None


def _one_line(reason: str) -> str:
    """zenoh's error without its Rust source location, on one line.

    A JSON5 syntax error comes as a drawing (`` --> 1:22``, the line, a caret, ``=
    expected ...``) and a misplaced key as a Rust debug print; both become
    ``line 1, column 22: ...``.
    """
    lines = [line.strip() for line in reason.strip().splitlines() if line.strip()]
    if lines and lines[0].startswith("-->"):
        where = lines[0].removeprefix("-->").strip()
        said = [line.removeprefix("=").strip() for line in lines if line.startswith("=")]
        line, _, column = where.partition(":")
        lines = [f"line {line}, column {column}: {said[-1] if said else 'syntax error'}"]
    text = " ".join(lines).split(" at /")[0]  # zenoh's Rust source location, and what it wraps
    return _SERDE_MESSAGE.sub(r"line \2, column \3: \1", text)


def close_session(session: zenoh.Session) -> None:
    """Close ``session``; a close that zenoh reports as failed (it timed out on a peer
    that stopped answering) is one warning in the log, never an exception: closing is
    what a command does on its way out, and a traceback there hides the real reason
    it is leaving."""
    try:
        session.close()
    except zenoh.ZError as exc:
        log.warning("zenoh session close: %s", _one_line(str(exc)))
