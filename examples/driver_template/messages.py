"""The wire format of docs/driver-protocol.md: strict request parsing and replies with
exactly the listed fields.

Written from the protocol page and docs/schemas/ alone (no import of the executive),
so it is also a worked example for a driver in another language: every rule of
"Validation (driver side)" is one branch below, and every refusal names the field it
is about first (``waypoints[0].x_in: ...``), which is what ``csl driver check`` looks
for. Nothing here touches the robot; driver.py calls it, robot.py defines the values.
"""

from __future__ import annotations

import json
import math
from collections.abc import Callable
from typing import Any

from knowledge import Knowledge
from overhead import image_body
from robot import GraspResult, Image, MoveResult, Pose, RobotState, SenseResult

PROTOCOL_VERSION = 1
VERSIONS = (1,)  # what `hello` lists: the versions this driver serves
FEATURES = ("profile",)  # optional features offered: hello names the robot profile served


class BadRequest(ValueError):
    """A request the protocol refuses; the text starts with the offending field."""


class _NonFinite:
    """What `NaN`, `Infinity` and `-Infinity` parse to, so that the field holding one
    is named in the refusal (Python's json would otherwise accept them as floats)."""

    def __init__(self, word: str) -> None:
        self.word = word


# ------------------------------------------------------------------------ field types


def _number(value: Any, path: str) -> float:
    if isinstance(value, _NonFinite):
        raise BadRequest(f"{path}: {value.word} is not a number")
    if isinstance(value, bool) or not isinstance(value, (int, float)):
        raise BadRequest(f"{path}: expected a number, got {_kind(value)}")
    try:
        number = float(value)
    except OverflowError:
        raise BadRequest(f"{path}: {value} does not fit a 64-bit double") from None
    if not math.isfinite(number):
        raise BadRequest(f"{path}: {value} does not fit a 64-bit double")
    return number


def _integer(value: Any, path: str) -> int:
    number = _number(value, path)
    if isinstance(value, float) and not number.is_integer():
        raise BadRequest(f"{path}: expected an integer, got {value}")
    return int(value)


def _name(value: Any, path: str) -> str:
    if not isinstance(value, str):
        raise BadRequest(f"{path}: expected a non-empty string, got {_kind(value)}")
    if not value:
        raise BadRequest(f"{path}: expected a non-empty string, got \"\"")
    return value


def _object(value: Any, path: str, required: tuple[str, ...], optional: tuple[str, ...] = ()) -> dict:
    if not isinstance(value, dict):
        raise BadRequest(f"{path or 'request'}: expected a JSON object, got {_kind(value)}")
    prefix = f"{path}." if path else ""
    for name in value:
        if name not in required and name not in optional:
            raise BadRequest(f"{prefix}{name}: unknown field")
    for name in required:
        if name not in value:
            raise BadRequest(f"{prefix}{name}: missing")
    return value


def _pose(value: Any, path: str) -> Pose:
    fields = _object(value, path, ("x_in", "y_in", "heading_deg"))
    return Pose(_number(fields["x_in"], f"{path}.x_in"), _number(fields["y_in"], f"{path}.y_in"),
                _number(fields["heading_deg"], f"{path}.heading_deg"))


def _kind(value: Any) -> str:
    if isinstance(value, _NonFinite):
        return value.word
    return {dict: "an object", list: "an array", str: "a string", bool: "a boolean",
            type(None): "null"}.get(type(value), "a number")


# ------------------------------------------------------------------- verb requests


def _move(fields: dict) -> dict:
    waypoints = fields["waypoints"]
    if not isinstance(waypoints, list):
        raise BadRequest(f"waypoints: expected an array of poses, got {_kind(waypoints)}")
    if not waypoints:
        raise BadRequest("waypoints: expected at least one pose")
    face = fields.get("face")
    if face is not None:
        if not isinstance(face, list) or len(face) != 2:
            raise BadRequest(f"face: expected [x_in, y_in] or null, got {_kind(face)}")
        face = (_number(face[0], "face[0]"), _number(face[1], "face[1]"))
    return {"waypoints": [_pose(w, f"waypoints[{i}]") for i, w in enumerate(waypoints)], "face": face}


def _procedure(fields: dict) -> dict:
    return {"procedure": _name(fields["procedure"], "procedure")}


def _reset(fields: dict) -> dict:
    world, seed = fields.get("world"), fields.get("seed")
    return {"world": None if world is None else _name(world, "world"),
            "seed": None if seed is None else _integer(seed, "seed")}


def _nothing(_fields: dict) -> dict:
    return {}


# verb -> (required fields, optional fields, how to read them): docs/driver-protocol.md's table
REQUESTS: dict[str, tuple[tuple[str, ...], tuple[str, ...], Callable[[dict], dict]]] = {
    "move": (("waypoints",), ("face",), _move),
    "sense": (("procedure",), (), _procedure),
    "grasp": (("procedure",), (), _procedure),
    "release": ((), (), _nothing),
    "camera": ((), (), _nothing),
    "reset": ((), ("world", "seed"), _reset),
    "noop": ((), (), _nothing),
    "hello": ((), (), _nothing),
}


def parse_request(verb: str, payload: bytes) -> dict:
    """The request's fields as Python values; BadRequest naming the field otherwise."""
    try:
        text = payload.decode("utf-8")
    except UnicodeDecodeError as exc:
        raise BadRequest(f"request: not UTF-8 (byte {exc.start})") from None
    try:
        message = json.loads(text, parse_constant=_NonFinite)
    except ValueError as exc:
        raise BadRequest(f"request: not JSON ({exc})") from None
    required, optional, read = REQUESTS[verb]
    fields = _object(message, "", ("v", *required), optional)
    version = _integer(fields["v"], "v")
    if version not in VERSIONS:
        raise BadRequest(f"v: version {version} is not served (this driver serves {list(VERSIONS)})")
    return read(fields)


# -------------------------------------------------------------------------- replies


def _pose_out(pose: Pose) -> dict:
    return {"x_in": pose.x_in, "y_in": pose.y_in, "heading_deg": pose.heading_deg}


def state_body(state: RobotState) -> dict:
    return {"pose": _pose_out(state.pose), "clock_s": state.clock_s, "battery": state.battery}


def result_body(result: object) -> dict:
    """A verb's result as its reply fields, exactly those of the verb table."""
    if isinstance(result, MoveResult):
        return {"pose": _pose_out(result.pose), "duration_s": result.duration_s,
                "collided": result.collided, "centred": result.centred}
    if isinstance(result, SenseResult):
        return {"procedure": result.procedure, "values": dict(result.values),
                "duration_s": result.duration_s, "distance_in": result.distance_in}
    if isinstance(result, GraspResult):
        return {"procedure": result.procedure, "success": result.success, "duration_s": result.duration_s}
    if isinstance(result, RobotState):
        return state_body(result)
    if isinstance(result, Image):
        return image_body(result)
    raise TypeError(f"not a verb result: {type(result).__name__}")


def hello_body(knowledge: Knowledge) -> dict:
    """Versions, features and, as the ``profile`` feature asks, which robot profile
    this driver serves: a client planning with another refuses the robot."""
    return {"versions": list(VERSIONS), "features": list(FEATURES),
            "profile": {"name": knowledge.name, "sha256": knowledge.sha256}}


def encode(fields: dict) -> bytes:
    """A reply or publication: ``v`` plus the fields, strict JSON (NaN raises ValueError)."""
    return json.dumps({"v": PROTOCOL_VERSION, **fields}, allow_nan=False).encode("utf-8")


def error(code: str, message: str) -> bytes:
    """An error reply body: ``v``, ``code`` and a one-line ``message``, nothing else."""
    return encode({"code": code, "message": " ".join(message.split())})
