"""The one profile reader: the shipped HERO file as typed values; bad files named in one line."""

from __future__ import annotations

import tomllib
from dataclasses import replace
from pathlib import Path

import pytest

from learner.knowledge import MoveModel
from robot_profile import DEFAULT_PROFILE, knowledge_from_dict, load_knowledge, load_profile, profile_from_dict

HERO = Path(__file__).resolve().parents[2] / "hero_driver" / "profiles" / "hero2000.toml"


def test_the_default_is_the_shipped_hero_profile() -> None:
    assert DEFAULT_PROFILE == HERO
    profile = load_profile()
    assert profile.source == str(HERO)
    geometry, motion = profile.robot.geometry, profile.robot.motion
    assert (geometry.base_radius_in, geometry.sensor_offset_in, geometry.sensor_height_in,
            geometry.raised_sensor_height_in) == (9.0, 11.0, 4.0, 18.0)
    assert (motion.speed_in_per_s, motion.turn_deg_per_s, motion.vision_s, motion.centring_s) == (0.5, 5.0, 5.0, 15.0)
    assert profile.move == MoveModel(2.0, 0.0, 0.0)
    assert len(profile.sensing) == 7 and profile.grasp_names == (
        "Front-Pinch", "Front-Wrap", "Top-Pinch", "Top-Vert-Grip", "Top-Hor-Grip", "No-Grab")


def test_procedures_are_found_by_name_or_not_at_all() -> None:
    profile = load_profile(HERO)
    scan = profile.sensing_procedure("D-Scan-0.3")
    assert scan is not None and scan.time_s == 84 and scan.range_in == (6.0, 6.0)
    assert [(f.name, f.binary, f.span) for f in scan.features] == [
        ("Height", False, (0.0, 127.0)), ("Depth", False, (0.0, 127.0)), ("Top-Hole?", True, (0.0, 1.0))]
    pinch = profile.grasping_procedure("Top-Pinch")
    assert pinch is not None and (pinch.time_s, pinch.side_effect_penalty_s, pinch.verifiable) == (63, 40, True)
    no_grab = profile.grasping_procedure("No-Grab")
    assert no_grab is not None and not no_grab.verifiable and no_grab.range_in == (6.0, 999.0)
    assert profile.sensing_procedure("Top-Pinch") is None and profile.grasping_procedure("H-Scan-0.3") is None


def test_a_grasps_failure_harm_is_read_and_0_when_left_out() -> None:
    data = _data()
    data["grasping"][2]["failure_harm_s"] = 300
    pinch, wrap = profile_from_dict(data, "k.toml").grasping[2], profile_from_dict(data, "k.toml").grasping[1]
    assert (pinch.name, pinch.failure_harm_s, wrap.failure_harm_s) == ("Top-Pinch", 300.0, 0.0)
    # priced with its harm (63 + 40 + 300) but a failure's robot seconds stay 63 + 40
    assert (pinch.feature_cost_s, pinch.failure_time_s) == (403.0, 103.0)


def _data() -> dict:
    with HERO.open("rb") as fh:
        return tomllib.load(fh)


@pytest.mark.parametrize(
    ("mutate", "message"),
    [
        (lambda d: d["sensing"][0].pop("time_s"), "sensing[0] (H-Sweep-1°): missing field 'time_s'"),
        (lambda d: d["sensing"][1].update(colour="red"), "sensing[1] (H-Sweep-5°): unknown key 'colour'"),
        (lambda d: d["grasping"][2].update(time_s=-1), "grasping[2] (Top-Pinch): 'time_s' must not be negative"),
        (lambda d: d["sensing"][4].update(range_in=[9, 6]), "sensing[4] (S-Sweep-1°): 'range_in' is empty"),
        (lambda d: d["move"].pop("overhead_s"), "[move]: missing field 'overhead_s'"),
        (lambda d: d.update(extra={}), "unknown key 'extra'"),
        (lambda d: d["sensing"][1]["features"].append({"name": "Width", "error": 0.7, "unit": "in", "span": [0, 127]}),
         "feature 'Width' is yielded by 'H-Sweep-5°' and 'H-Scan-0.3' with different errors"),
        (lambda d: d["sensing"][0]["features"][0].update(angular_of="Colour"), "'angular_of' names 'Colour'"),
        (lambda d: d.pop("robot"), "missing table [robot]"),
        (lambda d: d["robot"].pop("sensor_offset_in"), "[robot]: missing field 'sensor_offset_in'"),
        (lambda d: d["robot"].pop("sensor_height_in"), "[robot]: missing field 'sensor_height_in'"),
        (lambda d: d["robot"].update(speed_in_per_s=0), "[robot]: 'speed_in_per_s' must be greater than 0"),
        (lambda d: d["robot"].update(base_radius_in=0.0), "[robot]: 'base_radius_in' must be greater than 0"),
        (lambda d: d["robot"].update(vision_s=-5), "[robot]: 'vision_s' must not be negative"),
        (lambda d: d["robot"].update(wheels=3), "[robot]: unknown key 'wheels'"),
        (lambda d: d["robot"].update(turn_deg_per_s="fast"), "[robot]: 'turn_deg_per_s' must be a number, got 'fast'"),
        (lambda d: d["grasping"][0].update(verifiable="yes"),
         "grasping[0] (Front-Pinch): 'verifiable' must be true or false"),
        (lambda d: d["grasping"][1].update(name="Front-Pinch"), "procedure 'Front-Pinch' is defined twice"),
        (lambda d: d["grasping"][3].update(failure_harm_s=-120),
         "grasping[3] (Top-Vert-Grip): 'failure_harm_s' must not be negative, got -120"),
        (lambda d: d["grasping"][0].update(failure_harm_s="high"),
         "grasping[0] (Front-Pinch): 'failure_harm_s' must be a number, got 'high'"),
        (lambda d: d.update(grasping=[]), "no [[grasping]] procedures"),
    ],
)
def test_bad_profiles_are_rejected_naming_file_entry_and_problem(mutate, message) -> None:  # noqa: ANN001
    data = _data()
    mutate(data)
    with pytest.raises(ValueError) as err:
        profile_from_dict(data, "k.toml")
    assert str(err.value).startswith("k.toml: ")
    assert message in str(err.value) and "\n" not in str(err.value)


def test_the_learners_part_needs_no_robot_table_but_checks_one_given(tmp_path: Path) -> None:
    data = _data()
    full = profile_from_dict(data, "k.toml").knowledge()
    del data["robot"]
    assert knowledge_from_dict(data, "k.toml") == full  # [robot] is nothing of the learner's
    no_robot = tmp_path / "learner-only.toml"
    text = HERO.read_text(encoding="utf-8")
    robot_lines = ("[robot]", *(f"{key} " for key in tomllib.loads(text)["robot"]))  # whatever keys it has
    no_robot.write_text("".join(line for line in text.splitlines(keepends=True) if not line.startswith(robot_lines)),
                        encoding="utf-8")
    assert load_knowledge(no_robot).sensing == full.sensing and load_knowledge(no_robot).source == str(no_robot)
    with pytest.raises(ValueError, match=r"learner-only.toml: missing table \[robot\]"):
        load_profile(no_robot)  # whatever drives the planner or the simulator still needs it
    data = _data()
    data["robot"].update(wheels=3)
    with pytest.raises(ValueError, match=r"k.toml: \[robot\]: unknown key 'wheels'"):
        knowledge_from_dict(data, "k.toml")  # a typo there is still a typo


def test_unreadable_files_are_one_line_errors(tmp_path: Path) -> None:
    with pytest.raises(ValueError, match="missing.toml: knowledge file not found"):
        load_profile(tmp_path / "missing.toml")
    with pytest.raises(ValueError, match="is a folder, not a knowledge file"):
        load_profile(tmp_path)
    bad = tmp_path / "bad.toml"
    bad.write_text("[move\n")
    with pytest.raises(ValueError, match="bad.toml: not valid TOML"):
        load_profile(bad)
    bad.write_bytes(b"\xff\xfe[move]")
    with pytest.raises(ValueError, match="not a text"):
        load_profile(bad)


@pytest.mark.parametrize("bad", [dict(speed_in_per_s=0.0), dict(turn_deg_per_s=-1.0), dict(vision_s=-1.0)])
def test_motion_built_by_hand_refuses_impossible_constants(bad) -> None:  # noqa: ANN001
    with pytest.raises(ValueError, match="move model needs"):
        replace(load_profile().robot.motion, **bad)


def test_geometry_built_by_hand_refuses_a_body_without_size() -> None:
    with pytest.raises(ValueError, match="base_radius_in > 0"):
        replace(load_profile().robot.geometry, base_radius_in=0.0)
