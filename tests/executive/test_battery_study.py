"""The battery study's plumbing (experiments.study_battery) without running
episodes: its settings, its floors and its summary on rows made up by hand. The
``--quick`` run itself takes over 20 s on 2 cores and is not in the suite."""

from __future__ import annotations

import json
from pathlib import Path

import pytest

from experiments.study_battery import (
    DOCK, DRAIN_LEVEL, QUICK_DRAINS, QUICK_LEVELS, SETTINGS, BatteryJob, ObjectRow, cell, params_for, plan,
    learned_after_flat, summarise, write_docked_floor,
)


def test_the_settings_turn_the_guard_and_the_pricing_on_and_off() -> None:
    assert [(p.battery_low, p.price_detours) for p in map(params_for, SETTINGS)] == [
        (0.0, False), (0.2, False), (0.2, True)]
    with pytest.raises(ValueError, match="unknown battery setting 'both'"):
        params_for("both")


def test_a_docked_floor_has_the_dock_and_the_start_level(tmp_path: Path) -> None:
    world = json.loads(write_docked_floor(tmp_path, 3, 0.21).read_text())
    assert world["dock"] == DOCK and world["battery"] == 0.21 and world["battery_drain"] == 1.0 and world["objects"]
    assert json.loads(write_docked_floor(tmp_path, 3, 0.5, 8.0).read_text())["battery_drain"] == 8.0
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


@pytest.mark.slow
def test_one_floor_from_a_nearly_flat_battery_with_the_guard_off_and_on() -> None:
    from executive import defaults
    from experiments.worker import install_worker
    from experiments.study_battery import run_job
    from experiments.worlds import set_members
    from learner.library.format import read_library_json
    from robot_profile import load_profile

    install_worker({"trained": read_library_json(defaults.EXAMPLE_LIBRARY)}, load_profile())
    off = run_job(BatteryJob(0.03, "guard off", 0))
    on = run_job(BatteryJob(0.03, "guard", 0))
    assert len(off) == len(on) == len(set_members("test"))  # every object found and reported
    # 0.03 of a charge is 540 s of driving: the robot runs flat and the rest fail
    assert sum(r.flat for r in off) > 0 and not any(r.charges for r in off)
    # under the threshold from the start: one charge, then nothing runs flat
    assert sum(r.charges for r in on) == 1 and not any(r.flat for r in on)


def test_the_quick_plan_has_a_row_per_sweep_point() -> None:
    # quick: 2 levels at x1, then x1 and x8 from DRAIN_LEVEL, 3 settings, 1 floor
    jobs = plan(QUICK_LEVELS, [0], QUICK_DRAINS)
    assert len(jobs) == (2 + 2) * 3
    assert {(j.level, j.drain) for j in jobs} == {(0.03, 1.0), (0.21, 1.0), (DRAIN_LEVEL, 1.0), (DRAIN_LEVEL, 8.0)}
    results = {job: [row(job.setting, True, 120.0 * job.drain, charges=int(job.drain > 1))] for job in jobs}
    # one object of the x8 guard-off floor: failed flat, and (a bug this would show) a description saved
    x8_off = BatteryJob(DRAIN_LEVEL, "guard off", 0, 8.0)
    results[x8_off] = [ObjectRow(DRAIN_LEVEL, "guard off", 0, "x", "failed", False, 90.0, 0, False, True, 8.0, True)]
    study = summarise(results, QUICK_LEVELS, QUICK_DRAINS)
    levels_table, drains_table = study.details
    assert [r[0] for r in levels_table[1]] == ["0.03", "0.21"]
    assert drains_table[0] == ("drain (from 0.5)", *SETTINGS)
    assert [r[0] for r in drains_table[1]] == ["x1", "x8"]
    # x8 under the guard: 120 s x 8 = 16 min an object, one dock trip, resumed
    assert drains_table[1][1][2] == "100%, 16.0 min, 1 dock, 1 resumed, 0 flat"
    assert drains_table[1][1][1] == "0%, 1.5 min, 0 dock, 0 resumed, 1 flat"
    by_name = {r.measured: r.ours for r in study.rows}
    assert by_name["descriptions saved from attempts the battery cut short: guard off / guard / guard + pricing "
                   "(must be 0)"] == "1 / 0 / 0"
    assert by_name["success at drain x8 from 0.5: guard off / guard / guard + pricing"] == "0% / 100% / 100%"


def test_only_a_description_saved_after_a_refusal_counts_as_cut_short() -> None:
    empty = {"event": "driver_error", "code": "battery_empty"}
    events = [{"event": "learn", "object": 5, "id": "learned/Top-Pinch"}, {**empty, "object": 5},  # held, then flat
              {**empty, "object": 6}, {"event": "learn", "object": 6, "id": "learned/Front-Wrap"},  # flat, then saved
              {**empty, "object": 7}, {"event": "learn", "object": 7, "id": None}]  # flat, nothing saved
    assert learned_after_flat(events) == {6}
