"""The zenoh client: a :class:`LearnerService` whose library lives in another process
(``csl learner serve``), shared with every robot connected to it.

Calls are synchronous: ``library()`` is asked before a decision and ``learn()`` after
a grasp, both between ticks, and each is one round trip of a few milliseconds on a
LAN. The whole library is fetched once, page by page (``PAGE_SIZE`` descriptions a
request, so each reply comes well inside the timeout however large the library and
however many robots start together); after that ``library()`` asks only for the
changes since the version the robot holds (the ``changes`` verb), so what moves is
what other robots learned since, whatever the library's size.
A service that is not there is reported at construction (its liveliness token is
missing) and on every call that finds no answer, as a one-line ConnectionError: a
robot must never hang waiting for its library.
"""

from __future__ import annotations

import threading
import uuid
from collections.abc import Callable, Sequence
from typing import TypeVar

import zenoh

from learner.costs import GraspCostRecord
from learner.description import Descriptions, ObjectDescription
from learner.service import protocol
from learner.service.interface import (LearnerTimedOut, LearnerUnavailable, LibraryChanges, LibraryPage,
                                        LibrarySnapshot, check_robot_name)
from learner.service.protocol import (CHANGES, GRASP_COSTS, LEARN, LIBRARY, RECORD_GRASPS, VERSION_VERB,
                                      ProtocolError)
from zenoh_rpc.client import RpcClient
from zenoh_rpc.config import UserConfig, open_session
from zenoh_rpc.endpoints import LEARNER_ENDPOINT

T = TypeVar("T")

PAGE_SIZE = 2_000
"""Descriptions per ``library`` page at start-up: a few MB of JSON, well under a
second to cut and send even from a busy service (bench/bench_fleet_start.py)."""
FETCH_ATTEMPTS = 3
"""Whole fetches begun again when the library shrank between pages (a store restored
under a running service) before giving up with one line."""


class ZenohLearner:
    """Reaches the learner service ``name`` through the nodes at ``connect``.

    Every wait, from connecting to each reply, is bounded by ``timeout_s``; the
    session carries the user's zenoh config file ``zenoh_config`` (credentials, TLS)
    if given. Raises
    ConnectionError when no endpoint can be reached or no service ``name`` is alive
    there; later, an unanswered call raises ConnectionError and an error reply from
    the service raises ValueError.
    """

    def __init__(self, name: str = "default", connect: Sequence[str] = (LEARNER_ENDPOINT,),
                 timeout_s: float = 5.0, zenoh_config: UserConfig | None = None,
                 page_size: int = PAGE_SIZE) -> None:
        keys = protocol.learner_keys(name)
        self.name = keys.name
        if not timeout_s > 0:
            raise ValueError(f"timeout_s must be a positive number of seconds, got {timeout_s}")
        self.timeout_s = timeout_s
        if not 1 <= page_size <= protocol.MAX_PAGE:
            raise ValueError(f"page_size must be 1 to {protocol.MAX_PAGE}, got {page_size}")
        self.page_size = page_size
        self._paged = True  # False once a service from before pages refused one
        self._named_records = True  # False once a service from before named records refused one
        self._where = ", ".join(connect)
        self._lock = threading.Lock()
        self._cached: LibrarySnapshot | None = None
        self._closed = False
        try:
            self._session = open_session(connect=connect, connect_timeout_s=timeout_s, user=zenoh_config)
        except ConnectionError as exc:
            raise LearnerUnavailable(f"learner {self.name!r}: cannot reach a service: {exc}") from None
        self._rpc = RpcClient(self._session, keys)
        found = False
        try:
            found = self._rpc.wait_alive(self.timeout_s)
        finally:
            if not found:
                self._session.close()
        if not found:
            raise LearnerUnavailable(f"no learner service {self.name!r} on {self._where} "
                                     f"(no liveliness token {keys.alive} within {self.timeout_s:g} s)")

    def library(self) -> LibrarySnapshot:
        """The current library: the first call fetches it whole, later ones only what
        changed since the snapshot held (the same snapshot when nothing did)."""
        with self._lock:
            held = self._cached
        snapshot = self._fetch_all() if held is None else self._updated(held)
        with self._lock:
            if self._cached is None or snapshot.version >= self._cached.version:
                self._cached = snapshot
        return snapshot

    def changes(self, since: int) -> LibraryChanges:
        """What the service says changed after version ``since``."""
        return self._decode(protocol.decode_changes_reply,
                            self._call(CHANGES, protocol.encode_changes_request(since)))

    def _fetch_all(self) -> LibrarySnapshot:
        """The whole library, page by page: the first page says how many descriptions the
        library held and at which version; the library only grows, so the next pages
        complete exactly that snapshot, and the next ``changes`` round trip brings what
        was learned meanwhile. A library that shrank between pages (a store restored
        under the service) is fetched again from the start."""
        if not self._paged:
            return self._fetch_whole()
        for _ in range(FETCH_ATTEMPTS):
            try:
                first = self._page(0)
            except ValueError as exc:  # a service from before pages: it refuses the fields
                if "unknown field" not in str(exc):
                    raise
                self._paged = False
                return self._fetch_whole()
            held = list(first.descriptions)
            while len(held) < first.total:
                page = self._page(len(held))
                if page.total < first.total or not page.descriptions:
                    break  # the library shrank under us: begin again
                held += page.descriptions[:first.total - len(held)]
            else:
                return LibrarySnapshot(first.version, Descriptions(held[:first.total]))
        raise LearnerUnavailable(f"learner {self.name!r}: library: it shrank while being fetched, "
                                 f"{FETCH_ATTEMPTS} times (a store being restored?)")

    def _page(self, start: int) -> LibraryPage:
        return self._decode(protocol.decode_library_page_reply,
                            self._call(LIBRARY, protocol.encode_library_request(protocol.Page(start, self.page_size))))

    def _fetch_whole(self) -> LibrarySnapshot:
        whole = self._decode(protocol.decode_library_reply, self._call(LIBRARY, protocol.encode_library_request()))
        return LibrarySnapshot(whole.version, Descriptions(whole.descriptions))

    def _updated(self, held: LibrarySnapshot) -> LibrarySnapshot:
        """``held`` brought up to date by one ``changes`` round trip: extended by what
        was added, replaced when the service sent the whole library, fetched whole when
        the change does not follow on from what is held."""
        changed = self.changes(held.version)
        if changed.version == held.version and changed.start == len(held.descriptions) and not changed.added:
            return held
        if changed.start == 0:
            return LibrarySnapshot(changed.version, Descriptions(changed.added))
        if changed.start != len(held.descriptions) or not isinstance(held.descriptions, Descriptions):
            return self._fetch_all()
        return LibrarySnapshot(changed.version, held.descriptions.plus(changed.added))

    def learn(self, description: ObjectDescription, key: str | None = None) -> str:
        """Learn ``description`` under idempotency ``key`` (a fresh uuid when None: the
        caller that will retry must make the key itself and send it again)."""
        key = key if key is not None else str(uuid.uuid4())
        return self._decode(protocol.decode_learn_reply,
                            self._call(LEARN, protocol.encode_learn_request(description, key)))

    def record_grasp_attempts(self, attempts: Sequence[tuple[str, float, bool]], key: str | None = None,
                              robot: str | None = None) -> None:
        """Record ``(grasp, seconds, success)`` attempts under idempotency ``key`` (a fresh
        uuid when None, as :meth:`learn`), as ``robot``'s: sent to
        ``rpc/record_grasps/<robot>``, the key the router's access control lets only that
        robot's user query (docs/security.md); to ``rpc/record_grasps`` when None or when
        the service predates named records. ValueError when the service refuses them."""
        key = key if key is not None else str(uuid.uuid4())
        request = protocol.encode_record_grasps_request(attempts, key)
        if robot is not None and self._named_records:
            verb = f"{RECORD_GRASPS}/{check_robot_name(robot)}"
            try:
                self._decode(protocol.decode_recorded_reply, self._call(verb, request))
                return
            except ValueError as exc:  # a service from before named records: the key is no verb to it
                if "is not a verb" not in str(exc):
                    raise
                self._named_records = False
        self._decode(protocol.decode_recorded_reply, self._call(RECORD_GRASPS, request))

    def grasp_costs(self) -> list[GraspCostRecord]:
        """What each grasp has cost so far, as the service keeps it."""
        return self._decode(protocol.decode_grasp_costs_reply,
                            self._call(GRASP_COSTS, protocol.encode_empty_request()))

    def version(self) -> int:
        return self._decode(protocol.decode_version_reply,
                            self._call(VERSION_VERB, protocol.encode_empty_request()))

    def close(self) -> None:
        with self._lock:
            if self._closed:
                return
            self._closed = True
        self._session.close()

    def __enter__(self) -> ZenohLearner:
        return self

    def __exit__(self, *_exc: object) -> None:
        self.close()

    def _call(self, verb: str, payload: bytes) -> bytes:
        """The payload of the first reply to ``verb``; the error cases as documented."""
        with self._lock:
            if self._closed:
                raise LearnerUnavailable(f"learner {self.name!r}: {verb}: the client is closed")
        try:
            answer = self._rpc.ask(verb, payload, self.timeout_s)
        except zenoh.ZError as exc:
            raise LearnerUnavailable(f"learner {self.name!r}: {verb}: {exc}") from None
        if answer.late:  # zenoh ended the query at its deadline: the service is there, the reply was not
            raise LearnerTimedOut(f"learner {self.name!r}: {verb}: no reply within {self.timeout_s:g} s "
                                  "(a busy service, or a large library on a slow link: give it longer with "
                                  "--learner-timeout)")
        reply = answer.first
        if reply is None:
            raise LearnerUnavailable(f"learner {self.name!r}: {verb}: no service answered on "
                                     f"{self._rpc.keys.rpc(verb)} (is 'csl learner serve' running at {self._where}?)")
        if reply.ok is not None:
            return reply.ok
        data = reply.err or b""
        try:
            code, message = protocol.decode_error(data)
        except ProtocolError:  # not the service's: zenoh's own, e.g. the query timed out
            text = data.decode("utf-8", "replace").splitlines()[0] if data else "no reason given"
            raise LearnerUnavailable(f"learner {self.name!r}: {verb}: {text}") from None
        raise ValueError(f"learner {self.name!r}: {code}: {_one_line(message)}")

    def _decode(self, decode: Callable[[bytes], T], data: bytes) -> T:
        try:
            return decode(data)
        except ProtocolError as exc:
            raise LearnerUnavailable(f"learner {self.name!r}: malformed reply: {exc}") from None


def _one_line(text: str) -> str:
    return " ".join(text.split())
