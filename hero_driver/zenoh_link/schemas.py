"""JSON Schemas (draft 2020-12) of every driver-protocol message, for vendors who
validate in C, C++, Rust or anything else that has a JSON Schema validator.

The codec (:mod:`.codec`) stays the authority; these schemas say the same thing in a
language-neutral form, and ``tests/hero_driver/test_zenoh_schemas.py`` holds the two
together: every message the codec writes validates, and the schemas refuse what the
codec refuses (mutated messages are fed to both). What a schema cannot say is listed
in docs/driver-protocol.md: that ``image.data`` decodes to an H x W image, that a
scan's ``angles_deg`` increase and its ``ranges_in`` are as many and within its range
limits, and that ``NaN``/``Infinity`` are refused (they are not JSON, so a JSON parser refuses them).

Every number carries its unit twice: in ``description``, the annotation every JSON
Schema tool keeps and shows (editors, documentation and code generators), and in
``x-unit``, for programs that check units without reading prose (draft 2020-12 collects
an unknown keyword as an annotation and never fails on it; the ``x-`` prefix is the
usual mark of an extension, as in OpenAPI).

The protocol's schemas are the same for every robot: ``sense.reply`` cannot name
features, because the codec (the client) accepts any feature name. A robot profile's
own ``<profile>.sense.reply`` schema (:func:`sense_reply_schema`) adds what its
profile says: which features each procedure yields, each with its unit, span and
meaning (docs/driver-protocol.md, "Sensing features").

``python -m hero_driver.zenoh_link.schemas DIR [PROFILE.toml ...]`` writes them as
``DIR/<name>.json``, with the sense reply of each profile given (by default, of each
profile shipped in ``hero_driver/profiles/``); ``docs/schemas/`` holds the published set.
"""

from __future__ import annotations

import json
import sys
from collections.abc import Mapping, Sequence
from pathlib import Path
from typing import Any, Protocol

from hero_driver.interface import (
    ERROR_CODES,
    PROTOCOL_VERSION,
    CameraImage,
    GraspResult,
    MoveResult,
    RangeScan,
    RobotState,
    SenseResult,
)
from hero_driver.zenoh_link.codec import (MAX_SCAN_BEAMS, EmptyRequest, MoveRequest, ProcedureRequest, ResetRequest,
                                         WaitRequest)
from hero_driver.zenoh_link.verbs import VERBS, Verb
from hero_driver.zenoh_link.versions import Greeting
from robot_profile import DEFAULT_PROFILE, RobotProfile, load_profile, profile_stamp

Schema = dict[str, Any]
DIALECT = "https://json-schema.org/draft/2020-12/schema"
FEATURES_SECTION = "docs/driver-protocol.md, Sensing features"

UNITS: Mapping[str, str] = {
    "in": "inches",
    "deg": "degrees",
    "s": "seconds",
    "in/px": "inches per pixel",
    "px": "pixels",
    "1": "no unit",
}
"""The units the protocol's numbers are in (``x-unit``), and how ``description`` says them."""

BOOLEAN: Schema = {"type": "boolean"}
INTEGER: Schema = {"type": "integer"}  # 3.0 counts, as the codec's integers do
NAME: Schema = {"type": "string", "minLength": 1}
TEXT: Schema = {"type": "string"}
NULL: Schema = {"type": "null"}


def quantity(unit: str, meaning: str, **bounds: float) -> Schema:
    """A number in ``unit`` (a key of :data:`UNITS`), with what it measures and any
    ``minimum``/``maximum``/``exclusiveMinimum`` it must keep."""
    return {"type": "number", **bounds, "description": f"{meaning}, in {UNITS[unit]}", "x-unit": unit}


def _or_null(schema: Schema) -> Schema:
    return {"anyOf": [schema, NULL]}


def _numbers(count: int, item: Schema, meaning: str) -> Schema:
    return {"type": "array", "items": item, "minItems": count, "maxItems": count, "description": meaning}


def _object(fields: Mapping[str, Schema], optional: Sequence[str] = ()) -> Schema:
    """An object with exactly ``fields`` (those in ``optional`` may be left out)."""
    return {"type": "object", "properties": dict(fields),
            "required": [name for name in fields if name not in optional],
            "additionalProperties": False}


POSE = _object({"x_in": quantity("in", "world x of the base centre"),
                "y_in": quantity("in", "world y of the base centre"),
                "heading_deg": quantity("deg", "heading counter-clockwise from world +x (any finite value, "
                                               "read modulo 360)")})
DURATION = quantity("s", "robot time the verb took", minimum=0)
CLOCK = quantity("s", "robot time spent since the last reset", minimum=0)
STATE_FIELDS: Mapping[str, Schema] = {
    "pose": POSE, "clock_s": CLOCK,
    "battery": {"type": "number", "minimum": 0, "maximum": 1,
                "description": "charge left, as a fraction of a full charge (0 empty, 1 full), no unit",
                "x-unit": "1"},
}
IMAGE = _object({
    "format": {"enum": ["png", "raw"]},
    "height": {"type": "integer", "minimum": 1, "description": "rows, in pixels", "x-unit": "px"},
    "width": {"type": "integer", "minimum": 1, "description": "columns, in pixels", "x-unit": "px"},
    "data": {"type": "string", "pattern": "^[A-Za-z0-9+/]*={0,2}$"},
})
SENSE_VALUE = _or_null({"type": "number",
                        "description": f"a feature's value in the unit its robot profile gives it "
                                       f"({FEATURES_SECTION}); null when the sonar heard no echo"})

Fields = tuple[Mapping[str, Schema], Sequence[str]]  # a body's fields, and which of them are optional

# A message shape's fields (codec.Message.value): the verb table says which shape
# each verb sends and answers, so a verb of known shapes needs nothing added here.
REQUEST_FIELDS: Mapping[type, Fields] = {
    MoveRequest: ({"waypoints": {"type": "array", "items": POSE, "minItems": 1},
                   "face": _or_null(_numbers(2, quantity("in", "world coordinate of the point to face"),
                                             "[x_in, y_in]: the world point to turn to after the last waypoint"))},
                  ("face",)),
    ProcedureRequest: ({"procedure": NAME}, ()),
    EmptyRequest: ({}, ()),
    ResetRequest: ({"world": _or_null(NAME), "seed": _or_null(INTEGER)}, ("world", "seed")),
    WaitRequest: ({"seconds": quantity("s", "how long to stand still", minimum=0, maximum=3600)}, ()),
}
SENSE_FIELDS: Mapping[str, Schema] = {
    "procedure": NAME,
    "values": {"type": "object", "propertyNames": NAME, "additionalProperties": SENSE_VALUE},
    "duration_s": DURATION,
    "distance_in": quantity("in", "sonar point to the target's near face along the heading", minimum=0),
}
REPLY_FIELDS: Mapping[type, Fields] = {
    MoveResult: ({"pose": POSE, "duration_s": DURATION, "collided": BOOLEAN, "centred": BOOLEAN,
                  "blocked": _object({"x_in": quantity("in", "world x of the obstacle's centre"),
                                      "y_in": quantity("in", "world y of the obstacle's centre"),
                                      "radius_in": quantity("in", "how far the obstacle's outline reaches from its "
                                                                  "centre", minimum=0)})},
                 ("blocked",)),
    SenseResult: (SENSE_FIELDS, ()),
    GraspResult: ({"procedure": NAME, "success": BOOLEAN, "duration_s": DURATION}, ()),
    RobotState: (STATE_FIELDS, ()),
    CameraImage: ({"image": IMAGE,
                   "inches_per_pixel": quantity("in/px", "side of a square pixel", exclusiveMinimum=0),
                   "origin_x_in": quantity("in", "world x of the top-left corner of pixel (0, 0)"),
                   "origin_y_in": quantity("in", "world y of the top-left corner of pixel (0, 0)"),
                   "camera_matrix": _or_null({"type": "array", "items": _numbers(3, quantity(
                       "px", "an entry of OpenCV's fisheye camera matrix K (fx, fy, cx, cy; the last row 0 0 1)"),
                       "a row of K"), "minItems": 3, "maxItems": 3}),
                   "fisheye": _or_null(_numbers(4, {"type": "number", "description": "a distortion coefficient, "
                                                    "no unit", "x-unit": "1"},
                                                "OpenCV's fisheye coefficients D = (k1, k2, k3, k4)")),
                   "clock_s": quantity("s", "robot clock when the image was taken", minimum=0),
                   "meta": {"type": "object"}},
                  ("camera_matrix", "fisheye", "clock_s", "meta")),
    RangeScan: ({"pose": POSE,
                 "clock_s": quantity("s", "robot clock when the scan was taken", minimum=0),
                 "angles_deg": {"type": "array", "minItems": 1, "maxItems": MAX_SCAN_BEAMS,
                                "items": quantity("deg", "a beam's direction in the robot's frame, counter-clockwise "
                                                         "from its heading (strictly increasing)",
                                                  minimum=-180, exclusiveMaximum=180),
                                "description": "the beams' directions"},
                 "ranges_in": {"type": "array", "minItems": 1, "maxItems": MAX_SCAN_BEAMS,
                               "items": _or_null(quantity("in", "how far from the base centre the beam met "
                                                                "something (null: no echo within the limits)",
                                                          minimum=0)),
                               "description": "one range per angle, in the same order"},
                 "range_min_in": quantity("in", "the nearest range the sensor measures", minimum=0),
                 "range_max_in": quantity("in", "the farthest range the sensor measures", exclusiveMinimum=0)},
                ()),
    type(None): ({}, ()),
    Greeting: ({"versions": {"type": "array", "items": {"type": "integer", "minimum": 1},
                             "minItems": 1, "uniqueItems": True},
                "features": {"type": "array", "items": NAME, "uniqueItems": True},
                "profile": _object({"name": NAME, "sha256": {"type": "string", "pattern": "^[0-9a-f]{64}$"}}),
                "dock": POSE,
                "safety_in": quantity("in", "how near ahead of the base, outline to outline, a moving obstacle "
                                            "stops a move", minimum=0)},
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


class Feature(Protocol):
    """What a schema needs of a profile's feature (the profile reader's ``FeatureSpec``,
    which is the learner's type, so it is named here only by its shape)."""

    @property
    def name(self) -> str: ...
    @property
    def unit(self) -> str: ...
    @property
    def error(self) -> float: ...
    @property
    def span(self) -> tuple[float, float]: ...
    @property
    def binary(self) -> bool: ...


def feature_schema(feature: Feature) -> Schema:
    """One feature's value as its profile gives it: a binary feature 0 or 1, any other a
    number within its span, in its unit; ``null`` when the sonar heard no echo."""
    where = f"{FEATURES_SECTION}, {feature.name}"
    if feature.binary:
        value: Schema = {"enum": [0, 1], "description": f"{feature.name}: 1 yes, 0 no ({where})",
                         "x-unit": feature.unit}
    else:
        low, high = feature.span
        value = {"type": "number", "minimum": low, "maximum": high,
                 "description": f"{feature.name}, in {UNITS.get(feature.unit, feature.unit)}, from {low:g} to "
                                f"{high:g}; expected error {feature.error:g} ({where})",
                 "x-unit": feature.unit}
    return _or_null(value)


def sense_reply_schema(profile: RobotProfile) -> Schema:
    """The sense reply of a robot of ``profile``: the protocol's ``sense.reply`` with
    the procedure one of the profile's and ``values`` exactly that procedure's features
    (:func:`feature_schema`). A reply that passes ``sense.reply`` and fails this one is
    well-formed but is not what this robot can have measured."""
    name = profile_stamp(profile).name
    fields = {**SENSE_FIELDS, "procedure": {**NAME, "enum": [procedure.name for procedure in profile.sensing]}}
    schema = message(f"sense reply (query.reply payload) of a robot of profile {name}", fields)
    schema["allOf"] = [
        {"if": {"properties": {"procedure": {"const": procedure.name}}},
         "then": {"properties": {"values": _object({f.name: feature_schema(f) for f in procedure.features})}}}
        for procedure in profile.sensing]
    return schema


def profile_schemas(profile: RobotProfile) -> dict[str, Schema]:
    """A profile's own schemas by file stem (``<profile>.sense.reply``)."""
    return {f"{profile_stamp(profile).name}.sense.reply": sense_reply_schema(profile)}


def shipped_profiles() -> list[Path]:
    """The profiles shipped beside the HERO 2000's, whose schemas ``docs/schemas/`` holds."""
    return sorted(DEFAULT_PROFILE.parent.glob("*.toml"))


def render(schema: Schema) -> str:
    """The file text of one schema (stable, so the published files can be compared)."""
    return json.dumps(schema, indent=2, ensure_ascii=False) + "\n"


def published(profiles: Sequence[RobotProfile]) -> dict[str, Schema]:
    """Every schema a folder holds: the protocol's and each profile's."""
    schemas = all_schemas()
    for profile in profiles:
        schemas.update(profile_schemas(profile))
    return schemas


def write(folder: Path, profiles: Sequence[RobotProfile]) -> list[Path]:
    """Write the protocol's schemas and those of ``profiles`` into ``folder`` (created if
    missing); the paths written."""
    folder.mkdir(parents=True, exist_ok=True)
    written = []
    for name, schema in published(profiles).items():
        path = folder / f"{name}.json"
        path.write_text(render(schema), encoding="utf-8")
        written.append(path)
    return written


def main(argv: Sequence[str]) -> int:
    if not argv:
        print("usage: python -m hero_driver.zenoh_link.schemas DIR [PROFILE.toml ...]", file=sys.stderr)
        return 2
    try:
        profiles = [load_profile(path) for path in (argv[1:] or shipped_profiles())]
    except (OSError, ValueError) as error:
        print(f"schemas: {error}", file=sys.stderr)
        return 2
    for path in write(Path(argv[0]), profiles):
        print(path)
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
