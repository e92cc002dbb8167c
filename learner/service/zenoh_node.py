"""The learner node: serves any :class:`LearnerService` on zenoh so several robots
share one library.

The node owns everything protocol-shaped (keys, JSON, error replies, liveliness) so
that a service only deals in descriptions and snapshots. A request that breaks the
protocol is answered with ``bad_request`` and a service failure with ``internal``;
neither stops the node, because one robot's bad message must not cut the others off
their library.
"""

from __future__ import annotations

import logging
import threading
from collections.abc import Callable, Sequence

import zenoh

from learner.service import protocol
from learner.service.config import open_session
from learner.service.interface import LearnerService
from learner.service.protocol import BAD_REQUEST, INTERNAL, LEARN, LIBRARY, VERBS

log = logging.getLogger(__name__)


class LearnerNode:
    """Declares the protocol's keys for ``service`` under ``name`` until :meth:`close`.

    The session stays the caller's: closing the node undeclares what it declared (the
    liveliness token first, so clients stop sending) and leaves the session open.
    """

    def __init__(self, service: LearnerService, session: zenoh.Session, name: str) -> None:
        self.service = service
        self.name = protocol.check_name(name)
        self._closed = False
        self._queryables = [
            session.declare_queryable(protocol.rpc_key(name, verb), self._handler(verb), complete=True)
            for verb in VERBS
        ]
        self._queryables.append(session.declare_queryable(protocol.rpc_prefix(name), self._on_other_key))
        # Declared last: a client that sees the token finds every queryable in place.
        self._token = session.liveliness().declare_token(protocol.alive_key(name))

    def close(self) -> None:
        """Stop serving: undeclare the token, then the queryables."""
        if self._closed:
            return
        self._closed = True
        self._token.undeclare()
        for queryable in self._queryables:
            queryable.undeclare()

    def __enter__(self) -> LearnerNode:
        return self

    def __exit__(self, *_exc: object) -> None:
        self.close()

    def _handler(self, verb: str) -> Callable[[zenoh.Query], None]:
        exact_key = protocol.rpc_key(self.name, verb)

        def on_query(query: zenoh.Query) -> None:
            # A wildcard query (rpc/*) reaches this queryable too; it must not learn
            # anything. The catch-all refuses it.
            if str(query.key_expr) != exact_key:
                query.drop()
                return
            self._serve(verb, query)

        return on_query

    def _on_other_key(self, query: zenoh.Query) -> None:
        key = str(query.key_expr)
        verb = key.removeprefix(protocol.rpc_key(self.name, ""))
        if verb in VERBS:
            query.drop()  # answered by the verb's own queryable
        elif any(c in key for c in "*$"):
            _reply_error(query, BAD_REQUEST, f"{key}: verbs must be addressed by their exact key")
        else:
            _reply_error(query, BAD_REQUEST, f"{verb!r} is not a verb (known: {', '.join(VERBS)})")

    def _serve(self, verb: str, query: zenoh.Query) -> None:
        payload = b"" if query.payload is None else query.payload.to_bytes()
        try:
            reply = self._answer(verb, payload)
        except ValueError as exc:  # ProtocolError included: the request's fault
            _reply_error(query, BAD_REQUEST, f"{verb}: {exc}")
        except Exception as exc:  # the node outlives any service failure
            log.exception("learner %s failed to answer %s", self.name, verb)
            _reply_error(query, INTERNAL, f"{verb}: {type(exc).__name__}: {exc}")
        else:
            query.reply(query.key_expr, reply, encoding=zenoh.Encoding.APPLICATION_JSON)
            query.drop()

    def _answer(self, verb: str, payload: bytes) -> bytes:
        if verb == LEARN:
            description = protocol.decode_learn_request(payload)
            return protocol.encode_learn_reply(self.service.learn(description))
        protocol.decode_empty_request(payload)
        if verb == LIBRARY:
            return protocol.encode_library_reply(self.service.library())
        return protocol.encode_version_reply(self.service.version())


def _reply_error(query: zenoh.Query, code: str, message: str) -> None:
    query.reply_err(protocol.encode_error(code, message), encoding=zenoh.Encoding.APPLICATION_JSON)
    query.drop()


def serve_learner(service: LearnerService, name: str, listen_endpoints: Sequence[str],
                  stop_event: threading.Event, *, on_ready: Callable[[], None] | None = None) -> None:
    """Serve ``service`` as ``name`` on a session listening on ``listen_endpoints``
    until ``stop_event`` is set.

    ``on_ready`` runs once every key is declared (the CLI prints its line there, so a
    script that waits for that line can connect at once). Raises ConnectionError when
    an endpoint cannot be listened on.
    """
    session = open_session(listen=listen_endpoints)
    try:
        with LearnerNode(service, session, name):
            if on_ready is not None:
                on_ready()
            stop_event.wait()
    finally:
        session.close()
