"""JSON wire format of the driver protocol: interface dataclasses <-> bytes.

Every message is a JSON object carrying ``"v": PROTOCOL_VERSION``. Decoding is strict
(a missing, unknown or mistyped field, a non-finite number, a wrong version) because a
driver written by another team in another language must fail loudly at the boundary,
with the offending field named, rather than hand the executive a half-right value.
Encoding applies the same checks, so a Python driver that returns a wrong type is
caught on its own side before anything is sent.

Problems raise :class:`CodecError` naming the field path (``waypoints[1].x_in``); the
node answers them as ``bad_request``, the client reports a malformed reply as
``internal``. The formats are specified in ``docs/driver-protocol.md``; which codec
each verb's request and reply use is said once, in the verb table (:mod:`.verbs`).
"""

from __future__ import annotations

import base64
import binascii
import json
import math
import numbers
import sys
from collections.abc import Callable, Mapping, Sequence
from dataclasses import dataclass
from typing import Any

import cv2
import numpy as np

from camera_model.image import CameraImage
from hero_driver.interface import (
    ERROR_CODES, PROTOCOL_VERSION, DriverError, GraspResult, Hello, MoveResult, Obstacle, Pose, RangeScan, RobotState,
    SenseResult,
)
from hero_driver.zenoh_link.versions import BATTERY, BLOCKED_MOVES, PROFILE, Greeting
from zenoh_rpc.numbers import whole_number
from robot_profile import ProfileStamp

Json = dict[str, Any]

MAX_REQUEST_BYTES = 128 * 1024
"""The largest request payload a driver reads: a move of :data:`MAX_WAYPOINTS` poses
whose numbers take the longest form JSON gives a double is about 100 KiB (a test
holds it under this cap); anything larger is refused before it is parsed, so a 44 MB move
costs the driver no more than its length check."""
MAX_SCAN_BEAMS = 3600
"""The most beams one ``scan`` reply may carry: a tenth of a degree over a full turn."""
MAX_WAYPOINTS = 1000
"""The most waypoints one ``move`` may carry: the planner's paths have tens; a
million would keep the robot busy for minutes on a single request."""


class CodecError(ValueError):
    """A message that does not follow the protocol; the text starts with the field."""


# ----------------------------------------------------------------------------- requests


@dataclass(frozen=True)
class MoveRequest:
    """``move``'s arguments; the sequences are kept as tuples whatever the caller
    passed (a list of poses), so a request is a value."""

    waypoints: tuple[Pose, ...]
    face: tuple[float, float] | None = None

    def __post_init__(self) -> None:
        object.__setattr__(self, "waypoints", tuple(self.waypoints))
        object.__setattr__(self, "face", None if self.face is None else tuple(self.face))


@dataclass(frozen=True)
class ProcedureRequest:
    """``sense`` and ``grasp`` name one procedure of the robot's knowledge."""

    procedure: str


@dataclass(frozen=True)
class ResetRequest:
    world: str | None = None
    seed: int | None = None


@dataclass(frozen=True)
class WaitRequest:
    """``wait`` (the ``blocked_moves`` feature): stand still this many seconds."""

    seconds: float


@dataclass(frozen=True)
class EmptyRequest:
    """``release``, ``camera`` and ``noop`` take no arguments."""


Request = MoveRequest | ProcedureRequest | ResetRequest | WaitRequest | EmptyRequest
MAX_WAIT_S = 3600.0  # the longest wait a request may ask for


# --------------------------------------------------------------------------- primitives


def loads(data: bytes) -> Json:
    """Parse one protocol message: a JSON object of the supported version.

    ``NaN`` and ``Infinity`` (which some JSON writers emit) are parsed so that the
    field holding one can be named when it is rejected.
    """
    try:
        message = json.loads(bytes(data).decode("utf-8"))
    except UnicodeDecodeError as exc:
        raise CodecError(f"message: not UTF-8 ({exc.reason})") from None
    except json.JSONDecodeError as exc:
        raise CodecError(f"message: malformed JSON ({exc.msg} at char {exc.pos})") from None
    except RecursionError:  # no message of the protocol nests more than a few levels
        raise CodecError("message: JSON nested too deeply") from None
    except ValueError:  # int() refusing a literal of more than 4,300 digits
        raise CodecError(f"message: an integer of more than {sys.get_int_max_str_digits()} digits") from None
    if not isinstance(message, dict):
        raise CodecError(f"message: expected a JSON object, got {_kind(message)}")
    if "v" not in message:
        raise CodecError("v: missing field (the protocol version)")
    version = _integer(message["v"], "v")
    if version != PROTOCOL_VERSION:
        raise CodecError(f"v: protocol version {version} not supported (speaks {PROTOCOL_VERSION})")
    return message


def loads_request(data: bytes) -> Json:
    """:func:`loads` for a request, after checking its size against
    :data:`MAX_REQUEST_BYTES` (replies are not capped: a camera image is larger)."""
    if len(data) > MAX_REQUEST_BYTES:
        raise CodecError(f"message: {len(data)} bytes, more than the {MAX_REQUEST_BYTES} a request may have")
    return loads(data)


def dumps(fields: Json) -> bytes:
    """Serialise a message body, adding the version; never emits NaN or Infinity."""
    try:
        text = json.dumps({"v": PROTOCOL_VERSION, **fields}, allow_nan=False,
                          separators=(",", ":"), ensure_ascii=False)
    except (TypeError, ValueError) as exc:
        raise CodecError(f"message: not serialisable as JSON ({exc})") from None
    return text.encode("utf-8")


def _kind(value: object) -> str:
    if value is None:
        return "null"
    return {bool: "a boolean", str: "a string", list: "an array", dict: "an object",
            int: "an integer", float: "a number"}.get(type(value), type(value).__name__)


def _fields(obj: object, path: str, required: Sequence[str], optional: Sequence[str] = ()) -> Json:
    """Check that ``obj`` is an object with exactly the allowed keys."""
    if not isinstance(obj, dict):
        raise CodecError(f"{path or 'message'}: expected an object, got {_kind(obj)}")
    prefix = f"{path}." if path else ""
    for key in required:
        if key not in obj:
            raise CodecError(f"{prefix}{key}: missing field")
    allowed = set(required) | set(optional) | ({"v"} if not path else set())
    for key in obj:
        if key not in allowed:  # a key holding a newline must not split the line
            raise CodecError(f"{prefix}{key if key.isprintable() else repr(key)}: unknown field")
    return obj


def _real(value: object, path: str) -> float:
    if isinstance(value, (bool, np.bool_)) or not isinstance(value, numbers.Real):
        raise CodecError(f"{path}: expected a number, got {_kind(value)}")
    try:
        number = float(value)
    except OverflowError:  # an integer literal too long for a double
        raise CodecError(f"{path}: expected a finite number, got an integer of {len(str(value))} digits") from None
    if not math.isfinite(number):
        raise CodecError(f"{path}: expected a finite number, got {number}")
    return number


def _integer(value: object, path: str) -> int:
    """An integer by the wire's one rule (:func:`zenoh_rpc.numbers.whole_number`:
    ``3.0`` counts, as in JSON Schema)."""
    whole = whole_number(value)
    if whole is None:
        raise CodecError(f"{path}: expected an integer, got {_kind(value)}")
    return whole


def _boolean(value: object, path: str) -> bool:
    if not isinstance(value, (bool, np.bool_)):
        raise CodecError(f"{path}: expected a boolean, got {_kind(value)}")
    return bool(value)


def _text(value: object, path: str) -> str:
    if not isinstance(value, str):
        raise CodecError(f"{path}: expected a string, got {_kind(value)}")
    return value


def _name(value: object, path: str) -> str:
    text = _text(value, path)
    if not text:
        raise CodecError(f"{path}: expected a non-empty string")
    return text


def _between(number: float, low: float, high: float, path: str) -> float:
    if not low <= number <= high:
        raise CodecError(f"{path}: {number} outside [{low}, {high}]")
    return number


def _positive(number: float, path: str) -> float:
    if number <= 0:
        raise CodecError(f"{path}: expected a positive number, got {number}")
    return number


def _not_negative(number: float, path: str) -> float:
    if number < 0:
        raise CodecError(f"{path}: expected a number >= 0, got {number}")
    return number


def _array(value: object, path: str, length: int | None = None) -> Sequence[object]:
    if isinstance(value, (str, bytes, Mapping)) or not isinstance(value, (Sequence, np.ndarray)):
        raise CodecError(f"{path}: expected an array, got {_kind(value)}")
    if length is not None and len(value) != length:
        raise CodecError(f"{path}: expected {length} items, got {len(value)}")
    return value


def _reals(value: object, path: str, length: int) -> tuple[float, ...]:
    return tuple(_real(item, f"{path}[{i}]") for i, item in enumerate(_array(value, path, length)))


# ------------------------------------------------------------------------- value types


def _pose_out(pose: object, path: str) -> Json:
    if not isinstance(pose, Pose):
        raise CodecError(f"{path}: expected a Pose, got {type(pose).__name__}")
    return {"x_in": _real(pose.x_in, f"{path}.x_in"), "y_in": _real(pose.y_in, f"{path}.y_in"),
            "heading_deg": _real(pose.heading_deg, f"{path}.heading_deg")}


def _pose_in(obj: object, path: str) -> Pose:
    fields = _fields(obj, path, ("x_in", "y_in", "heading_deg"))
    return Pose(_real(fields["x_in"], f"{path}.x_in"), _real(fields["y_in"], f"{path}.y_in"),
                _real(fields["heading_deg"], f"{path}.heading_deg"))


def state_out(state: object) -> Json:
    if not isinstance(state, RobotState):
        raise CodecError(f"message: expected a RobotState, got {type(state).__name__}")
    return {"pose": _pose_out(state.pose, "pose"),
            "clock_s": _not_negative(_real(state.clock_s, "clock_s"), "clock_s"),
            "battery": _between(_real(state.battery, "battery"), 0.0, 1.0, "battery")}


def state_in(message: Json) -> RobotState:
    fields = _fields(message, "", ("pose", "clock_s", "battery"))
    return RobotState(_pose_in(fields["pose"], "pose"),
                      _not_negative(_real(fields["clock_s"], "clock_s"), "clock_s"),
                      _between(_real(fields["battery"], "battery"), 0.0, 1.0, "battery"))


def encode_state(state: RobotState) -> bytes:
    """The body of a ``hero/<robot>/state`` publication (also the reply of
    ``release`` and ``reset``)."""
    return dumps(state_out(state))


def decode_state(data: bytes) -> RobotState:
    return state_in(loads(data))


# ----------------------------------------------------------------------------- requests


def move_request_in(message: Json) -> MoveRequest:
    fields = _fields(message, "", ("waypoints",), ("face",))
    items = _waypoint_count(_array(fields["waypoints"], "waypoints"))
    face = fields.get("face")
    return MoveRequest(
        tuple(_pose_in(item, f"waypoints[{i}]") for i, item in enumerate(items)),
        None if face is None else _reals(face, "face", 2),  # type: ignore[arg-type]
    )


def move_request_out(request: MoveRequest) -> Json:
    items = _waypoint_count(_array(request.waypoints, "waypoints"))
    waypoints = [_pose_out(p, f"waypoints[{i}]") for i, p in enumerate(items)]
    face = None if request.face is None else list(_reals(request.face, "face", 2))
    return {"waypoints": waypoints, "face": face}


def _waypoint_count(items: Sequence[Any]) -> Sequence[Any]:
    if not items:
        raise CodecError("waypoints: expected at least one pose (the goal)")
    if len(items) > MAX_WAYPOINTS:
        raise CodecError(f"waypoints: {len(items)} poses, more than the {MAX_WAYPOINTS} a move may have")
    return items


def procedure_request_in(message: Json) -> ProcedureRequest:
    fields = _fields(message, "", ("procedure",))
    return ProcedureRequest(_name(fields["procedure"], "procedure"))


def reset_request_in(message: Json) -> ResetRequest:
    fields = _fields(message, "", (), ("world", "seed"))
    world, seed = fields.get("world"), fields.get("seed")
    return ResetRequest(None if world is None else _name(world, "world"),
                        None if seed is None else _integer(seed, "seed"))


def wait_request_in(message: Json) -> WaitRequest:
    fields = _fields(message, "", ("seconds",))
    return WaitRequest(_wait_seconds(fields["seconds"]))


def wait_request_out(request: WaitRequest) -> Json:
    return {"seconds": _wait_seconds(request.seconds)}


def _wait_seconds(value: object) -> float:
    seconds = _not_negative(_real(value, "seconds"), "seconds")
    if seconds > MAX_WAIT_S:
        raise CodecError(f"seconds: at most {MAX_WAIT_S:g}, got {seconds:g}")
    return seconds


def empty_request_in(message: Json) -> EmptyRequest:
    _fields(message, "", ())
    return EmptyRequest()


def procedure_request_out(request: ProcedureRequest) -> Json:
    return {"procedure": _name(request.procedure, "procedure")}


def reset_request_out(request: ResetRequest) -> Json:
    return {"world": None if request.world is None else _name(request.world, "world"),
            "seed": None if request.seed is None else _integer(request.seed, "seed")}


def empty_request_out(_request: EmptyRequest) -> Json:
    return {}


# ------------------------------------------------------------------------------ replies


def move_result_out(result: object) -> Json:
    if not isinstance(result, MoveResult):
        raise CodecError(f"message: expected a MoveResult, got {type(result).__name__}")
    return {"pose": _pose_out(result.pose, "pose"),
            "duration_s": _not_negative(_real(result.duration_s, "duration_s"), "duration_s"),
            "collided": _boolean(result.collided, "collided"),
            "centred": _boolean(result.centred, "centred"),
            **({} if result.blocked is None else {"blocked": _obstacle_out(result.blocked)})}


def move_result_in(message: Json) -> MoveResult:
    fields = _fields(message, "", ("pose", "duration_s", "collided", "centred"), ("blocked",))
    return MoveResult(_pose_in(fields["pose"], "pose"),
                      _not_negative(_real(fields["duration_s"], "duration_s"), "duration_s"),
                      _boolean(fields["collided"], "collided"),
                      _boolean(fields["centred"], "centred"),
                      _obstacle_in(fields["blocked"]) if "blocked" in fields else None)


def _obstacle_out(obstacle: Obstacle) -> Json:
    if not isinstance(obstacle, Obstacle):
        raise CodecError(f"blocked: expected an Obstacle, got {type(obstacle).__name__}")
    return {"x_in": _real(obstacle.x_in, "blocked.x_in"), "y_in": _real(obstacle.y_in, "blocked.y_in"),
            "radius_in": _not_negative(_real(obstacle.radius_in, "blocked.radius_in"), "blocked.radius_in")}


def _obstacle_in(value: object) -> Obstacle:
    fields = _fields(value, "blocked", ("x_in", "y_in", "radius_in"))
    return Obstacle(_real(fields["x_in"], "blocked.x_in"), _real(fields["y_in"], "blocked.y_in"),
                    _not_negative(_real(fields["radius_in"], "blocked.radius_in"), "blocked.radius_in"))


def _feature_values(values: object, path: str) -> dict[str, float | None]:
    if not isinstance(values, Mapping):
        raise CodecError(f"{path}: expected an object, got {_kind(values)}")
    out: dict[str, float | None] = {}
    for name, value in values.items():
        _name(name, f"{path} key")
        out[name] = None if value is None else _real(value, f"{path}.{name}")
    return out


def sense_result_out(result: object) -> Json:
    if not isinstance(result, SenseResult):
        raise CodecError(f"message: expected a SenseResult, got {type(result).__name__}")
    return {"procedure": _name(result.procedure, "procedure"),
            "values": _feature_values(result.values, "values"),
            "duration_s": _not_negative(_real(result.duration_s, "duration_s"), "duration_s"),
            "distance_in": _not_negative(_real(result.distance_in, "distance_in"), "distance_in")}


def sense_result_in(message: Json) -> SenseResult:
    fields = _fields(message, "", ("procedure", "values", "duration_s", "distance_in"))
    return SenseResult(_name(fields["procedure"], "procedure"),
                       _feature_values(fields["values"], "values"),
                       _not_negative(_real(fields["duration_s"], "duration_s"), "duration_s"),
                       _not_negative(_real(fields["distance_in"], "distance_in"), "distance_in"))


def grasp_result_out(result: object) -> Json:
    if not isinstance(result, GraspResult):
        raise CodecError(f"message: expected a GraspResult, got {type(result).__name__}")
    return {"procedure": _name(result.procedure, "procedure"),
            "success": _boolean(result.success, "success"),
            "duration_s": _not_negative(_real(result.duration_s, "duration_s"), "duration_s")}


def grasp_result_in(message: Json) -> GraspResult:
    fields = _fields(message, "", ("procedure", "success", "duration_s"))
    return GraspResult(_name(fields["procedure"], "procedure"),
                       _boolean(fields["success"], "success"),
                       _not_negative(_real(fields["duration_s"], "duration_s"), "duration_s"))


def range_scan_out(scan: object) -> Json:
    if not isinstance(scan, RangeScan):
        raise CodecError(f"message: expected a RangeScan, got {type(scan).__name__}")
    low, high = _range_limits(scan.range_min_in, scan.range_max_in)
    angles = _scan_angles(scan.angles_deg)
    ranges = _array(scan.ranges_in, "ranges_in", len(angles))
    return {"pose": _pose_out(scan.pose, "pose"),
            "clock_s": _not_negative(_real(scan.clock_s, "clock_s"), "clock_s"),
            "angles_deg": list(angles),
            "ranges_in": [None if _no_echo(r) else _scan_range(r, low, high, f"ranges_in[{i}]")
                          for i, r in enumerate(ranges)],
            "range_min_in": low, "range_max_in": high}


def range_scan_in(message: Json) -> RangeScan:
    fields = _fields(message, "", ("pose", "clock_s", "angles_deg", "ranges_in", "range_min_in", "range_max_in"))
    low, high = _range_limits(fields["range_min_in"], fields["range_max_in"])
    angles = _scan_angles(fields["angles_deg"])
    ranges = _array(fields["ranges_in"], "ranges_in", len(angles))
    return RangeScan(_pose_in(fields["pose"], "pose"),
                     _not_negative(_real(fields["clock_s"], "clock_s"), "clock_s"), angles,
                     tuple(math.inf if r is None else _scan_range(r, low, high, f"ranges_in[{i}]")
                           for i, r in enumerate(ranges)), low, high)


def _range_limits(low: object, high: object) -> tuple[float, float]:
    lo = _not_negative(_real(low, "range_min_in"), "range_min_in")
    hi = _real(high, "range_max_in")
    if hi <= lo:
        raise CodecError(f"range_max_in: {hi} is not above range_min_in {lo}")
    return lo, hi


def _scan_angles(value: object) -> tuple[float, ...]:
    """Beam angles: 1 to MAX_SCAN_BEAMS numbers in [-180, 180), strictly increasing."""
    items = _array(value, "angles_deg")
    if not 1 <= len(items) <= MAX_SCAN_BEAMS:
        raise CodecError(f"angles_deg: expected 1 to {MAX_SCAN_BEAMS} beams, got {len(items)}")
    angles = tuple(_real(item, f"angles_deg[{i}]") for i, item in enumerate(items))
    for i, angle in enumerate(angles):
        if not -180.0 <= angle < 180.0:
            raise CodecError(f"angles_deg[{i}]: {angle} outside [-180, 180) degrees")
        if i and angle <= angles[i - 1]:
            raise CodecError(f"angles_deg[{i}]: {angle} does not increase on the beam before it ({angles[i - 1]})")
    return angles


def _no_echo(value: object) -> bool:
    return isinstance(value, float) and value == math.inf


def _scan_range(value: object, low: float, high: float, path: str) -> float:
    return _between(_real(value, path), low, high, path)


def _pixels_out(pixels: object) -> Json:
    if not isinstance(pixels, np.ndarray) or pixels.dtype != np.uint8 or pixels.ndim != 2:
        raise CodecError("image: expected an HxW uint8 array")
    if 0 in pixels.shape:
        raise CodecError(f"image: expected a non-empty image, got shape {pixels.shape}")
    ok, png = cv2.imencode(".png", np.ascontiguousarray(pixels))
    if not ok:
        raise CodecError("image: PNG encoding failed")
    return {"format": "png", "height": int(pixels.shape[0]), "width": int(pixels.shape[1]),
            "data": base64.b64encode(png.tobytes()).decode("ascii")}


def _pixels_in(obj: object) -> np.ndarray:
    fields = _fields(obj, "image", ("format", "height", "width", "data"))
    height = _integer(fields["height"], "image.height")
    width = _integer(fields["width"], "image.width")
    if height <= 0 or width <= 0:
        raise CodecError(f"image: expected a positive height and width, got {height}x{width}")
    try:
        raw = base64.b64decode(_text(fields["data"], "image.data"), validate=True)
    except binascii.Error as exc:
        raise CodecError(f"image.data: not base64 ({exc})") from None
    image_format = _text(fields["format"], "image.format")
    if image_format == "raw":
        if len(raw) != height * width:
            raise CodecError(f"image.data: {len(raw)} bytes, expected height*width = {height * width}")
        return np.frombuffer(raw, dtype=np.uint8).reshape(height, width).copy()
    if image_format != "png":
        raise CodecError(f"image.format: expected 'png' or 'raw', got {image_format!r}")
    pixels = cv2.imdecode(np.frombuffer(raw, dtype=np.uint8), cv2.IMREAD_UNCHANGED)
    if pixels is None or pixels.dtype != np.uint8 or pixels.ndim != 2:
        raise CodecError("image.data: not an 8-bit grayscale PNG")
    if pixels.shape != (height, width):
        raise CodecError(f"image.data: PNG is {pixels.shape[0]}x{pixels.shape[1]}, "
                         f"declared {height}x{width}")
    return pixels


def _meta_out(meta: object) -> Json:
    if not isinstance(meta, Mapping):
        raise CodecError(f"meta: expected a mapping, got {type(meta).__name__}")
    for key in meta:
        _text(key, "meta key")
    try:
        # Round-trip so numpy values become plain JSON and anything else is refused.
        return json.loads(json.dumps(dict(meta), allow_nan=False, default=_numpy_to_json))
    except (TypeError, ValueError) as exc:
        raise CodecError(f"meta: not serialisable as JSON ({exc})") from None


def _finite_json(value: object, path: str) -> None:
    """Free-form JSON (``meta``) may hold any value but a non-finite number."""
    if isinstance(value, float):
        _real(value, path)
    elif isinstance(value, dict):
        for key, item in value.items():
            _finite_json(item, f"{path}.{key}")
    elif isinstance(value, list):
        for i, item in enumerate(value):
            _finite_json(item, f"{path}[{i}]")


def _numpy_to_json(value: object) -> object:
    if isinstance(value, (np.ndarray, np.generic)):
        return value.tolist()
    raise TypeError(f"{type(value).__name__} is not JSON")


def camera_out(image: object) -> Json:
    if not isinstance(image, CameraImage):
        raise CodecError(f"message: expected a CameraImage, got {type(image).__name__}")
    matrix = None
    if image.camera_matrix is not None:
        rows = _array(image.camera_matrix, "camera_matrix", 3)
        matrix = [list(_reals(row, f"camera_matrix[{i}]", 3)) for i, row in enumerate(rows)]
    return {"image": _pixels_out(image.pixels),
            "inches_per_pixel": _positive(_real(image.inches_per_pixel, "inches_per_pixel"),
                                          "inches_per_pixel"),
            "origin_x_in": _real(image.origin_x_in, "origin_x_in"),
            "origin_y_in": _real(image.origin_y_in, "origin_y_in"),
            "camera_matrix": matrix,
            "fisheye": None if image.fisheye is None else list(_reals(image.fisheye, "fisheye", 4)),
            "clock_s": _not_negative(_real(image.clock_s, "clock_s"), "clock_s"),
            "meta": _meta_out(image.meta)}


def camera_in(message: Json) -> CameraImage:
    fields = _fields(message, "", ("image", "inches_per_pixel", "origin_x_in", "origin_y_in"),
                     ("camera_matrix", "fisheye", "clock_s", "meta"))
    matrix = fields.get("camera_matrix")
    if matrix is not None:
        rows = _array(matrix, "camera_matrix", 3)
        matrix = np.array([_reals(row, f"camera_matrix[{i}]", 3) for i, row in enumerate(rows)])
    fisheye = fields.get("fisheye")
    if fisheye is not None and matrix is None:  # CameraImage refuses it too; here it is the driver's fault
        raise CodecError("fisheye: given without the camera_matrix that undistorts it")
    meta = fields.get("meta", {})
    if not isinstance(meta, dict):
        raise CodecError(f"meta: expected an object, got {_kind(meta)}")
    _finite_json(meta, "meta")
    return CameraImage(
        pixels=_pixels_in(fields["image"]),
        inches_per_pixel=_positive(_real(fields["inches_per_pixel"], "inches_per_pixel"),
                                   "inches_per_pixel"),
        origin_x_in=_real(fields["origin_x_in"], "origin_x_in"),
        origin_y_in=_real(fields["origin_y_in"], "origin_y_in"),
        camera_matrix=matrix,
        fisheye=None if fisheye is None else _reals(fisheye, "fisheye", 4),  # type: ignore[arg-type]
        clock_s=_not_negative(_real(fields.get("clock_s", 0.0), "clock_s"), "clock_s"),
        meta=meta,
    )


def hello_out(hello: object) -> Json:
    """A :class:`Greeting`, or a bare :class:`Hello` (a driver naming no profile)."""
    if isinstance(hello, Hello):
        hello = Greeting(hello)
    if not isinstance(hello, Greeting):
        raise CodecError(f"message: expected a Greeting or a Hello, got {type(hello).__name__}")
    fields: Json = {"versions": _versions(hello.served.versions), "features": _features(hello.served.features)}
    if hello.profile is not None:
        fields["profile"] = {"name": _name(hello.profile.name, "profile.name"),
                             "sha256": _sha256(hello.profile.sha256, "profile.sha256")}
    if hello.dock is not None:
        fields["dock"] = _pose_out(hello.dock, "dock")
    if hello.safety_in is not None:
        fields["safety_in"] = _not_negative(_real(hello.safety_in, "safety_in"), "safety_in")
    _listed(fields["features"], "profile", PROFILE, hello.profile is not None)
    _listed(fields["features"], "dock", BATTERY, hello.dock is not None)
    _listed(fields["features"], "safety_in", BLOCKED_MOVES, hello.safety_in is not None)
    return fields


def hello_in(message: Json) -> Greeting:
    fields = _fields(message, "", ("versions", "features"), ("profile", "dock", "safety_in"))
    served = Hello(tuple(_versions(fields["versions"])), tuple(_features(fields["features"])))
    profile = None
    if "profile" in fields:
        body = _fields(fields["profile"], "profile", ("name", "sha256"))
        profile = ProfileStamp(_name(body["name"], "profile.name"), _sha256(body["sha256"], "profile.sha256"))
    _listed(served.features, "profile", PROFILE, profile is not None)
    _listed(served.features, "dock", BATTERY, "dock" in fields)
    _listed(served.features, "safety_in", BLOCKED_MOVES, "safety_in" in fields)
    safety = _not_negative(_real(fields["safety_in"], "safety_in"), "safety_in") if "safety_in" in fields else None
    return Greeting(served, profile, _pose_in(fields["dock"], "dock") if "dock" in fields else None, safety)


def _sha256(value: object, path: str) -> str:
    text = _text(value, path)
    if len(text) != 64 or not set(text) <= set("0123456789abcdef"):
        raise CodecError(f"{path}: expected 64 lowercase hex digits, got {text!r}")
    return text


def _listed(features: Sequence[str], field: str, feature: str, stated: bool) -> None:
    """Field ``field`` and feature ``feature`` come together or not at all (``profile``
    with ``profile``, ``dock`` with ``battery``)."""
    if stated != (feature in features):
        raise CodecError(f"{field}: sent without the '{feature}' feature" if stated
                         else f"{field}: missing field (the '{feature}' feature is listed)")


def _versions(value: object) -> list[int]:
    items = [_integer(item, f"versions[{i}]") for i, item in enumerate(_array(value, "versions"))]
    if not items:
        raise CodecError("versions: expected at least one version")
    for i, version in enumerate(items):
        if version < 1:
            raise CodecError(f"versions[{i}]: expected an integer >= 1, got {version}")
    return _distinct(items, "versions")


def _features(value: object) -> list[str]:
    names = [_name(item, f"features[{i}]") for i, item in enumerate(_array(value, "features"))]
    return _distinct(names, "features")


def _distinct(items: list[Any], path: str) -> list[Any]:
    for i, item in enumerate(items):
        if item in items[:i]:
            raise CodecError(f"{path}[{i}]: {item!r} listed twice")
    return items


def noop_out(result: object) -> Json:
    if result is not None:
        raise CodecError(f"message: noop returns nothing, got {type(result).__name__}")
    return {}


def noop_in(message: Json) -> None:
    _fields(message, "", ())


# ------------------------------------------------------------------------ message shapes


@dataclass(frozen=True)
class Message:
    """One message shape of the protocol: the value it carries and the pair of codec
    functions between that value and the message's JSON body (``v`` aside).

    Verbs share shapes (``sense`` and ``grasp`` send a :class:`ProcedureRequest`, five
    verbs answer a :class:`RobotState`), so a new verb that sends and answers known
    shapes names two of these in its row of the verb table and adds no codec; the
    published schemas (:mod:`.schemas`) are keyed by the same ``value`` types.
    """

    value: type
    read: Callable[[Json], Any]
    write: Callable[[Any], Json]


# requests
MOVE = Message(MoveRequest, move_request_in, move_request_out)
PROCEDURE = Message(ProcedureRequest, procedure_request_in, procedure_request_out)
RESET = Message(ResetRequest, reset_request_in, reset_request_out)
WAIT = Message(WaitRequest, wait_request_in, wait_request_out)
EMPTY = Message(EmptyRequest, empty_request_in, empty_request_out)
# replies
MOVED = Message(MoveResult, move_result_in, move_result_out)
SENSED = Message(SenseResult, sense_result_in, sense_result_out)
GRASPED = Message(GraspResult, grasp_result_in, grasp_result_out)
STATE = Message(RobotState, state_in, state_out)
IMAGE = Message(CameraImage, camera_in, camera_out)
GREETING = Message(Greeting, hello_in, hello_out)
SCANNED = Message(RangeScan, range_scan_in, range_scan_out)
NOTHING = Message(type(None), noop_in, noop_out)


# ------------------------------------------------------------------------------- errors


def encode_error(code: str, message: str) -> bytes:
    """The ``reply_err`` body: ``{"v": 1, "code": ..., "message": ...}``."""
    if code not in ERROR_CODES:
        raise CodecError(f"code: {code!r} is not a protocol error code")
    return dumps({"code": code, "message": message})


def decode_error(data: bytes) -> DriverError:
    """The :class:`DriverError` an error reply stands for."""
    fields = _fields(loads(data), "", ("code", "message"))
    code = _text(fields["code"], "code")
    if code not in ERROR_CODES:
        raise CodecError(f"code: {code!r} is not a protocol error code")
    return DriverError(code, _text(fields["message"], "message"))
