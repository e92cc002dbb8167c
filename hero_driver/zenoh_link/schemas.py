"""JSON Schemas (draft 2020-12) of every driver-protocol message, for vendors who
validate in C, C++, Rust or anything else that has a JSON Schema validator.

The codec (:mod:`.codec`) stays the authority; these schemas say the same thing in a
language-neutral form, and ``tests/hero_driver/test_zenoh_schemas.py`` holds the two
together: every message the codec writes validates, and the schemas refuse what the
codec refuses (mutated messages are fed to both). What a schema cannot say is listed
in docs/driver-protocol.md: that ``image.data`` decodes to an H x W image, and that
``NaN``/``Infinity`` are refused (they are not JSON, so a JSON parser refuses them).

``python -m hero_driver.zenoh_link.schemas DIR`` writes them as ``DIR/<name>.json``;
``docs/schemas/`` holds the published set.
"""

from __future__ import annotations

import json
import sys
from collections.abc import Mapping, Sequence
from pathlib import Path
from typing import Any

from hero_driver.interface import (
    ERROR_CODES,
    PROTOCOL_VERSION,
    CameraImage,
    GraspResult,
    MoveResult,
    RobotState,
    SenseResult,
)
from hero_driver.zenoh_link.codec import EmptyRequest, MoveRequest, ProcedureRequest, ResetRequest, WaitRequest
from hero_driver.zenoh_link.verbs import VERBS, Verb
from hero_driver.zenoh_link.versions import Greeting

Schema = dict[str, Any]
DIALECT = "https://json-schema.org/draft/2020-12/schema"

NUMBER: Schema = {"type": "number"}
NOT_NEGATIVE: Schema = {"type": "number", "minimum": 0}
BOOLEAN: Schema = {"type": "boolean"}
INTEGER: Schema = {"type": "integer"}  # 3.0 counts, as the codec's integers do
NAME: Schema = {"type": "string", "minLength": 1}
TEXT: Schema = {"type": "string"}
NULL: Schema = {"type": "null"}


def _or_null(schema: Schema) -> Schema:
    return {"anyOf": [schema, NULL]}


def _numbers(count: int) -> Schema:
    return {"type": "array", "items": NUMBER, "minItems": count, "maxItems": count}


def _object(fields: Mapping[str, Schema], optional: Sequence[str] = ()) -> Schema:
    """An object with exactly ``fields`` (those in ``optional`` may be left out)."""
    return {"type": "object", "properties": dict(fields),
            "required": [name for name in fields if name not in optional],
            "additionalProperties": False}


POSE = _object({"x_in": NUMBER, "y_in": NUMBER, "heading_deg": NUMBER})
STATE_FIELDS: Mapping[str, Schema] = {"pose": POSE, "clock_s": NOT_NEGATIVE,
                                      "battery": {"type": "number", "minimum": 0, "maximum": 1}}
IMAGE = _object({
    "format": {"enum": ["png", "raw"]},
    "height": {"type": "integer", "minimum": 1},
    "width": {"type": "integer", "minimum": 1},
    "data": {"type": "string", "pattern": "^[A-Za-z0-9+/]*={0,2}$"},
})

Fields = tuple[Mapping[str, Schema], Sequence[str]]  # a body's fields, and which of them are optional

# A message shape's fields (codec.Message.value): the verb table says which shape
# each verb sends and answers, so a verb of known shapes needs nothing added here.
REQUEST_FIELDS: Mapping[type, Fields] = {
    MoveRequest: ({"waypoints": {"type": "array", "items": POSE, "minItems": 1},
                   "face": _or_null(_numbers(2))}, ("face",)),
    ProcedureRequest: ({"procedure": NAME}, ()),
    EmptyRequest: ({}, ()),
    ResetRequest: ({"world": _or_null(NAME), "seed": _or_null(INTEGER)}, ("world", "seed")),
    WaitRequest: ({"seconds": {"type": "number", "minimum": 0, "maximum": 3600}}, ()),
}
REPLY_FIELDS: Mapping[type, Fields] = {
    MoveResult: ({"pose": POSE, "duration_s": NOT_NEGATIVE, "collided": BOOLEAN, "centred": BOOLEAN,
                  "blocked": _object({"x_in": NUMBER, "y_in": NUMBER, "radius_in": NOT_NEGATIVE})}, ("blocked",)),
    SenseResult: ({"procedure": NAME,
                   "values": {"type": "object", "propertyNames": NAME,
                              "additionalProperties": _or_null(NUMBER)},
                   "duration_s": NOT_NEGATIVE, "distance_in": NOT_NEGATIVE}, ()),
    GraspResult: ({"procedure": NAME, "success": BOOLEAN, "duration_s": NOT_NEGATIVE}, ()),
    RobotState: (STATE_FIELDS, ()),
    CameraImage: ({"image": IMAGE, "inches_per_pixel": {"type": "number", "exclusiveMinimum": 0},
                   "origin_x_in": NUMBER, "origin_y_in": NUMBER,
                   "camera_matrix": _or_null({"type": "array", "items": _numbers(3), "minItems": 3, "maxItems": 3}),
                   "fisheye": _or_null(_numbers(4)), "clock_s": NOT_NEGATIVE, "meta": {"type": "object"}},
                  ("camera_matrix", "fisheye", "clock_s", "meta")),
    type(None): ({}, ()),
    Greeting: ({"versions": {"type": "array", "items": {"type": "integer", "minimum": 1},
                             "minItems": 1, "uniqueItems": True},
                "features": {"type": "array", "items": NAME, "uniqueItems": True},
                "profile": _object({"name": NAME, "sha256": {"type": "string", "pattern": "^[0-9a-f]{64}$"}}),
                "dock": POSE, "safety_in": NOT_NEGATIVE},
               ("profile", "dock", "safety_in")),
}
# The ``profile`` field comes exactly when the ``profile`` feature is listed, ``dock``
# exactly when ``battery`` is, ``safety_in`` exactly when ``blocked_moves`` is.
LISTS_PROFILE: Schema = {"properties": {"features": {"contains": {"const": "profile"}}}}
LISTS_BATTERY: Schema = {"properties": {"features": {"contains": {"const": "battery"}}}}
LISTS_BLOCKED_MOVES: Schema = {"properties": {"features": {"contains": {"const": "blocked_moves"}}}}
CONDITIONS: Mapping[type, Schema] = {
    Greeting: {"allOf": [
        {"if": {"required": ["profile"]}, "then": LISTS_PROFILE, "else": {"not": LISTS_PROFILE}},
        {"if": {"required": ["dock"]}, "then": LISTS_BATTERY, "else": {"not": LISTS_BATTERY}},
        {"if": {"required": ["safety_in"]}, "then": LISTS_BLOCKED_MOVES, "else": {"not": LISTS_BLOCKED_MOVES}}]},
}
"""What a reply of a shape must say beyond its fields."""


def verb_fields(verb: Verb) -> tuple[Fields, Fields]:
    """The fields of ``verb``'s request and of its reply, from its message shapes."""
    return REQUEST_FIELDS[verb.request.value], REPLY_FIELDS[verb.reply.value]


def message(title: str, fields: Mapping[str, Schema], optional: Sequence[str] = ()) -> Schema:
    """A top-level message: ``fields`` plus the protocol version ``v``."""
    body = _object({"v": {"const": PROTOCOL_VERSION}, **fields}, optional)
    return {"$schema": DIALECT, "title": title, **body}


def all_schemas() -> dict[str, Schema]:
    """Every message's schema by file stem: ``<verb>.request``, ``<verb>.reply``
    (every verb of the table), ``state`` and ``error``."""
    schemas: dict[str, Schema] = {}
    for verb in VERBS:
        (request, request_optional), (reply, reply_optional) = verb_fields(verb)
        schemas[f"{verb.name}.request"] = message(
            f"{verb.name} request (query payload on hero/<robot>/rpc/{verb.name})", request, request_optional)
        schemas[f"{verb.name}.reply"] = message(f"{verb.name} reply (query.reply payload)", reply, reply_optional)
        schemas[f"{verb.name}.reply"].update(CONDITIONS.get(verb.reply.value, {}))
    schemas["state"] = message("state publication on hero/<robot>/state", STATE_FIELDS)
    schemas["error"] = message("error reply (query.reply_err payload) of any verb",
                               {"code": {"enum": sorted(ERROR_CODES)}, "message": TEXT})
    return schemas


def render(schema: Schema) -> str:
    """The file text of one schema (stable, so the published files can be compared)."""
    return json.dumps(schema, indent=2, ensure_ascii=False) + "\n"


def write(folder: Path) -> list[Path]:
    """Write every schema into ``folder`` (created if missing); the paths written."""
    folder.mkdir(parents=True, exist_ok=True)
    written = []
    for name, schema in all_schemas().items():
        path = folder / f"{name}.json"
        path.write_text(render(schema), encoding="utf-8")
        written.append(path)
    return written


def main(argv: Sequence[str]) -> int:
    if len(argv) != 1:
        print("usage: python -m hero_driver.zenoh_link.schemas DIR", file=sys.stderr)
        return 2
    for path in write(Path(argv[0])):
        print(path)
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
