"""The calling half: queries with a deadline each, and the server's liveliness token.

Every call carries its own timeout, because verbs differ by orders of magnitude (a
health ping answers in milliseconds, a robot's move may take a quarter of an hour)
and a caller must never wait on a server that is gone. zenoh finishes a query that
outlived its timeout with a plain-text error reply of its own and then the end of
the query; a :class:`Reply` says whether it came at the deadline, so a protocol can
tell that marker from a real error reply it cannot parse.
"""

from __future__ import annotations

import threading
import time
from collections.abc import Callable
from dataclasses import dataclass

import zenoh

from zenoh_rpc.keys import KeySpace

JSON = zenoh.Encoding.APPLICATION_JSON
_DEADLINE_SLACK = 0.99  # zenoh's timer may fire a hair before the nominal timeout


@dataclass(frozen=True)
class Reply:
    """One reply: ``ok`` carries a result body, ``err`` an error body; ``late`` when
    it arrived at the query's deadline."""

    ok: bytes | None = None
    err: bytes | None = None
    late: bool = False


@dataclass(frozen=True)
class Answer:
    """Everything one query got back, in arrival order; ``late`` when the query ended
    at its deadline rather than because every server had answered."""

    replies: tuple[Reply, ...] = ()
    late: bool = False

    @property
    def first(self) -> Reply | None:
        return self.replies[0] if self.replies else None


@dataclass(frozen=True)
class _Deadline:
    started: float
    timeout_s: float

    def passed(self) -> bool:
        return time.monotonic() - self.started >= self.timeout_s * _DEADLINE_SLACK


class RpcClient:
    """Calls the verbs of ``keys`` and follows its liveliness token on ``session``
    (which stays the caller's)."""

    def __init__(self, session: zenoh.Session, keys: KeySpace) -> None:
        self.session = session
        self.keys = keys

    def send(self, verb: str, payload: bytes, timeout_s: float, on_reply: Callable[[Reply], None],
             on_done: Callable[[bool], None]) -> None:
        """Query ``verb`` without waiting: ``on_reply`` runs for each reply, then
        ``on_done(late)`` once the query ends. Raises zenoh.ZError when the session
        cannot send (it is closed).

        Both run on zenoh's own network thread (``indirect=False``): it halves the
        round trip's tail, at the price that they must be quick and never wait on
        another call.
        """
        deadline = _Deadline(time.monotonic(), timeout_s)

        def reply_in(reply: zenoh.Reply) -> None:
            if reply.ok is not None:
                on_reply(Reply(ok=reply.ok.payload.to_bytes(), late=deadline.passed()))
            else:
                on_reply(Reply(err=reply.err.payload.to_bytes(), late=deadline.passed()))

        self.session.get(self.keys.rpc(verb),
                         zenoh.handlers.Callback(reply_in, lambda: on_done(deadline.passed()), indirect=False),
                         payload=payload, encoding=JSON, consolidation=zenoh.ConsolidationMode.NONE,
                         timeout=timeout_s)

    def ask(self, verb: str, payload: bytes, timeout_s: float) -> Answer:
        """Query ``verb`` and wait until the query ends (at most ``timeout_s`` and a
        second of grace for zenoh's own end)."""
        replies: list[Reply] = []
        ended: list[bool] = []
        finished = threading.Event()

        def on_done(late: bool) -> None:
            ended.append(late)
            finished.set()

        self.send(verb, payload, timeout_s, replies.append, on_done)
        finished.wait(timeout_s + 1.0)
        return Answer(tuple(replies), ended[0] if ended else True)

    def wait_alive(self, timeout_s: float) -> bool:
        """Wait until a server's token is visible (one already declared counts);
        False after ``timeout_s``. Connected is not yet served: this is the wait a
        client makes before its first call."""
        alive = threading.Event()

        def on_token(sample: zenoh.Sample) -> None:
            if sample.kind == zenoh.SampleKind.PUT:
                alive.set()

        subscriber = self.session.liveliness().declare_subscriber(self.keys.alive, on_token, history=True)
        try:
            return alive.wait(timeout_s)
        finally:
            subscriber.undeclare()

    def watch_alive(self, on_change: Callable[[bool], None]) -> zenoh.Subscriber:
        """Call ``on_change(True)`` when a token appears and ``on_change(False)``
        when one goes, until the returned subscriber is undeclared. Changes only:
        pair it with :meth:`query_alive` for the tokens that exist already."""
        def on_token(sample: zenoh.Sample) -> None:
            on_change(sample.kind == zenoh.SampleKind.PUT)

        return self.session.liveliness().declare_subscriber(self.keys.alive, on_token)

    def query_alive(self, on_found: Callable[[], None], on_done: Callable[[], None] = lambda: None,
                    timeout_s: float | None = None) -> None:
        """Ask which tokens exist now without waiting: ``on_found`` runs once per
        token, then ``on_done`` (after ``timeout_s``, or zenoh's default query
        timeout, at the latest). Raises zenoh.ZError when the session is closed."""
        def on_reply(reply: zenoh.Reply) -> None:
            if reply.ok is not None:
                on_found()

        self.session.liveliness().get(self.keys.alive, zenoh.handlers.Callback(on_reply, on_done),
                                      timeout=timeout_s)
