"""Choosing a test: gains over noise-tolerant partitions, costs from here, ties, trends."""

from __future__ import annotations

import dataclasses
import math

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from learner.choosing.criteria import criterion
from learner.choosing.gain import partition_columns
from learner.choosing.matrix import DescriptionMatrix
from learner.choosing.node import Node
from learner.choosing.partition import match, nearest, partition
from learner.choosing.selection import rank
from tests.learner import test_matrix_append as append_tests
from tests.learner.fixtures import ANY, P, context, desc, four_objects, hero
from tests.learner.reference import information_gain


def H(*p: float) -> float:  # noqa: N802
    return -sum(x * math.log2(x) for x in p if x > 0)


def test_chained_merging_within_the_error() -> None:
    assert partition([7, 1, 3.5, 2], 1.5) == [(1, 3.5), (7, 7)]  # 1-2 and 2-3.5 chain
    assert partition([7, 1, 3.5, 2], 1.0) == [(1, 2), (3.5, 3.5), (7, 7)]
    assert partition([7, 1, 3.5, 2], 0.9) == [(1, 1), (2, 2), (3.5, 3.5), (7, 7)]
    assert partition([0, 1, 1, 0], 0.0) == [(0, 0), (1, 1)]


def test_matching_widens_ranges_by_the_error_and_rejects_overlaps() -> None:
    ranges = [(8, 9), (14, 15)]  # error 3: widened to [5, 12] and [11, 18]
    assert match(5.0, ranges, 3.0) == 0
    assert match(17.5, ranges, 3.0) == 1
    assert match(11.5, ranges, 3.0) is None  # in both widened ranges: unreliable
    assert match(4.0, ranges, 3.0) is None  # in none
    assert nearest(11.4, ranges) == 0 and nearest(11.6, ranges) == 1 and nearest(40, ranges) == 1


def test_gains_of_the_four_object_library_by_hand() -> None:
    ctx = context(four_objects())
    ranked = {str(s.test): s for s in rank(Node.root(4), P(60, 0), ctx, {})}
    assert ranked["Width-Degree-1°(24,0)"].gain == pytest.approx(2 - 0.5 * 1.0)
    assert ranked["Width-Degree-1°(24,0)"].ranges == ((8, 9), (18, 18), (30, 30))
    # Height: closed box missing, 3 ranges + unknown subset, 1/4 of it in each subset
    assert ranked["Height(6,*)"].gain == pytest.approx(2 - 3 * (1.25 / 4) * H(0.8, 0.2))
    # Top-Hole? is known for the tumbler only: one range cannot make two branches
    assert "Top-Hole?(6,*)" not in ranked
    # a grasp as a binary feature: one class against three
    assert ranked["Front-Pinch(6,*)"].gain == pytest.approx(2 - 0.75 * math.log2(3))
    assert "No-Grab(*,*)" not in ranked  # the finger sensor cannot confirm No-Grab


def test_scalar_reference_agrees_with_the_matrix_on_missing_values() -> None:
    # subsets {a, a/3} {b, b, a/3} {a/3}: only the middle one is mixed
    expected = H(0.5, 0.5) - (7 / 3) / 4 * H(1 / 7, 6 / 7)
    assert information_gain([("a", 0), ("b", 1), ("b", 1)], ["a"], 2, True) == pytest.approx(expected)
    lib = [desc("a1", "Front-Wrap", ("Width", P(6, 0), 3)), desc("a2", "Front-Wrap"),
           desc("b1", "Front-Pinch", ("Width", P(6, 0), 9)), desc("b2", "Front-Pinch", ("Width", P(6, 0), 9.2))]
    width = rank(Node.root(4), P(6, 0), context(lib, grasps=False), {})[0]
    assert width.gain == pytest.approx(expected)


def test_costs_from_the_current_position() -> None:
    ctx = context(four_objects())
    best = rank(Node.root(4), P(60, 0), ctx, {})[0]
    # from (60,0) to (24,0): 36 in x 2 s (the paper's worked example); sweep 100 s
    assert str(best.test) == "Width-Degree-1°(24,0)"
    assert best.move_cost == pytest.approx(72.0) and best.sense_cost == 100
    assert best.score == pytest.approx(1.5**2 / 172)
    from_side = rank(Node.root(4), P(24, 90), ctx, {})
    sweep = next(s for s in from_side if str(s.test) == "Width-Degree-1°(24,0)")
    assert sweep.move_cost == pytest.approx(2 * 24 * math.sqrt(2))  # the chord from (24,90)
    turning = dataclasses.replace(hero().move, seconds_per_degree=0.2, overhead_s=20.0)
    sweep = next(s for s in rank(Node.root(4), P(24, 90), context(four_objects(), move=turning), {})
                 if str(s.test) == "Width-Degree-1°(24,0)")
    # turn from facing 270 to travel -45 (45°), drive, turn to face the object at 180 (135°)
    assert sweep.move_cost == pytest.approx(20 + 2 * 24 * math.sqrt(2) + 0.2 * (45 + 135))


def test_a_measured_feature_is_free_and_chosen_first() -> None:
    ctx = context(four_objects())
    ranked = rank(Node.root(4), P(6, 0), ctx, {("Height", P(6, 0)): 9.0})
    assert str(ranked[0].test) == "Height(6,*)" and ranked[0].cost == 0


def test_equal_gain_and_sensing_cost_the_nearer_feature_wins() -> None:
    lib = [
        desc("a", "Front-Wrap", ("Width-Degree-1°", P(24, 0), 8), ("Width-Degree-1°", P(16, 0), 8)),
        desc("b", "Front-Pinch", ("Width-Degree-1°", P(24, 0), 20), ("Width-Degree-1°", P(16, 0), 30)),
    ]
    for name in ("cs-id3", "id3-cost-ties", "idx", "eg2"):  # id3 itself leaves ties to chance
        ranked = rank(Node.root(2), P(10, 0), context(lib, name=name, grasps=False), {})
        assert [str(s.test) for s in ranked] == ["Width-Degree-1°(16,0)", "Width-Degree-1°(24,0)"], name
        assert ranked[0].gain == ranked[1].gain == 1.0


def _trend_library() -> list:
    """Sweep at 24 in (100 s) splits 3 ways (1.5 bits); Height at 6 in (84 s) splits 4 (2 bits)."""
    return [
        desc("cup", "Front-Wrap", ("Width-Degree-1°", P(24, 0), 8), ("Height", P(6, ANY), 3.5)),
        desc("tumbler", "Top-Pinch", ("Width-Degree-1°", P(24, 0), 9), ("Height", P(6, ANY), 6)),
        desc("box", "Front-Pinch", ("Width-Degree-1°", P(24, 0), 18), ("Height", P(6, ANY), 9)),
        desc("closed", "No-Grab", ("Width-Degree-1°", P(24, 0), 30), ("Height", P(6, ANY), 12)),
    ]


def test_higher_move_costs_push_sensing_to_a_distance() -> None:
    k = hero()
    # from (40,0): sweep costs 100 + 16m, scan 84 + 34m; crossover where
    # 2.25 / (100 + 16m) = 4 / (84 + 34m), m = 16.9 s/in
    cheap = rank(Node.root(4), P(40, 0), context(_trend_library(), move=k.move), {})[0]
    assert cheap.target == P(6, 0)
    dear_move = dataclasses.replace(k.move, seconds_per_inch=40.0)
    dear = rank(Node.root(4), P(40, 0), context(_trend_library(), move=dear_move), {})[0]
    assert dear.target == P(24, 0)
    assert dear.score == pytest.approx(2.25 / (100 + 16 * 40))


def test_higher_sensing_costs_make_grasps_come_first() -> None:
    k = hero()
    first = rank(Node.root(4), P(40, 0), context(_trend_library()), {})[0]
    assert not first.test.is_grasp
    slow = dataclasses.replace(k, sensing=tuple(dataclasses.replace(p, time_s=p.time_s * 20) for p in k.sensing))
    first = rank(Node.root(4), P(40, 0), context(_trend_library(), knowledge=slow), {})[0]
    # Front-Pinch as a feature: 0.811 bits for 45 + 30 s plus the 68 s move, the cheapest grasp
    assert first.test.is_grasp and first.test.feature == "Front-Pinch"
    assert first.score == pytest.approx((2 - 0.75 * math.log2(3)) ** 2 / (68 + 75))


def test_criteria_formulas() -> None:
    assert criterion("cs-id3").score(1.5, 3.0) == pytest.approx(0.75)
    assert criterion("id3").score(1.5, 3.0) == 1.5
    assert criterion("idx").score(1.5, 3.0) == pytest.approx(0.5)
    assert criterion("eg2", 2.0).score(1.0, 3.0) == pytest.approx(1 / 16)
    assert criterion("cs-id3").score(0.5, 0.0) == math.inf
    with pytest.raises(ValueError, match="unknown criterion 'c4.5'"):
        criterion("c4.5")


@pytest.mark.slow
@settings(max_examples=60, deadline=None)
@given(st.lists(append_tests.descriptions(), min_size=1, max_size=14), st.data())
def test_the_vectorised_partition_equals_the_scalar_one_column_by_column(library: list, data: st.DataObject) -> None:
    # the fast path (known values only, all columns at once, the root memoised) against
    # learner.choosing.partition and the reference gain, one column and one row at a time
    matrix = DescriptionMatrix(library, hero())
    rows = sorted(data.draw(st.sets(st.sampled_from(range(len(library))), min_size=1)))
    columns = np.array(sorted(data.draw(st.sets(st.sampled_from(range(len(matrix.tests))), min_size=1))))
    found = partition_columns(rows, matrix, columns)
    for i, j in enumerate(columns.tolist()):
        values = [(matrix.values[r, j], matrix.classes[matrix.class_of[r]]) for r in rows]
        known = [(v, c) for v, c in values if not math.isnan(v)]
        ranges = partition([v for v, _ in known], matrix.errors[j])
        assert found.ranges[i] == ranges
        err, lo, hi = matrix.errors[j], matrix.span_lo[j], matrix.span_hi[j]
        covered = bool(ranges) and (ranges[0][0] - err <= lo + 1e-9 and ranges[-1][1] + err >= hi - 1e-9
                                    and all(b[0] - a[1] <= 2 * err + 1e-9 for a, b in zip(ranges, ranges[1:])))
        unknown = (len(ranges) < 2 if matrix.binary[j] else not covered) and not matrix.is_grasp[j]
        assert bool(found.unknown[i]) == unknown
        in_range = [(c, next(b for b, (a, z) in enumerate(ranges) if a <= v <= z)) for v, c in known]
        gain = information_gain(in_range, [c for v, c in values if math.isnan(v)], len(ranges), unknown)
        assert found.gains[i] == pytest.approx(gain if len(ranges) >= 2 else 0.0, abs=1e-9)
    assert partition_columns(rows, matrix, columns).ranges == found.ranges  # asked again (memoised at the root)
