"""The serving half: one queryable per verb, a catch-all that refuses the rest, and
the liveliness token that tells clients all of it is in place.

A queryable also receives every *wildcard* query whose key expression intersects its
own (``<prefix>/<name>/rpc/*`` reaches every verb). Running a verb for such a query
would let one careless ``get`` move a robot or write a library, so a verb's
queryable answers only its exact key; the catch-all on ``rpc/**`` gives wildcards
and unknown verbs one error reply each, so a client always learns why nothing ran.

A verb may also be *named*: served as well at ``rpc/<verb>/<name>``, one more chunk
that says on whose behalf the client asks (the learner's ``record_grasps/<robot>``),
so the router's access control, which knows who is asking, can allow each user its
own name only. The handler reads the name with :func:`named_by`.

Every query a server answers is logged at INFO, one line when it is answered: the
key, how long it took and the outcome (``ok`` or the error code), so an operator of
``csl driver sim`` or ``csl learner serve`` sees who asked what and what came of it.
"""

from __future__ import annotations

import logging
import time
from collections.abc import Callable, Sequence
from typing import Any

import zenoh

from zenoh_rpc.keys import KeySpace, check_chunk

JSON = zenoh.Encoding.APPLICATION_JSON
log = logging.getLogger(__name__)

Handler = Callable[[str, zenoh.Query], None]
ErrorEncoder = Callable[[str, str], bytes]


class _Logged:
    """A query on its way through a server: what a handler sees in place of the
    :class:`zenoh.Query`, answered through it, and logged once when it is finished
    (:func:`reply` and :func:`reply_err` both finish a query with ``drop``)."""

    def __init__(self, query: zenoh.Query) -> None:
        self._query = query
        self._key = str(query.key_expr)  # a dropped query no longer has one to read
        self._started = time.perf_counter()
        self.outcome = "dropped"  # unless answered
        self._logged = False

    @property
    def key_expr(self) -> zenoh.KeyExpr:
        return self._query.key_expr

    @property
    def payload(self) -> zenoh.ZBytes | None:
        return self._query.payload

    def reply(self, key_expr: Any, body: bytes, **options: Any) -> None:
        self._query.reply(key_expr, body, **options)
        self.outcome = "ok"

    def reply_err(self, body: bytes, **options: Any) -> None:
        self._query.reply_err(body, **options)
        if self.outcome == "dropped":  # a protocol's reply_error names the code first
            self.outcome = "error"

    def drop(self) -> None:
        self._query.drop()
        if not self._logged:
            self._logged = True
            log.info("%s: %s in %.1f ms", self._key, self.outcome,
                     (time.perf_counter() - self._started) * 1000)


class TooLarge(ValueError):
    """A request larger than its service accepts: refused by its size alone, before it
    is copied or parsed (a parse holds several times a document's size in memory)."""


def payload_of(query: zenoh.Query, limit: int | None = None) -> bytes:
    """The query's payload; empty when it carried none. Past ``limit`` bytes,
    :class:`TooLarge` before anything is copied out of zenoh's buffer."""
    if query.payload is None:
        return b""
    size = len(query.payload)
    if limit is not None and size > limit:
        raise TooLarge(f"message: {size} bytes, more than the {limit} a request may have")
    return query.payload.to_bytes()


def reply(query: zenoh.Query, body: bytes) -> None:
    """Answer ``query`` with a JSON result and finish it (exactly one reply)."""
    query.reply(query.key_expr, body, encoding=JSON)
    query.drop()


def reply_err(query: zenoh.Query, body: bytes) -> None:
    """Answer ``query`` with a JSON error body (code and message) and finish it."""
    query.reply_err(body, encoding=JSON)
    query.drop()


class RpcServer:
    """Declares ``verbs`` of ``keys`` on ``session``, then the liveliness token.

    ``handle(verb, query)`` gets each exact-key query and must answer it, at once or
    later from any thread, with :func:`reply` or :func:`reply_err`. ``encode_error``
    makes error bodies from a code and a message; a wildcard query is refused with
    ``bad_request`` and an unknown verb with ``unknown_verb`` (the same code where a
    protocol has no separate one). The session stays the caller's: :meth:`close`
    undeclares the token first, so clients stop sending, then the queryables.
    """

    def __init__(self, session: zenoh.Session, keys: KeySpace, verbs: Sequence[str], handle: Handler,
                 encode_error: ErrorEncoder, *, bad_request: str, unknown_verb: str,
                 named: Sequence[str] = ()) -> None:
        """``named``: the verbs (of ``verbs``) also served at ``rpc/<verb>/<name>``."""
        self.keys = keys
        self.verbs = tuple(verbs)
        self.named = tuple(named)
        self._handle = handle
        self._encode_error = encode_error
        self._bad_request = bad_request
        self._unknown_verb = unknown_verb
        self._closed = False
        self._queryables = [
            session.declare_queryable(keys.rpc(verb), self._exact(verb), complete=True)
            for verb in self.verbs
        ]
        self._queryables += [session.declare_queryable(f"{keys.rpc(verb)}/*", self._exact_named(verb), complete=True)
                             for verb in self.named]
        self._queryables.append(session.declare_queryable(keys.rpc_all, self._on_other_key))
        # Declared last: a client that sees the token finds every queryable in place.
        self._token = session.liveliness().declare_token(keys.alive)

    def reply_error(self, query: zenoh.Query, code: str, message: str) -> None:
        """Answer ``query`` with this protocol's error body and finish it."""
        if isinstance(query, _Logged):
            query.outcome = code
        reply_err(query, self._encode_error(code, message))

    def close(self) -> None:
        """Stop serving: undeclare the token, then the queryables."""
        if self._closed:
            return
        self._closed = True
        self._token.undeclare()
        for queryable in self._queryables:
            queryable.undeclare()

    def _exact(self, verb: str) -> Callable[[zenoh.Query], None]:
        exact_key = self.keys.rpc(verb)

        def on_query(query: zenoh.Query) -> None:
            if str(query.key_expr) != exact_key:
                query.drop()  # a wildcard: the catch-all answers it
                return
            self._handle(verb, _Logged(query))  # type: ignore[arg-type]  # quacks as a Query

        return on_query

    def _exact_named(self, verb: str) -> Callable[[zenoh.Query], None]:
        def on_query(query: zenoh.Query) -> None:
            if named_by(query, self.keys, verb) is None:
                query.drop()  # a wildcard or a name that is not one chunk: the catch-all answers it
                return
            self._handle(verb, _Logged(query))  # type: ignore[arg-type]  # quacks as a Query

        return on_query

    def _on_other_key(self, raw: zenoh.Query) -> None:
        key = str(raw.key_expr)
        verb = key.removeprefix(self.keys.rpc_root)
        if verb in self.verbs or any(named_by(raw, self.keys, v) is not None for v in self.named):
            raw.drop()  # answered by the verb's own queryable
            return
        query = _Logged(raw)
        if any(c in key for c in "*$"):
            self.reply_error(query, self._bad_request, f"{key}: verbs must be addressed by their exact key")
        else:
            self.reply_error(query, self._unknown_verb,
                             f"{verb!r} is not a verb (known: {', '.join(self.verbs)})")


def named_by(query: zenoh.Query, keys: KeySpace, verb: str) -> str | None:
    """The name a query for a named ``verb`` gives (``rpc/<verb>/<name>``): one key chunk
    (:func:`~zenoh_rpc.keys.check_chunk`); None for the verb's plain key, a wildcard, or
    anything else."""
    name = str(query.key_expr).removeprefix(keys.rpc(verb) + "/")
    if name == str(query.key_expr):
        return None
    try:
        return check_chunk(name)
    except ValueError:
        return None
