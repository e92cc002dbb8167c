"""The experiment CSV holds one row per true object even when the robot recorded one
object twice (the quick run once wrote 15 rows for a 14-object floor)."""

from __future__ import annotations

from experiments.episodes import one_row_per_object
from reporting.report import Row, Truth

TUMBLER = Truth("tumbler", ("Pinch-Top",), 10.0, 20.0)
CUP = Truth("cup", ("Pinch-Side",), 40.0, 20.0)


def _row(index: int, outcome: str, grasp: str, *, moving: float, tests: int,
         recoveries: tuple[tuple[str, int], ...] = ()) -> Row:
    text = ", ".join(f"{k} ×{v}" for k, v in recoveries) or "-"
    return Row("tumbler", grasp, outcome, outcome == "grasped", moving, 2.0, 1.0, 5.0, tests, text, index, recoveries)


def test_an_object_recorded_twice_is_one_row_adding_up_its_records() -> None:
    # record 0: the robot knocked the tumbler over and lost it; record 2: found again and grasped.
    first = _row(0, "lost", "-", moving=30.0, tests=2, recoveries=(("backtrack", 1),))
    cup = _row(1, "grasped", "Pinch-Side", moving=10.0, tests=1)
    again = _row(2, "grasped", "Pinch-Top", moving=12.0, tests=3, recoveries=(("backtrack", 1), ("reselect", 2)))
    out = one_row_per_object([(TUMBLER, first), (CUP, cup), (TUMBLER, again)])
    assert [indices for _, indices in out] == [(0, 2), (1,)]
    tumbler, _ = out[0]
    assert (tumbler.outcome, tumbler.grasp, tumbler.index) == ("grasped", "Pinch-Top", 2)
    assert (tumbler.moving_s, tumbler.sensing_s, tumbler.grasping_s) == (42.0, 4.0, 2.0)
    assert (tumbler.computing_ms, tumbler.tests) == (10.0, 5)
    assert tumbler.recoveries == "backtrack ×2, reselect ×2"
    assert out[1][0] == cup


def test_the_verdict_is_the_last_handled_record_not_a_later_unfinished_one() -> None:
    grasped = _row(0, "grasped", "Pinch-Top", moving=5.0, tests=1)
    unfinished = _row(3, "unfinished", "-", moving=1.0, tests=0)
    [(row, indices)] = one_row_per_object([(TUMBLER, grasped), (TUMBLER, unfinished)])
    assert (row.outcome, row.index, indices) == ("grasped", 0, (0, 3))


def test_records_without_a_truth_stay_apart() -> None:
    a, b = _row(0, "grasped", "Pinch-Top", moving=1.0, tests=1), _row(1, "left", "-", moving=1.0, tests=1)
    assert one_row_per_object([(None, a), (None, b)]) == [(a, (0,)), (b, (1,))]
