"""A second, clearly different robot (``hero_driver/profiles/rover.toml``) drives the
whole demo: training, the learner's choices, the planner and the simulator.

The Rover has no 1-degree sweeps and no S-Sweep, sweeps in 30 s / 28 s instead of
45 s / 42 s, and scans in 70 s / 60 s instead of 105 s / 84 s. A shipped-profile value
anywhere in the chain would show up as a procedure or a duration the Rover does not have.
"""

from __future__ import annotations

import json
from pathlib import Path

import pytest

from csl_cli.main import main
from robot_profile import DEFAULT_PROFILE, load_profile

ROVER = DEFAULT_PROFILE.parent / "rover.toml"


def test_the_rover_differs_from_the_hero_where_it_matters() -> None:
    rover, hero = load_profile(ROVER), load_profile()
    assert rover.robot.geometry.base_radius_in == 13.0 != hero.robot.geometry.base_radius_in
    assert rover.robot.motion.speed_in_per_s == 2 * hero.robot.motion.speed_in_per_s
    assert {p.name for p in rover.sensing} < {p.name for p in hero.sensing}


@pytest.mark.slow
def test_demo_with_the_rover_profile_senses_only_with_its_procedures(tmp_path: Path, capsys) -> None:  # noqa: ANN001
    rover = load_profile(ROVER)
    times = {p.name: p.time_s for p in rover.sensing}
    out = tmp_path / "out"
    assert main(["demo", "--knowledge", str(ROVER), "--out", str(out), "--no-plots"]) in (0, 1)
    printed = capsys.readouterr().out
    assert "7 objects:" in printed
    events = [json.loads(line) for line in (out / "episode.jsonl").read_text().splitlines()]
    sensed = [(e["procedure"], e["seconds"]) for e in events if e["event"] == "sense"]
    assert sensed and all(times[name] == seconds for name, seconds in sensed)
    # an object is handled when left (No-Grab) or held, by its grasp at a leaf or by a grasp
    # tried as a feature that held (the camera's appearance makes that common)
    handled = {e["object"] for e in events if e["event"] == "leave" or (e["event"] == "grasp" and e["success"])}
    assert len(handled) >= 5  # measured: 7 of 7 with seed 0
