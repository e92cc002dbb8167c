"""Choosing a test at a node: candidates, their gain and cost, and the ranking.

A *test* is a feature at a position (``Width-Degree-1°(24,0)``) or a grasp tried as a
binary feature (``Top-Pinch(6,*)``: success or failure). Candidates come from the
descriptions at the node: the learner can only test what some object was measured on.
Each is scored with the criterion on its gain and its cost *from the current position*;
the ranked list is kept so the executive can reselect the next-best test.

Gains for all columns are computed at once on the :class:`DescriptionMatrix`
(docs/method.md §3): values within the feature's error chain into one range; descriptions
lacking the value are spread evenly over the ranges (plus an "unknown" subset when the
ranges, widened by the error, leave part of the feature's domain uncovered).
"""

from __future__ import annotations

import functools
import math
from collections.abc import Mapping, Sequence
from dataclasses import dataclass, field

import numpy as np

from learner.costs import MoveCostEstimator
from learner.criteria import Criterion
from learner.knowledge import Knowledge
from learner.matrix import DescriptionMatrix, Test
from learner.partition import Range
from learner.position import Position

_MIN_GAIN = 1e-12
_EPS = 1e-9


@dataclass(frozen=True)
class Node:
    """The descriptions at a tree node: matrix rows, and which of them were *carried*
    there only because they lacked a tested feature (they help score tests but never
    decide a leaf's class)."""

    rows: tuple[int, ...]
    carried: tuple[bool, ...]

    @staticmethod
    def root(n: int, exclude: Sequence[int] = ()) -> Node:
        dropped = set(exclude)
        rows = tuple(i for i in range(n) if i not in dropped)
        return Node(rows, (False,) * len(rows))


@dataclass(frozen=True)
class ScoredTest:
    """A candidate test priced from the current position, with its branches."""

    test: Test
    target: Position  # the concrete position the robot goes to for it
    gain: float
    move_cost: float
    sense_cost: float
    score: float
    ranges: tuple[Range, ...]
    error: float  # the feature's expected error, for matching a measurement

    @property
    def cost(self) -> float:
        return self.move_cost + self.sense_cost


Measurements = Mapping[tuple[str, Position], float]


@dataclass(frozen=True)
class Context:
    """What scoring needs besides the node: the library, the criterion, the move costs,
    and a seeded generator for the choices a criterion leaves to chance (a cost-blind
    criterion breaks ties at random), so a run is repeatable from its seed."""

    matrix: DescriptionMatrix
    criterion: Criterion
    estimator: MoveCostEstimator
    rng: np.random.Generator = field(default_factory=lambda: np.random.default_rng(0), compare=False)

    @property
    def knowledge(self) -> Knowledge:
        return self.matrix.knowledge


def deciding_rows(node: Node) -> list[int]:
    """Rows whose class counts at a leaf: the genuine ones, or all when none is."""
    genuine = [r for r, c in zip(node.rows, node.carried) if not c]
    return genuine or list(node.rows)


def leaf_classes(node: Node, matrix: DescriptionMatrix) -> list[str]:
    """Grasps of the deciding rows, sorted: exactly one means the node is a leaf."""
    return sorted({matrix.descriptions[r].grasp for r in deciding_rows(node)})


def measured_value(test: Test, measurements: Measurements) -> float | None:
    """A value already measured on this object that serves for ``test`` (free to use)."""
    for (feature, at), value in measurements.items():
        # a value at (6,90) serves Height(6,*); one at (6,*) (an object with no
        # orientation) serves Height(6,90)
        if feature == test.feature and (test.position.covers(at) or at.covers(test.position)):
            return value
    return None


def target_for(test: Test, current: Position, ctx: Context) -> Position:
    """Where the robot goes for a test: ``*`` slots stay where the robot is, within range."""
    k = ctx.knowledge
    lo, hi = k.grasp(test.procedure).range_in if test.is_grasp else k.procedure_for(test.feature).range_in
    distance = test.position.distance_in
    if distance is None:
        distance = min(max(current.distance_in if current.distance_in is not None else lo, lo), hi)
    orientation = test.position.orientation_deg
    if orientation is None:
        orientation = current.orientation_deg if current.orientation_deg is not None else 0.0
    return Position(distance, orientation)


@dataclass(frozen=True)
class _Split:
    """Per-column partition of a node's rows: the ranges and the information gain."""

    ranges: list[list[Range]]
    gains: np.ndarray
    n_ranges: np.ndarray


def _partition_node(node: Node, matrix: DescriptionMatrix, columns: np.ndarray) -> _Split:
    """Chain-merged ranges and information gain of every column at once."""
    n, k, m = len(node.rows), len(matrix.classes), len(columns)
    order, vals = matrix.order[columns], matrix.sorted_values[columns]
    if n < len(matrix.descriptions):  # keep the node's rows, still sorted by value, NaN last
        member = np.zeros(len(matrix.descriptions), dtype=bool)
        member[list(node.rows)] = True
        keep = member[order]
        order, vals = order[keep].reshape(m, n), vals[keep].reshape(m, n)
    vcls = matrix.class_of[order]
    known = ~np.isnan(vals)
    n_known = known.sum(axis=1)
    err = matrix.errors[columns][:, None]
    step = np.zeros_like(vals)
    step[:, 1:] = vals[:, 1:] - vals[:, :-1]
    breaks = known & (step > err + _EPS)
    starts = breaks.copy()
    starts[:, 0] = known[:, 0]
    range_id = np.cumsum(starts, axis=1, dtype=np.int32) - 1
    n_ranges = starts.sum(axis=1)

    # the "unknown" subset: the ranges widened by the error leave part of the domain open
    last = np.take_along_axis(vals, np.maximum(n_known - 1, 0)[:, None], axis=1)[:, 0]
    widest_gap = np.where(breaks, step, 0.0).max(axis=1) if n > 1 else np.zeros(m)
    e = err[:, 0]
    numeric_covered = ((vals[:, 0] - e <= matrix.span_lo[columns] + _EPS)
                       & (last + e >= matrix.span_hi[columns] - _EPS) & (widest_gap <= 2 * e + _EPS))
    unknown = np.where(matrix.binary[columns], n_ranges < 2, ~numeric_covered) & ~matrix.is_grasp[columns]

    subsets = n_ranges + unknown
    max_r = int(n_ranges.max()) + 1 if m else 1
    col = np.arange(m, dtype=np.int32)[:, None]
    counts = np.bincount(((col * max_r + range_id) * k + vcls)[known],
                         minlength=m * max_r * k).astype(float).reshape(m, max_r, k)
    missing = np.bincount((col * k + vcls)[~known], minlength=m * k).astype(float).reshape(m, k)
    share = missing / np.maximum(subsets, 1)[:, None]
    in_range = np.arange(max_r)[None, :] < n_ranges[:, None]
    counts += np.where(in_range[:, :, None], share[:, None, :], 0.0)
    weights = np.concatenate([counts, np.where(unknown[:, None], share, 0.0)[:, None, :]], axis=1)
    totals = np.bincount(matrix.class_of[list(node.rows)], minlength=k).astype(float)
    h_total = _entropy(totals[None, :])[0]
    remainder = (weights.sum(axis=2) / max(n, 1) * _entropy(weights)).sum(axis=1)
    gains = np.where(n_ranges >= 2, np.maximum(h_total - remainder, 0.0), 0.0)

    ends = starts.copy()
    ends[:, :-1] = starts[:, 1:]
    ends[:, -1] = False
    ends |= known & (np.arange(n)[None, :] == (n_known - 1)[:, None])
    los, his = vals[starts].tolist(), vals[ends].tolist()
    bounds = np.concatenate([[0], np.cumsum(n_ranges)]).tolist()
    ranges = [list(zip(los[bounds[j]:bounds[j + 1]], his[bounds[j]:bounds[j + 1]])) for j in range(m)]
    return _Split(ranges, gains, n_ranges)


def _entropy(counts: np.ndarray) -> np.ndarray:
    """Entropy in bits along the last axis of (fractional) class counts."""
    total = counts.sum(axis=-1, keepdims=True)
    with np.errstate(divide="ignore", invalid="ignore"):
        p = np.where(total > 0, counts / total, 0.0)
        terms = np.where(p > 0, p * np.log2(np.where(p > 0, p, 1.0)), 0.0)
    return -terms.sum(axis=-1)


def rank(
    node: Node,
    current: Position,
    ctx: Context,
    measurements: Measurements,
    exclude: frozenset[Test] = frozenset(),
) -> list[ScoredTest]:
    """All usable tests at a node, best first (ties: the nearer, then the cheaper).

    A test is usable when it splits the node into two or more branches with positive
    gain (or, when none gains anything, any test that splits); grasp tests only while
    the node holds more than one grasp.
    """
    matrix = ctx.matrix
    several_classes = len(np.unique(matrix.class_of[list(node.rows)])) > 1
    columns = np.array([j for j, t in enumerate(matrix.tests)
                        if t not in exclude and (several_classes or not t.is_grasp)], dtype=np.int64)
    if len(columns) == 0 or not node.rows:
        return []
    split = _partition_node(node, matrix, columns)
    usable = split.gains > _MIN_GAIN
    if not usable.any():
        # No single test gains anything (XOR-like data), yet a split may separate the
        # classes one level down: take splitting tests anyway, cheapest first.
        usable = split.n_ranges >= 2
    move_costs: dict[Position, float] = {}  # many tests share a position: price each once
    scored: list[ScoredTest] = []
    for j in np.flatnonzero(usable):
        test = matrix.tests[columns[j]]
        gain = float(split.gains[j])
        if not test.is_grasp and measured_value(test, measurements) is not None:
            target, move, sense = current, 0.0, 0.0
        else:
            target = target_for(test, current, ctx)
            if target not in move_costs:
                move_costs[target] = ctx.estimator.move_cost(current, target)
            move = move_costs[target]
            sense = (ctx.knowledge.grasp(test.procedure).feature_cost_s if test.is_grasp
                     else ctx.knowledge.procedure_for(test.feature).time_s)
        if not math.isfinite(move):
            continue  # no path to the test's position: the learner cannot use it
        score = ctx.criterion.score(gain, move + sense)
        scored.append(ScoredTest(test, target, gain, move, sense, score, tuple(split.ranges[j]),
                                 float(matrix.errors[columns[j]])))
    return sorted(scored, key=functools.cmp_to_key(_better))


def _better(a: ScoredTest, b: ScoredTest) -> int:
    """Order two scored tests; scores within 1e-9 relative are a tie."""
    if math.isinf(a.score) and math.isinf(b.score):
        if not math.isclose(a.gain, b.gain, rel_tol=1e-9, abs_tol=1e-12):
            return -1 if a.gain > b.gain else 1
    elif not math.isclose(a.score, b.score, rel_tol=1e-9, abs_tol=1e-12):
        return -1 if a.score > b.score else 1
    for x, y in ((a.move_cost, b.move_cost), (a.sense_cost, b.sense_cost)):
        if not math.isclose(x, y, rel_tol=1e-9, abs_tol=1e-9):
            return -1 if x < y else 1
    return -1 if a.test < b.test else (1 if b.test < a.test else 0)


def split(node: Node, scored: ScoredTest, matrix: DescriptionMatrix) -> list[Node]:
    """The node of each branch: rows in its range, plus every row lacking the value
    (carried, so it does not decide a leaf)."""
    j = matrix.column[scored.test]
    rows: list[list[int]] = [[] for _ in scored.ranges]
    carried: list[list[bool]] = [[] for _ in scored.ranges]
    for r, c in zip(node.rows, node.carried):
        v = matrix.values[r, j]
        if np.isnan(v):
            for b in range(len(rows)):
                rows[b].append(r)
                carried[b].append(True)
            continue
        for b, (lo, hi) in enumerate(scored.ranges):
            if lo - _EPS <= v <= hi + _EPS:
                rows[b].append(r)
                carried[b].append(c)
                break
    return [Node(tuple(r), tuple(c)) for r, c in zip(rows, carried)]
