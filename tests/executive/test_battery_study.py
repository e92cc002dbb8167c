"""The battery study's plumbing (executive.experiment.study_battery) without running
episodes: its settings, its floors and its summary on rows made up by hand. The
``--quick`` run itself takes over 20 s on 2 cores and is not in the suite."""

from __future__ import annotations

import json
from pathlib import Path

import pytest

from executive.experiment.study_battery import (
    DOCK, SETTINGS, BatteryJob, ObjectRow, cell, params_for, plan, summarise, write_docked_floor,
)


def test_the_settings_turn_the_guard_and_the_pricing_on_and_off() -> None:
    assert [(p.battery_low, p.price_detours) for p in map(params_for, SETTINGS)] == [
        (0.0, False), (0.2, False), (0.2, True)]
    with pytest.raises(ValueError, match="unknown battery setting 'both'"):
        params_for("both")


def test_a_docked_floor_has_the_dock_and_the_start_level(tmp_path: Path) -> None:
    world = json.loads(write_docked_floor(tmp_path, 3, 0.21).read_text())
    assert world["dock"] == DOCK and world["battery"] == 0.21 and world["objects"]
    # the dock is clear of the objects' slots (the first column starts 45 +- 6 in from the wall)
    assert all(o["x_in"] - DOCK["x_in"] > 20 for o in world["objects"])


def row(setting: str, correct: bool, robot_s: float, charges: int = 0, flat: bool = False) -> ObjectRow:
    return ObjectRow(0.1, setting, 0, "x", "grasped" if correct else "failed", correct, robot_s, charges,
                     charges > 0 and correct, flat)


def test_the_summary_counts_by_hand() -> None:
    assert len(plan([0.1, 0.2], [0, 1])) == 2 * 3 * 2
    c = cell([row("guard", True, 600.0, charges=1), row("guard", False, 300.0)])
    assert (c.success, c.minutes, c.charges, c.resumed, c.flat, c.objects) == (0.5, 7.5, 1, 1, 0, 2)
    results = {BatteryJob(0.1, "guard off", 0): [row("guard off", False, 60.0, flat=True)] * 2,
               BatteryJob(0.1, "guard", 0): [row("guard", True, 600.0, charges=1), row("guard", True, 300.0)],
               BatteryJob(0.1, "guard + pricing", 0): [row("guard + pricing", True, 540.0), row("guard + pricing",
                                                                                              True, 300.0)]}
    study = summarise(results, [0.1])
    by_name = {r.measured: r.ours for r in study.rows}
    assert by_name["flat-battery failures with the guard on (must be 0)"] == "0"
    assert by_name["robot min per object over all levels: guard / guard + pricing"] == "7.5 / 7.0"
    assert by_name["dock trips over all levels: guard / guard + pricing"] == "1 / 0"
    [(headers, body)] = study.details
    assert headers[1:] == SETTINGS and body[0][1].startswith("0%") and body[0][1].endswith("2 flat")


def test_one_floor_from_a_nearly_flat_battery_with_the_guard_off_and_on() -> None:
    from executive import defaults
    from executive.experiment.situation import install
    from executive.experiment.study_battery import run_job
    from executive.experiment.worlds import set_members
    from learner.library import read_library_json
    from robot_profile import load_profile

    install(read_library_json(defaults.EXAMPLE_LIBRARY), load_profile())
    off = run_job(BatteryJob(0.03, "guard off", 0))
    on = run_job(BatteryJob(0.03, "guard", 0))
    assert len(off) == len(on) == len(set_members("test"))  # every object found and reported
    # 0.03 of a charge is 540 s of driving: the robot runs flat and the rest fail
    assert sum(r.flat for r in off) > 0 and not any(r.charges for r in off)
    # under the threshold from the start: one charge, then nothing runs flat
    assert sum(r.charges for r in on) == 1 and not any(r.flat for r in on)
