"""The report's ``tests`` column counts every test applied to recognize the object: the
paid sensing procedures and the grasps tried as binary features, whether they held or not
(once, an object whose tree showed three grasps tried as tests read 0)."""

from __future__ import annotations

from types import SimpleNamespace

import pytest

from behaviours.records import Ledger
from reporting.report import print_report, rows


def _record(tests: list[str], outcome: str, grasp: str | None) -> SimpleNamespace:
    region = SimpleNamespace(centroid=(10.0, 20.0))
    return SimpleNamespace(index=3, region=region, first_region=region, outcome=outcome, grasp=grasp,
                           ledger=Ledger(moving_s=60.0, tests=tests))


def test_three_grasps_tried_as_features_and_a_sensing_procedure_are_four_tests() -> None:
    # Fig. 5's path for an object: a width reading, then three grasps tried as features that
    # did not hold, then the leaf's grasp (not a test) held.
    ledger = ["Width-Degree-1°(24,0)=8.5", "Front-Wrap(6,*)=0", "Top-Pinch(6,*)=0", "Side-Pinch(6,*)=0"]
    [row] = rows([_record(ledger, "grasped", "Front-Pinch")])  # type: ignore[list-item]
    assert (row.tests, row.index, row.grasp) == (4, 3, "Front-Pinch")


def test_the_table_says_what_the_column_counts(capsys: pytest.CaptureFixture[str]) -> None:
    print_report(rows([_record(["Front-Wrap(6,*)=1"], "grasped", "Front-Wrap")]))  # type: ignore[list-item]
    out = capsys.readouterr().out
    caption = [line for line in out.splitlines() if line.startswith(("min:", "tests:"))]
    assert caption[1] == "tests: sensing procedures applied, grasps tried as features (not a leaf's grasp)"
    assert max(len(line) for line in caption) <= 80
