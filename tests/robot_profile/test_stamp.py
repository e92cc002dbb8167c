"""The profile stamp: a fingerprint of what the robot does, the same whatever the
order of keys and entries in the file, different for any change the planner or the
simulator would feel, and blind to the learner's own knowledge."""

from __future__ import annotations

import copy
import hashlib
import tomllib
from typing import Any

import pytest
from hypothesis import given
from hypothesis import strategies as st

from robot_profile import DEFAULT_PROFILE, load_profile, profile_from_dict, profile_stamp

SMALL: dict[str, Any] = {
    "move": {"seconds_per_inch": 2, "seconds_per_degree": 0, "overhead_s": 0},
    "robot": {"base_radius_in": 9, "sensor_offset_in": 12, "sensor_height_in": 4, "raised_sensor_height_in": 18,
              "speed_in_per_s": 0.5, "turn_deg_per_s": 5, "vision_s": 4, "centring_s": 15},
    "sensing": [{"name": "Sweep", "time_s": 45, "range_in": [6, 96],
                 "features": [{"name": "Width", "error": 0.5, "unit": "in", "span": [0, 127]}]}],
    "grasping": [{"name": "Pinch", "time_s": 45, "range_in": [6, 6], "side_effect_penalty_s": 30}],
}
# The canonical text of SMALL, written out by hand from docs/driver-protocol.md.
SMALL_CANONICAL = (
    '{"grasping":[{"name":"Pinch","range_in":[6.0,6.0],"time_s":45.0}],'
    '"robot":{"base_radius_in":9.0,"centring_s":15.0,"raised_sensor_height_in":18.0,"sensor_height_in":4.0,'
    '"sensor_offset_in":12.0,"speed_in_per_s":0.5,"turn_deg_per_s":5.0,"vision_s":4.0},'
    '"sensing":[{"features":["Width"],"name":"Sweep","range_in":[6.0,96.0],"time_s":45.0}]}'
)


def stamp_of(data: dict[str, Any], source: str = "profiles/small.toml") -> str:
    return profile_stamp(profile_from_dict(data, source)).sha256


def test_the_stamp_is_the_sha256_of_the_canonical_text() -> None:
    stamp = profile_stamp(profile_from_dict(SMALL, "profiles/small.toml"))
    assert stamp.name == "small"
    assert stamp.sha256 == hashlib.sha256(SMALL_CANONICAL.encode()).hexdigest()


def test_the_shipped_profiles_have_different_stamps() -> None:
    hero, rover = profile_stamp(load_profile()), profile_stamp(load_profile(DEFAULT_PROFILE.parent / "rover.toml"))
    assert (hero.name, rover.name) == ("hero2000", "rover")
    assert hero.sha256 != rover.sha256


@pytest.mark.slow
@given(st.randoms(use_true_random=False))
def test_the_order_of_keys_and_entries_changes_nothing(rng: Any) -> None:
    with DEFAULT_PROFILE.open("rb") as fh:
        data = tomllib.load(fh)

    def shuffled(value: Any) -> Any:
        if isinstance(value, dict):
            items = list(value.items())
            rng.shuffle(items)
            return {key: shuffled(item) for key, item in items}
        if isinstance(value, list) and value and isinstance(value[0], dict):
            items = [shuffled(item) for item in value]
            rng.shuffle(items)
            return items
        return value

    assert stamp_of(shuffled(data)) == stamp_of(data)


def changed(path: tuple[Any, ...], value: Any) -> dict[str, Any]:
    data = copy.deepcopy(SMALL)
    parent = data
    for step in path[:-1]:
        parent = parent[step]
    parent[path[-1]] = value
    return data


@pytest.mark.parametrize(("path", "value"), [
    *((("robot", key), SMALL["robot"][key] + 1) for key in SMALL["robot"]),
    (("sensing", 0, "name"), "Sweep-2"),
    (("sensing", 0, "time_s"), 46),
    (("sensing", 0, "range_in"), [6, 97]),
    (("sensing", 0, "features", 0, "name"), "Breadth"),
    (("grasping", 0, "name"), "Pinch-2"),
    (("grasping", 0, "time_s"), 44),
    (("grasping", 0, "range_in"), [5, 6]),
])
def test_what_the_robot_does_changes_the_stamp(path: tuple[Any, ...], value: Any) -> None:
    assert stamp_of(changed(path, value)) != stamp_of(SMALL)


@pytest.mark.parametrize(("path", "value"), [
    (("move", "seconds_per_inch"), 3),
    (("sensing", 0, "features", 0, "error"), 0.25),
    (("sensing", 0, "features", 0, "span"), [0, 64]),
    (("grasping", 0, "side_effect_penalty_s"), 10),
    (("grasping", 0, "failure_harm_s"), 300),
    (("grasping", 0, "verifiable"), False),
])
def test_what_only_the_learner_knows_leaves_it(path: tuple[Any, ...], value: Any) -> None:
    assert stamp_of(changed(path, value)) == stamp_of(SMALL)


def test_the_name_is_not_part_of_the_fingerprint() -> None:
    assert stamp_of(SMALL, "elsewhere/other.toml") == stamp_of(SMALL)
