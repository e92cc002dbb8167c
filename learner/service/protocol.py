"""The learner protocol on zenoh (docs/learner-protocol.md): keys and JSON messages.

Keys, message shapes and error codes live in one module so the node and the client
cannot drift apart; the transport they ride on is the shared :mod:`zenoh_rpc` kit.
Descriptions travel in the library JSON format (docs/library-format.md), so a library
reply is also a valid library file. Decoding checks only that format; whether the robot
can use a description (known features, values in their spans, reachable positions) is
the service's check (:mod:`learner.service.admission`), which knows the robot.
"""

from __future__ import annotations

import json
import math
from dataclasses import dataclass
from collections.abc import Mapping, Sequence
from typing import cast

from learner.costs import GraspCostRecord
from learner.description import ObjectDescription
from learner.library.format import FORMAT, VERSION, descriptions_from_json, descriptions_to_json
from learner.library.json_text import NotJson, parse_json
from learner.service.interface import LibraryChanges, LibraryPage, LibrarySnapshot, check_grasp_attempts, check_learn_key
from zenoh_rpc.keys import KeySpace
from zenoh_rpc.numbers import whole_number

PREFIX = "csl/learner"
PROTOCOL_VERSION = 1

LIBRARY, LEARN, VERSION_VERB, CHANGES = "library", "learn", "version", "changes"
RECORD_GRASPS, GRASP_COSTS = "record_grasps", "grasp_costs"  # docs/method.md §5.7
VERBS = (LIBRARY, LEARN, VERSION_VERB, CHANGES, RECORD_GRASPS, GRASP_COSTS)

BAD_REQUEST = "bad_request"  # the request is malformed or cannot be stored; resending will not help
INTERNAL = "internal"  # the service failed (disk full, a bug); the library is unchanged
ERROR_CODES = (BAD_REQUEST, INTERNAL)


MAX_REQUEST_BYTES = 256 * 1024
"""The largest request the service reads, refused by its size before it is copied or
parsed (a parse holds several times a document's size in memory, so one oversized
request could grow the service by gigabytes): far above the largest ``learn`` (one
description) or ``record_grasps`` (``MAX_GRASP_ATTEMPTS`` attempts) a client sends,
which tests/learner/test_service_zenoh.py holds under it; twice the driver's cap."""


class ProtocolError(ValueError):
    """A message that does not follow the protocol; the text names the field."""


# -- keys -----------------------------------------------------------------------------
def learner_keys(name: str) -> KeySpace:
    """The keys of the service ``name``; ValueError when the name is not one key
    chunk (it could smuggle ``*`` or ``/`` into a key)."""
    return KeySpace(PREFIX, name, "learner name")


# -- requests -------------------------------------------------------------------------
def encode_empty_request() -> bytes:
    """The request of ``library`` and ``version``: ``{"v": 1}``."""
    return _dumps({})


def decode_empty_request(data: bytes) -> None:
    """Check a ``version`` (or other empty) request."""
    _fields(data, ())


MAX_PAGE = 5_000
"""The most descriptions one ``library`` page may ask for: a page of the largest is a
few MB of JSON, so a service answers many robots starting together page by page, each
reply well inside a client's timeout, instead of one whole library each at once."""


@dataclass(frozen=True)
class Page:
    """Descriptions ``start`` to ``start + limit`` (fewer at the end) of the library."""

    start: int
    limit: int


def encode_library_request(page: Page | None = None) -> bytes:
    """``{"v": 1}`` for the whole library, or ``{"v": 1, "start": S, "limit": L}`` for
    one page of it."""
    return _dumps({} if page is None else {"start": page.start, "limit": page.limit})


def decode_library_request(data: bytes) -> Page | None:
    """The page a ``library`` request asks for (None: the whole library). ``start`` and
    ``limit`` come together; ``limit`` is 1 to :data:`MAX_PAGE`."""
    fields = _fields(data, (), optional=("start", "limit"))
    if ("start" in fields) != ("limit" in fields):
        raise ProtocolError("start and limit: give both for a page, or neither for the whole library")
    if "start" not in fields:
        return None
    limit = _version(fields["limit"], "limit")
    if not 1 <= limit <= MAX_PAGE:
        raise ProtocolError(f"limit: must be 1 to {MAX_PAGE}, got {limit}")
    return Page(_version(fields["start"], "start"), limit)


def encode_learn_request(description: ObjectDescription, key: str | None = None) -> bytes:
    """``{"v": 1, "description": <one library entry>, "key": <idempotency key>}``; the
    key is optional (a client from before idempotent learning sends none)."""
    return _dumps({"description": _entry(description), **({} if key is None else {"key": key})})


def decode_learn_request(data: bytes) -> tuple[ObjectDescription, str | None]:
    """The description a ``learn`` request carries, validated like a library file, and
    its idempotency key (None when the request has none)."""
    fields = _fields(data, ("description",), optional=("key",))
    key = fields.get("key")
    if key is not None:
        try:
            check_learn_key(key)
        except ValueError as exc:
            raise ProtocolError(str(exc)) from None
    return _description(fields["description"], "description"), cast("str | None", key)


def encode_changes_request(since: int) -> bytes:
    """``{"v": 1, "since": N}``: what changed after version N."""
    return _dumps({"since": since})


def decode_changes_request(data: bytes) -> int:
    return _version(_fields(data, ("since",))["since"], "since")


def encode_record_grasps_request(attempts: Sequence[tuple[str, float, bool]], key: str) -> bytes:
    """``{"v": 1, "attempts": [[grasp, seconds, success], ...], "key": <idempotency key>}``."""
    return _dumps({"attempts": [[g, s, ok] for g, s, ok in attempts], "key": key})


def decode_record_grasps_request(data: bytes) -> tuple[list[tuple[str, float, bool]], str]:
    """The attempts a ``record_grasps`` request carries, each checked (a grasp name,
    finite seconds >= 0, a boolean; at most ``MAX_GRASP_ATTEMPTS``), and its key. The
    key is required: a record sent again (a retry, or a replay) must count once, or one
    client could skew every robot's grasp prices by repeating itself."""
    fields = _fields(data, ("attempts", "key"))
    try:
        key = check_learn_key(fields["key"])
        return check_grasp_attempts(fields["attempts"]), key
    except ValueError as exc:
        raise ProtocolError(str(exc)) from None


# -- replies --------------------------------------------------------------------------
def encode_library_reply(snapshot: LibrarySnapshot) -> bytes:
    """``{"v": 1, "version": N, "library": <library JSON document>}``."""
    return _dumps({"version": snapshot.version, "library": descriptions_to_json(snapshot.descriptions)})


def encode_library_page_reply(page: LibraryPage) -> bytes:
    """``{"v": 1, "version": N, "start": S, "total": T, "library": <library JSON
    document of descriptions S to S + L>}``: ``version`` and ``total`` are the library's
    when the page was cut (it only grows, so the first ``total`` never change)."""
    return _dumps({"version": page.version, "start": page.start, "total": page.total,
                   "library": descriptions_to_json(page.descriptions)})


def decode_library_page_reply(data: bytes) -> LibraryPage:
    fields = _fields(data, ("version", "start", "total", "library"))
    try:
        descriptions = descriptions_from_json(fields["library"], "library")
    except ValueError as exc:
        raise ProtocolError(str(exc)) from None
    return LibraryPage(_version(fields["version"]), _version(fields["start"], "start"),
                       _version(fields["total"], "total"), tuple(descriptions))


def decode_library_reply(data: bytes) -> LibrarySnapshot:
    fields = _fields(data, ("version", "library"))
    try:
        descriptions = descriptions_from_json(fields["library"], "library")
    except ValueError as exc:
        raise ProtocolError(str(exc)) from None
    return LibrarySnapshot(_version(fields["version"]), tuple(descriptions))


def encode_changes_reply(changes: LibraryChanges) -> bytes:
    """``{"v": 1, "version": N, "start": S, "library": <library JSON document of the
    descriptions added after the first S>}``."""
    return _dumps({"version": changes.version, "start": changes.start,
                   "library": descriptions_to_json(changes.added)})


def decode_changes_reply(data: bytes) -> LibraryChanges:
    fields = _fields(data, ("version", "start", "library"))
    try:
        added = descriptions_from_json(fields["library"], "library")
    except ValueError as exc:
        raise ProtocolError(str(exc)) from None
    return LibraryChanges(_version(fields["version"]), _version(fields["start"], "start"), tuple(added))


def encode_learn_reply(object_id: str) -> bytes:
    """``{"v": 1, "id": <the id the description was stored under>}``."""
    return _dumps({"id": object_id})


def decode_learn_reply(data: bytes) -> str:
    object_id = _fields(data, ("id",))["id"]
    if not isinstance(object_id, str) or not object_id:
        raise ProtocolError(f"id: must be a non-empty string, got {object_id!r}")
    return object_id


def encode_recorded_reply(count: int) -> bytes:
    """``{"v": 1, "recorded": N}``: how many attempts the request carried, now counted
    (a retried request's too: they were counted once, by the first)."""
    return _dumps({"recorded": count})


def decode_recorded_reply(data: bytes) -> int:
    return _version(_fields(data, ("recorded",))["recorded"], "recorded")


def encode_grasp_costs_reply(records: Sequence[GraspCostRecord]) -> bytes:
    """``{"v": 1, "grasp_costs": [{"grasp", "successes", "success_s", "failures",
    "failure_s"}, ...]}``: each grasp's running totals (docs/library-format.md)."""
    return _dumps({"grasp_costs": [{"grasp": r.grasp, "successes": r.successes, "success_s": r.success_s,
                                    "failures": r.failures, "failure_s": r.failure_s} for r in records]})


def decode_grasp_costs_reply(data: bytes) -> list[GraspCostRecord]:
    records = _fields(data, ("grasp_costs",))["grasp_costs"]
    if not isinstance(records, list):
        raise ProtocolError(f"grasp_costs: must be a list, got {type(records).__name__}")
    return [_grasp_cost(r, f"grasp_costs[{i}]") for i, r in enumerate(records)]


def _grasp_cost(entry: object, where: str) -> GraspCostRecord:
    names = ("grasp", "successes", "success_s", "failures", "failure_s")
    if not isinstance(entry, dict) or set(entry) != set(names):
        raise ProtocolError(f"{where}: must be an object with exactly {', '.join(names)}")
    grasp = entry["grasp"]
    if not isinstance(grasp, str) or not grasp:
        raise ProtocolError(f"{where}: grasp must be a non-empty string, got {grasp!r:.80}")
    totals = [entry[k] for k in ("success_s", "failure_s")]
    if any(isinstance(t, bool) or not isinstance(t, (int, float)) or not 0 <= t < math.inf for t in totals):
        raise ProtocolError(f"{where}: success_s and failure_s must be finite numbers >= 0")
    return GraspCostRecord(grasp, _version(entry["successes"], f"{where}: successes"), float(entry["success_s"]),
                           _version(entry["failures"], f"{where}: failures"), float(entry["failure_s"]))


def encode_version_reply(version: int) -> bytes:
    """``{"v": 1, "version": N}``."""
    return _dumps({"version": version})


def decode_version_reply(data: bytes) -> int:
    return _version(_fields(data, ("version",))["version"])


def encode_error(code: str, message: str) -> bytes:
    """The ``reply_err`` body: ``{"v": 1, "code": ..., "message": ...}``."""
    if code not in ERROR_CODES:
        raise ProtocolError(f"code: {code!r} is not a protocol error code")
    return _dumps({"code": code, "message": message})


def decode_error(data: bytes) -> tuple[str, str]:
    """``(code, message)`` of an error reply."""
    fields = _fields(data, ("code", "message"))
    code, message = fields["code"], fields["message"]
    if code not in ERROR_CODES:
        raise ProtocolError(f"code: {code!r} is not a protocol error code")
    if not isinstance(message, str):
        raise ProtocolError(f"message: must be a string, got {message!r}")
    return cast(str, code), message


# -- helpers --------------------------------------------------------------------------
def _dumps(fields: Mapping[str, object]) -> bytes:
    return json.dumps({"v": PROTOCOL_VERSION, **fields}, ensure_ascii=False, allow_nan=False).encode()


def _fields(data: bytes, expected: tuple[str, ...], optional: tuple[str, ...] = ()) -> dict[str, object]:
    """The fields of a message that must carry exactly ``"v"`` and ``expected``, and may
    carry ``optional``."""
    if not data:
        raise ProtocolError(f'empty payload: messages are JSON objects with "v": {PROTOCOL_VERSION}')
    try:
        message = parse_json(data.decode("utf-8"))
    except (UnicodeDecodeError, NotJson) as exc:
        raise ProtocolError(f"not valid JSON: {exc}") from None
    if not isinstance(message, dict):
        raise ProtocolError(f"a message must be a JSON object, got {type(message).__name__}")
    if whole_number(message.get("v")) != PROTOCOL_VERSION:
        raise ProtocolError(f"v: unsupported protocol version {message.get('v')!r} "
                            f"(this learner speaks {PROTOCOL_VERSION})")
    unknown = sorted(set(message) - {"v", *expected, *optional})
    if unknown:
        raise ProtocolError(f"unknown field {unknown[0]!r}")
    missing = [f for f in expected if f not in message]
    if missing:
        raise ProtocolError(f"missing field {missing[0]!r}")
    return message


def _version(value: object, field: str = "version") -> int:
    whole = whole_number(value)
    if whole is None or whole < 0:
        raise ProtocolError(f"{field}: must be a non-negative integer, got {value!r}")
    return whole


def _entry(description: ObjectDescription) -> object:
    entries = cast(list[object], descriptions_to_json([description])["descriptions"])
    return entries[0]


def _description(entry: object, where: str) -> ObjectDescription:
    document = {"format": FORMAT, "version": VERSION, "descriptions": [entry]}
    try:
        return descriptions_from_json(document, where)[0]
    except ValueError as exc:
        raise ProtocolError(str(exc)) from None
