"""``csl experiment clutter``: the summary worked by hand, and the quick run end to end."""

from __future__ import annotations

import math

import pytest

from csl_cli.main import main
from experiments.study_clutter import APART, ClutterJob, ObjectRow, plan, summarise


def row(gap: float, check: bool, correct: bool, robot_s: float, readings: int, bad: int,
        blocked: int = 0) -> ObjectRow:
    return ObjectRow(gap, check, 0, "x", "grasped" if correct else "failed", correct, robot_s, readings, bad, blocked)


def test_summary_by_hand() -> None:
    results = {
        ClutterJob(APART, True, 0): [row(APART, True, True, 300.0, 2, 0), row(APART, True, False, 420.0, 3, 0)],
        ClutterJob(APART, False, 0): [row(APART, False, True, 300.0, 2, 0), row(APART, False, True, 420.0, 3, 0)],
        ClutterJob(1.0, True, 0): [row(1.0, True, True, 360.0, 1, 0, 2), row(1.0, True, True, 480.0, 2, 0, 1)],
        ClutterJob(1.0, False, 0): [row(1.0, False, False, 600.0, 4, 2), row(1.0, False, True, 600.0, 2, 1)],
    }
    study = summarise(results, (APART, 1.0))
    measured = {r.measured: r.ours for r in study.rows}
    assert measured["contaminated readings used, beam check on / off"] == "0 / 3"
    assert measured["success at 1 in: check on / off"] == "100% / 50%"
    assert measured["robot min per object at 1 in: check on / off"] == "7.0 / 10.0"  # (360+480)/2/60, 600/60
    (_, table), = study.details
    assert table[0] == ("apart", "50%, 6.0 min, 0/5 contaminated, 0 beam blocked",
                        "100%, 6.0 min, 0/5 contaminated, 0 beam blocked")
    assert table[1][1] == "100%, 7.0 min, 0/3 contaminated, 3 beam blocked"  # 2 + 1 refusals


def test_every_gap_runs_with_the_check_on_and_off_on_the_same_floors() -> None:
    jobs = plan((APART, 2.0), (0, 1))
    assert len(jobs) == 8 and {(j.gap, j.check) for j in jobs} == {(g, c) for g in (APART, 2.0) for c in (True, False)}
    assert math.isinf(jobs[0].gap)


@pytest.mark.slow
def test_quick_run_prints_the_section(capsys: pytest.CaptureFixture[str]) -> None:
    assert main(["experiment", "clutter", "--quick", "--jobs", "1"]) == 0
    out = capsys.readouterr().out
    assert out.startswith("### Clutter: success, cost and contaminated readings")
    assert "| apart | " in out and "| 2 in | " in out
    # objects ~62 in apart: no reading is ever contaminated, whatever the check
    apart = next(line for line in out.splitlines() if line.startswith("| apart |"))
    assert apart.count(" 0/") == 2
