"""The published JSON Schemas (docs/schemas/) against the codec: the files are what the
generator makes, every message the codec writes validates, and a message mutated at
random is accepted by its schema exactly when the codec accepts it."""

from __future__ import annotations

import json
from collections.abc import Callable
from pathlib import Path
from typing import Any

import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from jsonschema import Draft202012Validator

from hero_driver.interface import BUSY, Hello, Pose, RobotState
from hero_driver.zenoh_link import codec
from hero_driver.zenoh_link.codec import CodecError, EmptyRequest
from hero_driver.zenoh_link.schemas import all_schemas, render
from hero_driver.zenoh_link.verbs import BY_NAME, NAMES
from hero_driver.zenoh_link.versions import Greeting
from robot_profile import ProfileStamp
from tests.hero_driver.test_zenoh_verbs import EXAMPLES

FOLDER = Path(__file__).resolve().parents[2] / "docs" / "schemas"
SCHEMAS = all_schemas()
STATE = RobotState(Pose(30.0, -2.5, 270.0), 12.0, 0.5)


def decoder(name: str) -> Callable[[bytes], object]:
    """How the codec reads the message a schema describes."""
    if name == "state":
        return codec.decode_state
    if name == "error":
        return codec.decode_error
    verb, kind = name.split(".")
    return BY_NAME[verb].decode_request if kind == "request" else BY_NAME[verb].decode_result


def codec_accepts(name: str, message: object) -> bool:
    try:
        decoder(name)(json.dumps(message).encode())
    except CodecError:
        return False
    return True


def schema_accepts(name: str, message: object) -> bool:
    return Draft202012Validator(SCHEMAS[name]).is_valid(message)


def written(name: str) -> dict[str, Any]:
    """A real message as the codec writes it."""
    if name == "state":
        return json.loads(codec.encode_state(STATE))
    if name == "error":
        return json.loads(codec.encode_error(BUSY, "move: the robot is still executing sense"))
    verb, kind = name.split(".")
    request, result = EXAMPLES[verb]
    body = BY_NAME[verb].encode_request(request) if kind == "request" else BY_NAME[verb].encode_result(result)
    return json.loads(body)


def test_one_schema_per_request_reply_state_and_error() -> None:
    assert set(SCHEMAS) == {f"{verb}.{kind}" for verb in NAMES for kind in ("request", "reply")} | {"state", "error"}


def test_the_published_files_are_the_generated_schemas() -> None:
    on_disk = {path.stem: path.read_text(encoding="utf-8") for path in FOLDER.glob("*.json")}
    assert on_disk == {name: render(schema) for name, schema in SCHEMAS.items()}, \
        "regenerate with: python -m hero_driver.zenoh_link.schemas docs/schemas"


@pytest.mark.parametrize("name", sorted(SCHEMAS))
def test_each_schema_is_valid_draft_2020_12(name: str) -> None:
    Draft202012Validator.check_schema(SCHEMAS[name])


@pytest.mark.parametrize("name", sorted(SCHEMAS))
def test_what_the_codec_writes_validates(name: str) -> None:
    message = written(name)
    assert codec_accepts(name, message)
    assert schema_accepts(name, message)


# Representative bad messages, each refused by the codec and by the schema.
BAD: list[tuple[str, object]] = [
    ("move.request", {"v": 1, "waypoints": []}),
    ("move.request", {"v": 1, "waypoints": [{"x_in": 1, "y_in": 2}]}),
    ("move.request", {"v": 1, "waypoints": [{"x_in": 1, "y_in": 2, "heading_deg": True}]}),
    ("move.request", {"v": 1, "waypoints": "north", "face": None}),
    ("move.request", {"v": 1, "waypoints": [{"x_in": 1, "y_in": 2, "heading_deg": 0}], "face": [1, 2, 3]}),
    ("move.request", {"v": 1, "waypoints": [{"x_in": 1, "y_in": 2, "heading_deg": 0}], "speed": 2}),
    ("sense.request", {"v": 1, "procedure": ""}),
    ("sense.request", {"v": 1, "procedure": 42}),
    ("sense.request", {"v": 1}),
    ("sense.request", {"procedure": "H-Sweep-5°"}),
    ("sense.request", {"v": 2, "procedure": "H-Sweep-5°"}),
    ("sense.request", {"v": "1", "procedure": "H-Sweep-5°"}),
    ("grasp.request", {"v": 1, "procedure": None}),
    ("reset.request", {"v": 1, "seed": 1.5}),
    ("reset.request", {"v": 1, "seed": "seven"}),
    ("reset.request", {"v": 1, "world": ""}),
    ("noop.request", {"v": 1, "ping": True}),
    ("hello.request", []),
    ("move.reply", {"v": 1, "pose": {"x_in": 0, "y_in": 0, "heading_deg": 0}, "duration_s": 1,
                    "collided": False, "centred": False, "speed_in_s": 0.5}),  # one field too many
    ("move.reply", {"v": 1, "pose": {"x_in": 0, "y_in": 0, "heading_deg": 0}, "duration_s": -1,
                    "collided": False, "centred": False}),
    ("move.reply", {"v": 1, "pose": {"x_in": 0, "y_in": 0, "heading_deg": 0}, "duration_s": 1,
                    "collided": "no", "centred": False}),
    ("sense.reply", {"v": 1, "procedure": "H-Sweep-5°", "values": {"Width": "wide"}, "duration_s": 1,
                     "distance_in": 20}),
    ("sense.reply", {"v": 1, "procedure": "H-Sweep-5°", "values": {"": 1}, "duration_s": 1, "distance_in": 20}),
    ("sense.reply", {"v": 1, "procedure": "H-Sweep-5°", "values": [], "duration_s": 1, "distance_in": 20}),
    ("grasp.reply", {"v": 1, "procedure": "Front-Pinch", "success": 1, "duration_s": 1}),
    ("camera.reply", {"v": 1, "image": {"format": "jpeg", "height": 1, "width": 1, "data": "AA=="},
                      "inches_per_pixel": 0.8, "origin_x_in": 0, "origin_y_in": 0}),
    ("camera.reply", {"v": 1, "image": {"format": "raw", "height": 1, "width": 1, "data": "AA=="},
                      "inches_per_pixel": 0, "origin_x_in": 0, "origin_y_in": 0}),
    ("camera.reply", {"v": 1, "image": {"format": "raw", "height": 0, "width": 1, "data": ""},
                      "inches_per_pixel": 0.8, "origin_x_in": 0, "origin_y_in": 0}),
    ("camera.reply", {"v": 1, "image": {"format": "raw", "height": 1, "width": 1, "data": "A?=="},
                      "inches_per_pixel": 0.8, "origin_x_in": 0, "origin_y_in": 0}),
    ("camera.reply", {"v": 1, "image": {"format": "raw", "height": 1, "width": 1, "data": "AA=="},
                      "inches_per_pixel": 0.8, "origin_x_in": 0, "origin_y_in": 0, "fisheye": [0, 0, 0]}),
    ("hello.reply", {"v": 1, "versions": [], "features": []}),
    ("hello.reply", {"v": 1, "versions": [0], "features": []}),
    ("hello.reply", {"v": 1, "versions": [1, 1.0], "features": []}),
    ("hello.reply", {"v": 1, "versions": [1], "features": ["x", "x"]}),
    ("hello.reply", {"v": 1, "versions": [1]}),
    ("hello.reply", {"v": 1, "versions": [1], "features": [], "profile": {"name": "rover", "sha256": "ab" * 32}}),
    ("hello.reply", {"v": 1, "versions": [1], "features": ["profile"]}),
    ("hello.reply", {"v": 1, "versions": [1], "features": ["profile"],
                     "profile": {"name": "rover", "sha256": "AB" * 32}}),
    ("hello.reply", {"v": 1, "versions": [1], "features": ["profile"],
                     "profile": {"name": "", "sha256": "ab" * 32}}),
    ("hello.reply", {"v": 1, "versions": [1], "features": ["profile"], "profile": {"name": "rover"}}),
    ("noop.reply", {"v": 1, "ok": True}),
    ("state", {"v": 1, "pose": {"x_in": 0, "y_in": 0, "heading_deg": 0}, "clock_s": 0, "battery": 1.5}),
    ("state", {"v": 1, "pose": {"x_in": 0, "y_in": 0, "heading_deg": 0}, "clock_s": -1, "battery": 1}),
    ("error", {"v": 1, "code": "on_fire", "message": "the gripper is smoking"}),
    ("error", {"v": 1, "code": "busy"}),
]


@pytest.mark.parametrize(("name", "message"), BAD)
def test_a_message_the_codec_refuses_the_schema_refuses(name: str, message: object) -> None:
    assert not codec_accepts(name, message)
    assert not schema_accepts(name, message)


# Edge cases both accept: an integer written as 3.0, optional fields left out, a dropout.
GOOD: list[tuple[str, object]] = [
    ("sense.request", {"v": 1.0, "procedure": "H-Sweep-5°"}),
    ("reset.request", {"v": 1, "seed": 3.0}),
    ("reset.request", {"v": 1}),
    ("move.request", {"v": 1, "waypoints": [{"x_in": 1, "y_in": 2, "heading_deg": -725.5}]}),
    ("sense.reply", {"v": 1, "procedure": "H-Sweep-5°", "values": {"Width": None}, "duration_s": 0,
                     "distance_in": 20}),
    ("camera.reply", {"v": 1, "image": {"format": "raw", "height": 1, "width": 1, "data": "AA=="},
                      "inches_per_pixel": 0.8, "origin_x_in": 0, "origin_y_in": 0}),
]


@pytest.mark.parametrize(("name", "message"), GOOD)
def test_edge_cases_both_accept(name: str, message: object) -> None:
    assert codec_accepts(name, message)
    assert schema_accepts(name, message)


def test_non_finite_numbers_are_not_json_so_a_strict_parser_refuses_them() -> None:
    """No schema can see ``NaN`` (it is not JSON); the codec names the field, and a
    vendor's standard JSON parser refuses the whole message."""
    payload = '{"v": 1, "waypoints": [{"x_in": NaN, "y_in": 0, "heading_deg": Infinity}]}'
    with pytest.raises(ValueError):
        json.loads(payload, parse_constant=lambda constant: (_ for _ in ()).throw(ValueError(constant)))
    with pytest.raises(CodecError, match=r"waypoints\[0\]\.x_in"):
        BY_NAME["move"].decode_request(payload.encode())


# ------------------------------------------------------------------ random mutations

# Values on the edges the codec and the schemas test (sign, bounds, integral floats,
# emptiness, repeats) are drawn as often as arbitrary JSON.
edges = st.sampled_from([0, -1, -0.0, 0.5, 1, 1.0, 1.5, 2, 3.0, 1e300, "", "x", [], [1], [1, 1], [1, 2],
                         ["x", "x"], {}, {"x": 1}, [0.0, 0.0], [0, 0, 0, 0]])
json_values = edges | st.recursive(
    st.none() | st.booleans() | st.integers(-(2 ** 53), 2 ** 53)
    | st.floats(allow_nan=False, allow_infinity=False) | st.text(max_size=5),
    lambda inner: st.lists(inner, max_size=3) | st.dictionaries(st.text(max_size=5), inner, max_size=3),
    max_leaves=6,
)


def paths(value: object, here: tuple[Any, ...] = ()) -> list[tuple[Any, ...]]:
    """Every place in a JSON value, the root included."""
    found = [here]
    if isinstance(value, dict):
        for key, item in value.items():
            found += paths(item, (*here, key))
    elif isinstance(value, list):
        for i, item in enumerate(value):
            found += paths(item, (*here, i))
    return found


def mutated(message: dict[str, Any], path: tuple[Any, ...], operation: str, value: object,
            key: str) -> object:
    """``message`` with the value at ``path`` replaced, deleted (from its object) or
    given an extra ``key``."""
    copy = json.loads(json.dumps(message))
    if not path:
        return value if operation == "replace" else {**copy, key: value}
    parent = copy
    for step in path[:-1]:
        parent = parent[step]
    last = path[-1]
    if operation == "replace":
        parent[last] = value
    elif operation == "delete" and isinstance(parent, dict):
        del parent[last]
    elif isinstance(parent[last], dict):
        parent[last][key] = value
    else:
        parent[last] = value
    return copy


def image_content(path: tuple[Any, ...], operation: str) -> bool:
    """A new value inside ``image``: whether the data still decodes to an H x W
    picture is beyond a schema (docs/driver-protocol.md says so)."""
    return len(path) >= 2 and path[0] == "image" and operation != "delete"


@pytest.mark.parametrize("name", sorted(SCHEMAS))
@settings(max_examples=100, deadline=None)
@given(data=st.data())
def test_schema_and_codec_agree_on_mutated_messages(name: str, data: st.DataObject) -> None:
    message = written(name)
    path = data.draw(st.sampled_from(paths(message)), label="path")
    operation = data.draw(st.sampled_from(["replace", "delete", "add"]), label="operation")
    if image_content(path, operation):
        return
    value = data.draw(json_values, label="value")
    key = data.draw(st.text(max_size=5), label="key")
    changed = mutated(message, path, operation, value, key)
    assert codec_accepts(name, changed) == schema_accepts(name, changed), changed


PROFILED = Greeting(Hello((1,), ("profile",)), ProfileStamp("rover", "0123456789abcdef" * 4))


@settings(max_examples=200, deadline=None)
@given(data=st.data())
def test_schema_and_codec_agree_on_a_mutated_hello_naming_its_profile(data: st.DataObject) -> None:
    message = json.loads(BY_NAME["hello"].encode_result(PROFILED))
    path = data.draw(st.sampled_from(paths(message)), label="path")
    operation = data.draw(st.sampled_from(["replace", "delete", "add"]), label="operation")
    value = data.draw(json_values | st.just("profile"), label="value")
    key = data.draw(st.text(max_size=5), label="key")
    changed = mutated(message, path, operation, value, key)
    assert codec_accepts("hello.reply", changed) == schema_accepts("hello.reply", changed), changed


def test_a_hello_naming_its_profile_round_trips_and_validates() -> None:
    verb = BY_NAME["hello"]
    body = verb.encode_result(PROFILED)
    assert verb.decode_result(body) == PROFILED
    assert json.loads(body) == {"v": 1, "versions": [1], "features": ["profile"],
                                "profile": {"name": "rover", "sha256": "0123456789abcdef" * 4}}
    assert schema_accepts("hello.reply", json.loads(body))


def test_hello_round_trips_through_the_codec() -> None:
    verb = BY_NAME["hello"]
    served = Hello((1, 2), ("profile-hash",))
    assert verb.decode_result(verb.encode_result(served)) == Greeting(served)
    assert verb.decode_request(verb.encode_request(EmptyRequest())) == EmptyRequest()
    assert json.loads(verb.encode_result(served)) == {"v": 1, "versions": [1, 2], "features": ["profile-hash"]}
