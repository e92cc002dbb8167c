"""The learner node: serves any :class:`LearnerService` on zenoh so several robots
share one library.

The node owns everything protocol-shaped (keys, JSON, error replies, liveliness) so
that a service only deals in descriptions and snapshots; the transport plumbing it
shares with the driver link comes from :mod:`zenoh_rpc`. A request that breaks the
protocol is answered with ``bad_request`` and a service failure with ``internal``;
neither stops the node, because one robot's bad message must not cut the others off
their library. A description the service will not admit (``LocalLearner`` checks it
against the robot's knowledge) raises ValueError there and is answered ``bad_request``
with that one line, nothing stored.
"""

from __future__ import annotations

import logging
import threading
from collections.abc import Callable, Sequence

import zenoh

from learner.service import protocol
from learner.service.interface import KeepsChanges, KeepsGraspCosts, LearnerService, LibraryChanges, LibraryPage
from learner.service.protocol import (BAD_REQUEST, CHANGES, GRASP_COSTS, INTERNAL, LEARN, LIBRARY, RECORD_GRASPS,
                                      VERBS)
from zenoh_rpc.server import RpcServer, named_by, payload_of, reply
from zenoh_rpc.config import UserConfig
from zenoh_rpc.serving import serve_until

log = logging.getLogger(__name__)


class LearnerNode:
    """Declares the protocol's keys for ``service`` under ``name`` until :meth:`close`.

    The session stays the caller's: closing the node undeclares what it declared (the
    liveliness token first, so clients stop sending) and leaves the session open.
    """

    def __init__(self, service: LearnerService, session: zenoh.Session, name: str) -> None:
        self.service = service
        keys = protocol.learner_keys(name)
        self.name = keys.name
        # No separate unknown-verb code in this protocol: a wrong verb is a bad request.
        self._server = RpcServer(session, keys, VERBS, self._serve, protocol.encode_error,
                                 bad_request=BAD_REQUEST, unknown_verb=BAD_REQUEST, named=(RECORD_GRASPS,))

    def close(self) -> None:
        """Stop serving: undeclare the token, then the queryables."""
        self._server.close()

    def __enter__(self) -> LearnerNode:
        return self

    def __exit__(self, *_exc: object) -> None:
        self.close()

    def _serve(self, verb: str, query: zenoh.Query) -> None:
        try:
            body = self._answer(verb, payload_of(query, protocol.MAX_REQUEST_BYTES),
                                named_by(query, self._server.keys, verb))
        except ValueError as exc:  # ProtocolError included: the request's fault
            self._server.reply_error(query, BAD_REQUEST, f"{verb}: {exc}")
        except Exception as exc:  # the node outlives any service failure
            log.exception("learner %s failed to answer %s", self.name, verb)
            self._server.reply_error(query, INTERNAL, f"{verb}: {type(exc).__name__}: {exc}")
        else:
            reply(query, body)

    def _answer(self, verb: str, payload: bytes, robot: str | None = None) -> bytes:
        """The reply to ``verb``; ``robot``: the name its key gives (only
        ``record_grasps/<robot>`` has one: whose attempts they are)."""
        if verb == LEARN:
            description, key = protocol.decode_learn_request(payload)
            return protocol.encode_learn_reply(self.service.learn(description, key))
        if verb == CHANGES:
            return protocol.encode_changes_reply(self._changes(protocol.decode_changes_request(payload)))
        if verb == RECORD_GRASPS:
            attempts, key = protocol.decode_record_grasps_request(payload)
            self._grasp_costs().record_grasp_attempts(attempts, key, robot)
            return protocol.encode_recorded_reply(len(attempts))
        if verb == GRASP_COSTS:
            protocol.decode_empty_request(payload)
            return protocol.encode_grasp_costs_reply(self._grasp_costs().grasp_costs())
        if verb == LIBRARY:
            page = protocol.decode_library_request(payload)
            snapshot = self.service.library()
            if page is None:
                return protocol.encode_library_reply(snapshot)
            cut = snapshot.descriptions[page.start:page.start + page.limit]
            return protocol.encode_library_page_reply(
                LibraryPage(snapshot.version, page.start, len(snapshot.descriptions), cut))
        protocol.decode_empty_request(payload)
        return protocol.encode_version_reply(self.service.version())


    def _grasp_costs(self) -> KeepsGraspCosts:
        """The service as a keeper of grasp costs; ValueError (a bad request) for one
        that keeps none."""
        if not isinstance(self.service, KeepsGraspCosts):
            raise ValueError("this learner keeps no grasp costs")
        return self.service

    def _changes(self, since: int) -> LibraryChanges:
        """The service's own answer, or the whole library from one that keeps no
        changes (every client then refetches all of it, as before deltas)."""
        if isinstance(self.service, KeepsChanges):
            return self.service.changes(since)
        snapshot = self.service.library()
        return LibraryChanges(snapshot.version, 0, snapshot.descriptions)


def serve_learner(service: LearnerService, name: str, listen_endpoints: Sequence[str],
                  stop_event: threading.Event, *, on_ready: Callable[[], None] | None = None,
                  zenoh_config: UserConfig | None = None) -> None:
    """Serve ``service`` as ``name`` on a session listening on ``listen_endpoints``
    until ``stop_event`` is set.

    ``on_ready`` runs once every key is declared (the CLI prints its line there, so a
    script that waits for that line can connect at once). Raises ConnectionError when
    an endpoint cannot be listened on. ``zenoh_config`` is the user's zenoh config
    file, whose authentication and access control keep others from writing to the
    library (docs/security.md).
    """
    serve_until(stop_event, listen_endpoints, lambda session: LearnerNode(service, session, name), on_ready,
                zenoh_config, max_request_bytes=protocol.MAX_REQUEST_BYTES)
