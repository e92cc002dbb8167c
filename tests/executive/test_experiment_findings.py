"""The measurements behind the experiment's findings (docs/method.md, "Findings"),
worked by hand on small libraries."""

from __future__ import annotations

from pathlib import Path

import pytest

from experiments import study_execution
from experiments.conditions import STRATEGIES_OFF, STRATEGIES_ON
from experiments.config import ExperimentConfig
from experiments.episodes import EpisodeRow
from experiments.study_execution import first_grasp_right, recoveries_per_object
from experiments.study_training import distances_note, unresolved_hours
from experiments.study_trends import root_gain_by_distance
from learner.choosing.criteria import DEFAULT_CRITERION
from learner.training.stage import DistanceReason, TrainingLog
from tests.learner.fixtures import ANY, P, desc, hero


def test_the_best_root_gain_of_a_test_from_each_distance() -> None:
    # Near, the 5° sweep tells the three grasps apart: log2 3 = 1.585 bits. From 39 in the
    # 1° sweep reads 4, 13, 14: 13 and 14 lie within its ±3° and merge, so it tells the cup
    # from the other two only: 1.585 - 2/3 x 1 = 0.918 bits. The grasps (1 bit at most
    # here, Front-Wrap against the rest: 0.918) are not sensing tests and are left out, and
    # so is a height made anywhere, (*,*): it has no distance.
    library = [
        desc("cup", "Front-Wrap", ("Width-Degree-5°", P(6, 0), 25), ("Width-Degree-1°", P(39, 0), 4),
             ("Height-Degree-5°", P(ANY, ANY), 30)),
        desc("box", "Front-Pinch", ("Width-Degree-5°", P(6, 0), 45), ("Width-Degree-1°", P(39, 0), 13),
             ("Height-Degree-5°", P(ANY, ANY), 60)),
        desc("tumbler", "Top-Pinch", ("Width-Degree-5°", P(6, 0), 65), ("Width-Degree-1°", P(39, 0), 14),
             ("Height-Degree-5°", P(ANY, ANY), 90)),
    ]
    gains = root_gain_by_distance(library, hero())
    assert list(gains) == [6.0, 39.0]
    assert gains[6.0] == pytest.approx(1.5850, abs=1e-4)
    assert gains[39.0] == pytest.approx(1.5850 - 2 / 3, abs=1e-4)


def test_no_library_no_gains() -> None:
    assert root_gain_by_distance([], hero()) == {}


def _row(success: bool, wrong_grasps: int, recoveries: str = "-") -> EpisodeRow:
    return EpisodeRow("baselines", "v", "cs-id3-failure", "paper", 1.0, "off", 1.0, 1.0, "trained", "training", 0, 0,
                      14, "cup", "grasped" if success else "failed", "Front-Wrap", success, 300.0, 45.0, 120.0, 135.0,
                      5.0, 1, 6.0, 0, wrong_grasps, recoveries)


def test_first_grasp_right_needs_success_and_no_failed_leaf_grasp() -> None:
    assert first_grasp_right(_row(True, 0))
    assert not first_grasp_right(_row(True, 1))  # right in the end, after a failed-grasp recovery
    assert not first_grasp_right(_row(False, 0))


def test_recoveries_are_counted_per_object_by_their_name() -> None:
    rows = [_row(True, 0, "backtrack ×2, nearest neighbour ×1, reselect ×3"), _row(True, 0, "reselect ×1"),
            _row(True, 0)]
    assert recoveries_per_object(rows, "reselect") == pytest.approx(4 / 3)
    assert recoveries_per_object(rows, "backtrack") == pytest.approx(2 / 3)
    assert recoveries_per_object(rows, "nearest neighbour") == pytest.approx(1 / 3)
    assert recoveries_per_object(rows, "neighbour") == 0.0  # a whole name, not a part of one


def test_strategies_off_runs_on_both_object_sets_beside_the_execution_runs() -> None:
    config = ExperimentConfig(quick=True, seeds=(0, 1), jobs=1, out=Path("."), command="csl experiment paper --quick")
    specs = study_execution.plan(config)
    off = [s for s in specs if s.control == STRATEGIES_OFF]
    assert sorted((s.objects, s.seed) for s in off) == [("test", 0), ("test", 1), ("training", 0), ("training", 1)]
    on = {(s.objects, s.seed) for s in specs if s.control == STRATEGIES_ON and s.library == "trained"
          and s.criterion == DEFAULT_CRITERION}
    assert {(s.objects, s.seed) for s in off} <= on  # every off run has its on run, paired by floor


def test_the_distances_note_counts_the_candidates_each_distance_stands_for() -> None:
    # candidates 6, 6.4, 8 and 11 stand for 6 in; 15.5 and 20 for 15 in; 39.7 for 39 in
    log = TrainingLog(distances=[6.0, 15.0, 39.0], distance_reasons=[
        DistanceReason("Width-Degree-5°", "a", "b", d) for d in (6.0, 6.4, 8.0, 11.0, 15.5, 20.0)]
        + [DistanceReason("Width-Degree-1°", "box", "open-box", 39.7)])
    note = distances_note(log)
    assert "7 candidates" in note
    assert "6 in: 4, 15 in: 2, 39 in: 1." in note
    assert "The farthest, 39.7 in (Width-Degree-1° separating box from open-box)" in note


def test_unresolved_hours_count_the_sensing_at_pairs_never_classified() -> None:
    # the box at (15,0) was never classified: its two sweeps there (100 s + 45 s) count;
    # the same sweep on the cup, and the box's at 6 in, do not
    k = hero()
    at, near = P(15, 0), P(6, 0)
    log = TrainingLog(applied=[("box", "H-Sweep-1°", at, "discriminate"), ("box", "H-Sweep-5°", at, "discriminate"),
                               ("cup", "H-Sweep-1°", at, "discriminate"), ("box", "H-Scan-0.3", near, "discriminate")],
                      unresolved=[("box", at), ("box", at)])
    times = {p.name: p.time_s for p in k.sensing}
    assert unresolved_hours(log, k) == pytest.approx((times["H-Sweep-1°"] + times["H-Sweep-5°"]) / 3600)
