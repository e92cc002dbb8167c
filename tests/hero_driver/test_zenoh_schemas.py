"""The published JSON Schemas (docs/schemas/) against the codec: the files are what the
generator makes, every message the codec writes validates, and a message mutated at
random is accepted by its schema exactly when the codec accepts it; every number names
its unit; a profile's sense reply schema accepts what its simulated robot answers and
refuses what that robot cannot have measured."""

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
from hero_driver.sim.probe import probe
from hero_driver.zenoh_link import codec
from hero_driver.zenoh_link.codec import CodecError, EmptyRequest
from hero_driver.zenoh_link.schemas import (
    UNITS,
    all_schemas,
    main,
    profile_schemas,
    published,
    render,
    shipped_profiles,
)
from hero_driver.zenoh_link.verbs import BY_NAME, NAMES
from hero_driver.zenoh_link.versions import Greeting
from robot_profile import ProfileStamp, load_profile
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
    generated = published([load_profile(path) for path in shipped_profiles()])
    assert on_disk == {name: render(schema) for name, schema in generated.items()}, \
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
    ("scan.reply", {"v": 1, "pose": {"x_in": 0, "y_in": 0, "heading_deg": 0}, "clock_s": 0, "angles_deg": [180],
                    "ranges_in": [1], "range_min_in": 0, "range_max_in": 10}),
    ("scan.reply", {"v": 1, "pose": {"x_in": 0, "y_in": 0, "heading_deg": 0}, "clock_s": 0, "angles_deg": [0],
                    "ranges_in": ["far"], "range_min_in": 0, "range_max_in": 10}),
    ("scan.reply", {"v": 1, "pose": {"x_in": 0, "y_in": 0, "heading_deg": 0}, "clock_s": 0, "angles_deg": [],
                    "ranges_in": [], "range_min_in": 0, "range_max_in": 10}),
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
    ("scan.reply", {"v": 1, "pose": {"x_in": 0, "y_in": 0, "heading_deg": 0}, "clock_s": 0, "angles_deg": [-180, 0],
                    "ranges_in": [None, 10], "range_min_in": 0, "range_max_in": 10}),
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


SCAN_BEAMS = ("angles_deg", "ranges_in", "range_min_in", "range_max_in")


def scan_content(path: tuple[Any, ...], operation: str) -> bool:
    """A new value in a scan's beams or range limits: that the angles increase, that the
    ranges are as many and within the limits is beyond a schema (docs/driver-protocol.md
    says so; tests/hero_driver/test_zenoh_scan.py holds the codec to it)."""
    return bool(path) and path[0] in SCAN_BEAMS and not (len(path) == 1 and operation == "delete")


@pytest.mark.parametrize("name", sorted(SCHEMAS))
@settings(max_examples=100, deadline=None)
@given(data=st.data())
def test_schema_and_codec_agree_on_mutated_messages(name: str, data: st.DataObject) -> None:
    message = written(name)
    path = data.draw(st.sampled_from(paths(message)), label="path")
    operation = data.draw(st.sampled_from(["replace", "delete", "add"]), label="operation")
    if image_content(path, operation) or (name == "scan.reply" and scan_content(path, operation)):
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


# ------------------------------------------------------------------ units

# Numbers that count or name rather than measure: a seed, protocol versions, and the
# generic sense values, whose unit is their feature's (each profile's schema gives it).
UNITLESS = {"seed", "versions", "values"}
SUFFIX_UNITS = {"_in": "in", "_deg": "deg", "_s": "s"}


def numbers(schema: object, field: str = "", here: tuple[Any, ...] = ()) -> list[tuple[str, tuple[Any, ...], dict]]:
    """Every number or integer node of a schema, with the field it belongs to (the
    nearest property name above it) and its path."""
    found: list[tuple[str, tuple[Any, ...], dict]] = []
    if isinstance(schema, dict):
        if schema.get("type") in ("number", "integer"):
            found.append((field, here, schema))
        for key, item in schema.items():
            inner = key if here and here[-1] == "properties" else field
            found += numbers(item, inner, (*here, key))
    elif isinstance(schema, list):
        for i, item in enumerate(schema):
            found += numbers(item, field, (*here, i))
    return found


@pytest.mark.parametrize("name", sorted(SCHEMAS))
def test_every_number_names_its_unit_in_its_description_and_in_x_unit(name: str) -> None:
    for field, path, node in numbers(SCHEMAS[name]):
        if field in UNITLESS:
            assert "x-unit" not in node, (name, path)
            continue
        assert node.get("x-unit") in UNITS, (name, path)
        assert UNITS[node["x-unit"]] in node["description"], (name, path, node["description"])
        for suffix, unit in SUFFIX_UNITS.items():
            if field.endswith(suffix):
                assert node["x-unit"] == unit, (name, path)


def test_the_units_of_the_state_and_the_move_reply() -> None:
    """Worked by hand from docs/driver-protocol.md: inches, degrees CCW, robot seconds,
    the battery a fraction with no unit."""
    units = {field: node["x-unit"] for field, _, node in numbers(SCHEMAS["state"])}
    assert units == {"x_in": "in", "y_in": "in", "heading_deg": "deg", "clock_s": "s", "battery": "1"}
    move = SCHEMAS["move.reply"]["properties"]
    assert move["duration_s"]["x-unit"] == "s"
    assert move["duration_s"]["description"] == "robot time the verb took, in seconds"
    camera = SCHEMAS["camera.reply"]["properties"]
    assert camera["inches_per_pixel"]["x-unit"] == "in/px"
    assert camera["image"]["properties"]["height"]["x-unit"] == "px"


# ------------------------------------------------------------------ a profile's sense reply

HERO = load_profile(next(path for path in shipped_profiles() if path.stem == "hero2000"))
HERO_SENSE = profile_schemas(HERO)["hero2000.sense.reply"]


def test_the_shipped_profiles_each_have_a_sense_reply_schema() -> None:
    assert sorted(path.stem for path in shipped_profiles()) == ["hero2000", "rover"]
    assert set(published([load_profile(path) for path in shipped_profiles()])) - set(SCHEMAS) == {
        "hero2000.sense.reply", "rover.sense.reply"}


def test_a_features_schema_carries_its_profiles_unit_span_and_meaning() -> None:
    then = next(rule["then"] for rule in HERO_SENSE["allOf"]
                if rule["if"]["properties"]["procedure"]["const"] == "H-Scan-0.3")
    width, hole = (then["properties"]["values"]["properties"][name]["anyOf"][0] for name in ("Width", "Front-Hole?"))
    assert (width["x-unit"], width["minimum"], width["maximum"]) == ("in", 0, 127)
    assert width["description"] == ("Width, in inches, from 0 to 127; expected error 0.5 "
                                    "(docs/driver-protocol.md, Sensing features, Width)")
    assert (hole["enum"], hole["x-unit"]) == ([0, 1], "bool")
    assert then["properties"]["values"]["required"] == ["Width", "Front-Hole?"]


@pytest.mark.parametrize("profile_path", shipped_profiles(), ids=lambda path: path.stem)
@pytest.mark.parametrize("noise", [False, True])
def test_a_profiles_schema_accepts_every_reply_of_its_simulated_robot(profile_path: Path, noise: bool) -> None:
    """Every procedure of the profile applied to the 10 in box at 6 in (every range
    holds 6 in), noise off and on (a dropout's ``null`` included, over seeds)."""
    profile = load_profile(profile_path)
    schema = Draft202012Validator(profile_schemas(profile)[f"{profile_path.stem}.sense.reply"])
    for procedure in profile.sensing:
        for seed in range(4 if noise else 1):
            result = probe("closed-box-10x10x10/upright", procedure.name, 6, 0, seed=seed, noise=noise,
                           profile=profile)
            reply = json.loads(BY_NAME["sense"].encode_result(result))
            assert schema.is_valid(reply), list(schema.iter_errors(reply))


H_SCAN = {"v": 1, "procedure": "H-Scan-0.3", "values": {"Width": 10.2, "Front-Hole?": 0}, "duration_s": 105,
          "distance_in": 6.0}
WRONG_VALUES: list[dict[str, object]] = [
    {"Width": 10.2},                                    # a feature missing
    {"Width": 10.2, "Front-Hole?": 0, "Height": 9.9},  # a feature of another procedure added
    {"Width": 10.2, "Front-Hole?": 0.5},               # a hole is 0 or 1
    {"Width": 10.2, "Front-Hole?": True},              # ... a number, not a JSON boolean
    {"Width": 130.0, "Front-Hole?": 0},                # past the span's 127 in
    {"Width": -0.3, "Front-Hole?": 0},                 # below it
]


@pytest.mark.parametrize("values", WRONG_VALUES)
def test_a_profiles_schema_refuses_values_its_robot_cannot_have_measured(values: dict[str, object]) -> None:
    reply = {**H_SCAN, "values": values}
    assert not Draft202012Validator(HERO_SENSE).is_valid(reply)
    if values.get("Front-Hole?") is not True:  # the codec, profile-blind, takes them as well formed
        assert schema_accepts("sense.reply", reply) and codec_accepts("sense.reply", reply)


def test_a_profiles_schema_takes_a_dropout_and_refuses_a_procedure_it_lacks() -> None:
    validator = Draft202012Validator(HERO_SENSE)
    assert validator.is_valid(H_SCAN)
    assert validator.is_valid({**H_SCAN, "values": {"Width": None, "Front-Hole?": None}})
    assert not validator.is_valid({**H_SCAN, "procedure": "X-Scan-0.3"})
    assert not validator.is_valid({**H_SCAN, "values": {"Height": 9.9, "Depth": 9.9, "Top-Hole?": 0}})


def test_the_generator_writes_the_sense_reply_of_the_profile_it_is_given(tmp_path: Path,
                                                                         capsys: pytest.CaptureFixture[str]) -> None:
    rover = next(path for path in shipped_profiles() if path.stem == "rover")
    assert main([str(tmp_path), str(rover)]) == 0
    assert sorted(path.name for path in tmp_path.glob("*.sense.reply.json")) == ["rover.sense.reply.json"]
    assert len(list(tmp_path.glob("*.json"))) == len(SCHEMAS) + 1
    capsys.readouterr()


def test_the_generator_refuses_a_profile_it_cannot_read_in_one_line(tmp_path: Path,
                                                                    capsys: pytest.CaptureFixture[str]) -> None:
    bad = tmp_path / "robot.toml"
    bad.write_text("[move]\nseconds_per_inch = 'fast'\n", encoding="utf-8")
    assert main([str(tmp_path / "out"), str(bad)]) == 2
    assert main([str(tmp_path / "out"), str(tmp_path / "missing.toml")]) == 2
    lines = capsys.readouterr().err.splitlines()
    assert len(lines) == 2 and "robot.toml" in lines[0] and "missing.toml" in lines[1], lines
    assert not (tmp_path / "out").exists()
