"""The wire codec: every interface value survives a round trip, and every way a
foreign driver or client can get a message wrong is refused with the field named."""

from __future__ import annotations

import base64
import json
import re

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from hypothesis.extra.numpy import arrays

from hero_driver.interface import (
    BAD_REQUEST,
    PROTOCOL_VERSION,
    CameraImage,
    DriverError,
    GraspResult,
    MoveResult,
    Pose,
    RobotState,
    SenseResult,
)
from hero_driver.zenoh_link import codec
from hero_driver.zenoh_link.codec import CodecError, EmptyRequest, MoveRequest, ProcedureRequest, ResetRequest
from hero_driver.zenoh_link.verbs import BY_NAME

finite = st.floats(allow_nan=False, allow_infinity=False, width=64)
not_negative = st.floats(min_value=0, max_value=1e9, allow_nan=False)
names = st.text(min_size=1, max_size=20)
poses = st.builds(Pose, finite, finite, finite)
states = st.builds(RobotState, poses, not_negative, st.floats(0, 1))


def body(**fields: object) -> bytes:
    return json.dumps({"v": PROTOCOL_VERSION, **fields}).encode()


@given(states)
def test_state_round_trips(state: RobotState) -> None:
    assert codec.decode_state(codec.encode_state(state)) == state


@given(st.lists(poses, min_size=1, max_size=5),
       st.none() | st.tuples(finite, finite))
def test_move_request_round_trips(waypoints: list[Pose], face: tuple[float, float] | None) -> None:
    request = MoveRequest(tuple(waypoints), face)
    assert BY_NAME["move"].decode_request(BY_NAME["move"].encode_request(request)) == request


@given(names)
def test_procedure_request_round_trips(procedure: str) -> None:
    request = ProcedureRequest(procedure)
    assert BY_NAME["sense"].decode_request(BY_NAME["sense"].encode_request(request)) == request


@given(st.none() | names, st.none() | st.integers())
def test_reset_request_round_trips(world: str | None, seed: int | None) -> None:
    request = ResetRequest(world, seed)
    assert BY_NAME["reset"].decode_request(BY_NAME["reset"].encode_request(request)) == request


@given(poses, not_negative, st.booleans(), st.booleans())
def test_move_result_round_trips(pose: Pose, duration: float, collided: bool, centred: bool) -> None:
    result = MoveResult(pose, duration, collided, centred)
    assert BY_NAME["move"].decode_result(BY_NAME["move"].encode_result(result)) == result


@given(names, st.dictionaries(names, st.none() | finite, max_size=4), not_negative, not_negative)
def test_sense_result_round_trips(procedure: str, values: dict[str, float | None], duration: float,
                                  distance: float) -> None:
    result = SenseResult(procedure, values, duration, distance)
    assert BY_NAME["sense"].decode_result(BY_NAME["sense"].encode_result(result)) == result


@given(names, st.booleans(), not_negative)
def test_grasp_result_round_trips(procedure: str, success: bool, duration: float) -> None:
    result = GraspResult(procedure, success, duration)
    assert BY_NAME["grasp"].decode_result(BY_NAME["grasp"].encode_result(result)) == result


@settings(deadline=None)  # PNG coding of the first examples can be slow on a busy machine
@given(arrays(np.uint8, st.tuples(st.integers(1, 40), st.integers(1, 40))),
       st.floats(0.01, 10), finite, finite, st.booleans())
def test_camera_image_round_trips_losslessly(pixels: np.ndarray, scale: float, ox: float, oy: float,
                                             fisheye: bool) -> None:
    image = CameraImage(pixels, scale, ox, oy,
                        camera_matrix=np.eye(3) * 2.0 if fisheye else None,
                        fisheye=(0.1, -0.02, 0.0, 0.001) if fisheye else None,
                        clock_s=12.5, meta={"world": "lab", "rows": np.int64(3)})
    back = BY_NAME["camera"].decode_result(BY_NAME["camera"].encode_result(image))
    np.testing.assert_array_equal(back.pixels, pixels)
    assert back.pixels.dtype == np.uint8
    assert (back.inches_per_pixel, back.origin_x_in, back.origin_y_in) == (scale, ox, oy)
    assert back.fisheye == image.fisheye
    assert (back.camera_matrix is None) == (image.camera_matrix is None)
    assert back.meta == {"world": "lab", "rows": 3}


def test_raw_pixels_are_accepted_for_drivers_without_png() -> None:
    pixels = np.arange(12, dtype=np.uint8).reshape(3, 4)
    image = {"format": "raw", "height": 3, "width": 4, "data": base64.b64encode(pixels.tobytes()).decode()}
    back = BY_NAME["camera"].decode_result(body(image=image, inches_per_pixel=0.8, origin_x_in=0,
                                              origin_y_in=2.4))
    np.testing.assert_array_equal(back.pixels, pixels)


def test_noop_and_empty_requests() -> None:
    assert BY_NAME["camera"].decode_request(BY_NAME["camera"].encode_request(EmptyRequest())) == EmptyRequest()
    assert BY_NAME["noop"].decode_result(BY_NAME["noop"].encode_result(None)) is None


def test_a_request_of_another_verb_is_refused_before_sending() -> None:
    with pytest.raises(CodecError, match="message: expected a ProcedureRequest, got EmptyRequest"):
        BY_NAME["sense"].encode_request(EmptyRequest())


def test_errors_round_trip_with_their_code() -> None:
    error = codec.decode_error(codec.encode_error(BAD_REQUEST, "seed: expected an integer"))
    assert isinstance(error, DriverError)
    assert (error.code, error.message) == (BAD_REQUEST, "seed: expected an integer")


@pytest.mark.parametrize(("verb", "data", "field"), [
    ("sense", b"{", "malformed JSON"),
    ("sense", b"\xff\xfe", "not UTF-8"),
    ("sense", b"[1, 2]", "expected a JSON object"),
    ("sense", b"[" * 30_000 + b"]" * 30_000, "nested too deeply"),  # 60 kB: under the size cap
    ("sense", b" " * (128 * 1024) + b"{}", "131074 bytes, more than the 131072 a request may have"),
    ("move", json.dumps({"v": 1, "waypoints": [{"x_in": 0, "y_in": 0, "heading_deg": 0}] * 1001}).encode(),
     "waypoints: 1001 poses, more than the 1000 a move may have"),
    ("sense", json.dumps({"procedure": "H-Sweep-5°"}).encode(), "v: missing"),
    ("sense", json.dumps({"v": 2, "procedure": "H-Sweep-5°"}).encode(), "v: protocol version 2"),
    ("sense", json.dumps({"v": True, "procedure": "H-Sweep-5°"}).encode(), "v: expected an integer"),
    ("sense", body(), "procedure: missing field"),
    ("sense", body(procedure=7), "procedure: expected a string"),
    ("sense", body(procedure=""), "procedure: expected a non-empty string"),
    ("sense", body(procedure="H-Sweep-5°", speed=2), "speed: unknown field"),
    ("move", body(waypoints=[]), "waypoints: expected at least one pose"),
    ("move", body(waypoints="north"), "waypoints: expected an array"),
    ("move", body(waypoints=[{"x_in": 1, "y_in": 2}]), "waypoints[0].heading_deg: missing field"),
    ("move", body(waypoints=[{"x_in": 1, "y_in": "2", "heading_deg": 0}]), "waypoints[0].y_in: expected a number"),
    ("move", body(waypoints=[{"x_in": True, "y_in": 2, "heading_deg": 0}]), "waypoints[0].x_in: expected a number"),
    ("move", body(waypoints=[{"x_in": 1, "y_in": 2, "heading_deg": 0, "z_in": 0}]), "waypoints[0].z_in: unknown field"),
    ("move", b'{"v":1,"waypoints":[{"x_in":NaN,"y_in":0,"heading_deg":0}]}', "waypoints[0].x_in: expected a finite number"),
    ("move", b'{"v":1,"waypoints":[{"x_in":0,"y_in":0,"heading_deg":0}],"face":[1,Infinity]}', "face[1]: expected a finite number"),
    ("move", body(waypoints=[{"x_in": 0, "y_in": 0, "heading_deg": 0}], face=[1, 2, 3]), "face: expected 2 items"),
    ("reset", body(seed=1.5), "seed: expected an integer"),
    ("reset", body(world=3), "world: expected a string"),
    ("camera", body(zoom=2), "zoom: unknown field"),
])
def test_bad_requests_are_refused_naming_the_field(verb: str, data: bytes, field: str) -> None:
    with pytest.raises(CodecError, match=re.escape(field)):
        BY_NAME[verb].decode_request(data)


@pytest.mark.parametrize(("verb", "result", "field"), [
    ("move", MoveResult(Pose(0, 0, 0), 1.0, "no", False), "collided: expected a boolean"),  # type: ignore[arg-type]
    ("move", MoveResult(Pose(0, float("nan"), 0), 1.0, False, False), "pose.y_in: expected a finite number"),
    ("sense", SenseResult("H-Sweep-5°", {"Width": "wide"}, 1.0, 2.0), "values.Width: expected a number"),  # type: ignore[dict-item]
    ("sense", GraspResult("Front-Pinch", True, 1.0), "expected a SenseResult"),
    ("grasp", GraspResult("Front-Pinch", True, -1.0), "duration_s: expected a number >= 0"),
    ("release", RobotState(Pose(0, 0, 0), 0.0, 7.0), "battery: 7.0 outside"),
    ("camera", CameraImage(np.zeros((2, 2), dtype=np.float32), 0.8, 0, 0), "image: expected an HxW uint8"),
    ("camera", CameraImage(np.zeros((2, 2), dtype=np.uint8), 0.0, 0, 0), "inches_per_pixel: expected a positive"),
    ("camera", CameraImage(np.zeros((2, 2), dtype=np.uint8), 0.8, 0, 0, meta={"f": object()}), "meta: not serialisable"),
    ("noop", 1, "noop returns nothing"),
])
def test_malformed_driver_results_are_refused_before_sending(verb: str, result: object, field: str) -> None:
    with pytest.raises(CodecError, match=re.escape(field)):
        BY_NAME[verb].encode_result(result)


@pytest.mark.parametrize(("data", "field"), [
    (body(pose={"x_in": 0, "y_in": 0, "heading_deg": 0}, clock_s=-1, battery=1), "clock_s: expected a number >= 0"),
    (body(pose={"x_in": 0, "y_in": 0, "heading_deg": 0}, clock_s=0), "battery: missing field"),
    (body(pose=[0, 0, 0], clock_s=0, battery=1), "pose: expected an object"),
])
def test_bad_state_publications_are_refused(data: bytes, field: str) -> None:
    with pytest.raises(CodecError, match=re.escape(field)):
        codec.decode_state(data)


def test_bad_images_and_error_replies_are_refused() -> None:
    png = {"format": "png", "height": 3, "width": 4, "data": "not base64!"}
    with pytest.raises(CodecError, match="image.data: not base64"):
        BY_NAME["camera"].decode_result(body(image=png, inches_per_pixel=1, origin_x_in=0, origin_y_in=0))
    raw = {"format": "raw", "height": 3, "width": 4, "data": base64.b64encode(b"12345").decode()}
    with pytest.raises(CodecError, match="5 bytes, expected height\\*width = 12"):
        BY_NAME["camera"].decode_result(body(image=raw, inches_per_pixel=1, origin_x_in=0, origin_y_in=0))
    with pytest.raises(CodecError, match="code: 'oops' is not a protocol error code"):
        codec.decode_error(body(code="oops", message="?"))
    with pytest.raises(CodecError, match="code: 'oops'"):
        codec.encode_error("oops", "?")
