"""The disturbance study's arithmetic (experiments.study_disturbance) and its
ground-truth count of descriptions saved from disturbed attempts
(experiments.disturbed), on hand-made rows, records and events."""

from __future__ import annotations

from types import SimpleNamespace

import pytest

from executive import defaults
from experiments.disturbed import saved_from_disturbed, sim_index, unnoticed
from experiments.worker import install_worker
from experiments.study_disturbance import DisturbanceJob, ObjectRow, cell, plan, preset, run_job, summarise
from experiments.worlds import set_members
from hero_driver.sim.disturber import Happened
from learner.library.format import read_library_json
from robot_profile import load_profile


def truth(index: int, x: float, y: float) -> SimpleNamespace:
    return SimpleNamespace(index=index, x_in=x, y_in=y)


def record(index: int, x: float, y: float, learned: str | None) -> SimpleNamespace:
    return SimpleNamespace(index=index, first_region=SimpleNamespace(centroid=(x, y)), learned_id=learned)


START = [truth(0, 50.0, 50.0), truth(1, 150.0, 50.0)]


def test_records_are_matched_to_the_simulators_objects_by_where_they_were_first_seen() -> None:
    # the executive's object 0 is the simulator's object 1 (it was nearer the robot)
    assert sim_index(record(0, 149.0, 52.0, None), START) == 1  # type: ignore[arg-type]
    assert sim_index(record(1, 51.0, 49.0, None), START) == 0  # type: ignore[arg-type]


def test_a_disturbance_counts_unless_the_check_found_the_object_moved_or_changed() -> None:
    records = [record(0, 150.0, 50.0, "learned/A"), record(1, 50.0, 50.0, "learned/B")]
    happened = [Happened(2, 90.0, 1, "nudge", "moved 6.0 in"), Happened(9, 500.0, 0, "replace", "a -> b")]
    noticed = [{"event": "disturbance", "object": 0, "found": "moved"}]
    assert unnoticed(records, noticed, happened, START) == [1]  # type: ignore[arg-type]
    assert saved_from_disturbed(records, noticed, happened, START) == 1  # type: ignore[arg-type]
    # a second disturbance of the same object needs a second finding
    twice = [*happened, Happened(12, 700.0, 1, "nudge", "moved 4.0 in")]
    assert unnoticed(records, noticed, twice, START) == [0, 1]  # type: ignore[arg-type]
    # an object not learned saves nothing, disturbed or not
    assert saved_from_disturbed([record(1, 50.0, 50.0, None)], [], happened, START) == 0  # type: ignore[arg-type]


def test_the_preset_mix_and_the_plan() -> None:
    assert preset(0.4).rates == (("nudge", 0.2), ("replace", 0.1), ("remove", 0.1))
    jobs = plan([0.0, 0.5], [0, 1])
    assert len(jobs) == 8 and DisturbanceJob(0.5, False, 1) in jobs


def row(outcome: str, correct: bool, removed: bool, robot_s: float, saved: bool = False,
        check: bool = True) -> ObjectRow:
    return ObjectRow(0.5, check, 0, "thing", outcome, correct, removed, removed or saved, robot_s, saved)


def test_a_cell_counts_success_over_the_objects_still_there() -> None:
    found = [row("grasped", True, False, 300.0), row("failed", False, False, 900.0),
             row("gone", False, True, 60.0), row("grasped", True, False, 240.0, saved=True)]
    c = cell(found)
    assert c.success == pytest.approx(2 / 3) and c.minutes == pytest.approx(1500.0 / 4 / 60.0)
    assert (c.gone, c.removed, c.saved_disturbed, c.objects) == (1, 1, 1, 4)


def test_the_summary_reads_the_counts_per_setting() -> None:
    results = {DisturbanceJob(0.5, True, 0): [row("gone", False, True, 60.0)],
               DisturbanceJob(0.5, False, 0): [row("failed", False, True, 600.0),
                                                 row("grasped", True, False, 300.0, saved=True, check=False)]}
    study = summarise(results, [0.5])
    measured = {r.measured: r.ours for r in study.rows}
    assert measured["descriptions saved from disturbed attempts, check on (must be 0)"] == "0"
    assert measured["descriptions saved from disturbed attempts, check off"] == "1"
    [(_, table)] = study.details
    assert table == (("0.5", "-, 1.0 min, 1/1 gone, 0 bad", "100%, 7.5 min, 0/1 gone, 1 bad"),)


@pytest.mark.slow
def test_one_job_runs_a_disturbed_floor_with_the_check_on() -> None:
    install_worker({"trained": read_library_json(defaults.EXAMPLE_LIBRARY)}, load_profile())
    rows = run_job(DisturbanceJob(1.0, True, 0))
    assert len(rows) == len(set_members("test"))  # every object of the floor found and reported
    assert not any(r.saved_disturbed for r in rows) and any(r.disturbed for r in rows)
    assert all(r.outcome == "gone" for r in rows if r.removed)
