"""A process that serves until it is told to stop: ``csl driver sim`` and
``csl learner serve`` run this way under a terminal or a service manager.

SIGINT (Ctrl-C) and SIGTERM (systemd, docker, ``kill``) both mean "stop cleanly":
the server undeclares its liveliness token before the process exits, so clients
learn at once that it is gone instead of waiting for the lease to run out.
"""

from __future__ import annotations

import signal
import threading
from collections.abc import Callable, Iterator, Sequence
from contextlib import AbstractContextManager, contextmanager
from types import FrameType

from zenoh import Session

from zenoh_rpc.config import UserConfig, close_session, open_session

STOP_SIGNALS = (signal.SIGINT, signal.SIGTERM)


@contextmanager
def stop_on_signals(signals: Sequence[signal.Signals] = STOP_SIGNALS) -> Iterator[threading.Event]:
    """An event that ``signals`` set while the block runs; the previous handlers
    come back afterwards (so a test calling the CLI in-process keeps its own)."""
    stop = threading.Event()

    def on_signal(_signum: int, _frame: FrameType | None) -> None:
        stop.set()

    previous = {sig: signal.signal(sig, on_signal) for sig in signals}
    try:
        yield stop
    finally:
        for sig, handler in previous.items():
            signal.signal(sig, handler)


SIGNAL_POLL_S = 0.2
"""How often :func:`wait_for_stop` returns to the interpreter to run pending signal handlers."""


def wait_for_stop(stop: threading.Event) -> None:
    """Block until ``stop`` is set, waking every :data:`SIGNAL_POLL_S` seconds.

    Why not ``stop.wait()``: the kernel delivers a process signal to any thread that does
    not block it, and zenoh runs a dozen threads of its own. When SIGTERM lands on one of
    them, Python only notes it as pending; the handler that sets ``stop`` runs when the
    main thread next executes bytecode, and a main thread asleep in an untimed wait never
    does, so the process hangs until it is killed (seen on the loaded CI machine: a
    service that ignored SIGTERM for 30 s). A timed wait returns to the interpreter, which
    runs the handler within one poll.
    """
    while not stop.wait(SIGNAL_POLL_S):
        pass


HEADER_ROOM = 64 * 1024
"""Bytes a server accepts beyond its request cap: zenoh's own headers and the key; a
request within the cap is always received whole, and refused by the server in one line."""


def serve_until(stop: threading.Event, listen: Sequence[str],
                declare: Callable[[Session], AbstractContextManager[object]],
                on_ready: Callable[[], None] | None = None, user: UserConfig | None = None,
                max_request_bytes: int | None = None) -> None:
    """Open a session listening on ``listen`` (with the user's zenoh config file
    ``user`` under it, if any), declare a server on it with ``declare(session)`` and
    keep it until ``stop`` is set; then close both.

    ``on_ready`` runs once every key is declared (a CLI prints its line there, so a
    script waiting for that line can connect at once). Raises ConnectionError when
    an endpoint cannot be listened on. With ``max_request_bytes`` (the server's request
    cap), zenoh itself drops a message larger than it plus :data:`HEADER_ROOM`, so no
    request can grow the server by more than that however large it is
    (:func:`~zenoh_rpc.config.make_config`).
    """
    room = None if max_request_bytes is None else max_request_bytes + HEADER_ROOM
    session = open_session(listen=listen, user=user, max_message_bytes=room)
    try:
        with declare(session):
            if on_ready is not None:
                on_ready()
            wait_for_stop(stop)
    finally:
        close_session(session)
