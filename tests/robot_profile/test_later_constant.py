"""A ``[robot]`` constant added after the shipped profiles were written (the recipe in
docs/conventions.md, "Adding a robot constant"): a field with a default. Profiles that
lack the key load with the default and keep their fingerprint; a profile that sets
another value is another robot."""

from __future__ import annotations

import tomllib
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import pytest

import robot_profile.reader as reader
from robot_profile import DEFAULT_PROFILE, load_profile, profile_from_dict, profile_stamp
from robot_profile.model import RobotMotion


@dataclass(frozen=True)
class LaterMotion(RobotMotion):
    """RobotMotion with one constant more, as the recipe adds it."""

    settle_s: float = 0.0


@pytest.fixture
def later(monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.setattr(reader, "RobotMotion", LaterMotion)


def _hero(**robot: Any) -> dict[str, Any]:
    with DEFAULT_PROFILE.open("rb") as fh:
        data = tomllib.load(fh)
    data["robot"].update(robot)
    return data


def test_a_profile_without_the_key_takes_the_default_and_keeps_its_fingerprint(later: None) -> None:
    before = profile_stamp(load_profile(DEFAULT_PROFILE.parent / "rover.toml"))
    monkeypatched = load_profile(DEFAULT_PROFILE.parent / "rover.toml")
    assert isinstance(monkeypatched.robot.motion, LaterMotion) and monkeypatched.robot.motion.settle_s == 0.0
    assert profile_stamp(monkeypatched) == before


def test_the_key_at_its_default_is_the_same_robot_and_another_value_another(later: None, tmp_path: Path) -> None:
    shipped = profile_stamp(profile_from_dict(_hero(), str(DEFAULT_PROFILE))).sha256
    assert profile_stamp(profile_from_dict(_hero(settle_s=0.0), str(DEFAULT_PROFILE))).sha256 == shipped
    settled = profile_from_dict(_hero(settle_s=1.5), str(DEFAULT_PROFILE))
    assert settled.robot.motion.settle_s == 1.5  # type: ignore[attr-defined]
    assert profile_stamp(settled).sha256 != shipped


def test_the_new_key_is_checked_like_the_others(later: None) -> None:
    with pytest.raises(ValueError, match=r"settle_s"):
        profile_from_dict(_hero(settle_s=-1.0), "hero.toml")


def test_the_first_keys_stay_required() -> None:
    data = _hero()
    del data["robot"]["vision_s"]
    with pytest.raises(ValueError, match=r"vision_s"):
        profile_from_dict(data, "hero.toml")
