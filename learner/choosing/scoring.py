"""Ranking the tests at a node by score: candidates, their gain and cost, the criterion.

A *test* is a feature at a position (``Width-Degree-1°(24,0)``) or a grasp tried as a
binary feature (``Top-Pinch(6,*)``: success or failure). Candidates come from the
descriptions at the node: the learner can only test what some object was measured on.
Each is scored with the criterion on its gain and its cost *from the current position*;
the ranked list is kept so the executive can reselect the next-best test.

Gains come from ``learner.choosing.gain`` (docs/method.md §3); what a criterion does besides its
formula (cost-blind ties and ``*`` slots, joint gain, lookahead) it declares in its
registry entry, and the ranking here follows it. A ``rollout`` criterion's last step,
its best few ranked again by expected cost to the end, is ``learner.choosing.selection``'s:
the rollouts finish each candidate with the ranking here.
"""

from __future__ import annotations

import dataclasses
import functools
import math

import numpy as np

from learner.choosing.gain import joint_gain, partition_columns
from learner.choosing.matrix import DescriptionMatrix, Test
from learner.choosing.node import (Context, Measurements, Node, ScoredTest, leaf_classes, measured_value,
                                   procedure_cost, procedure_range, split, target_for, yielded)
from learner.choosing.partition import Split
from learner.costs import sensing_cost
from learner.position import Position

_MIN_GAIN = 1e-12
LOOKAHEAD_WIDTH = 8
"""How many of the best tests by one step a lookahead criterion scores again over two:
each costs a ranking per branch, and a test far down the one-step order is rarely the
best over two steps."""


def rank_by_score(
    node: Node,
    current: Position,
    ctx: Context,
    measurements: Measurements,
    exclude: frozenset[Test] = frozenset(),
) -> list[ScoredTest]:
    """All usable tests at a node, best first by the criterion's score.

    A test is usable when it splits the node into two or more branches with positive
    gain (or, when none gains anything, any test that splits); grasp tests only while
    the node holds more than one grasp. Each is scored by the criterion on its gain (the
    joint gain of its procedure application, for a ``joint_gain`` criterion) and its
    cost from ``current``; a ``lookahead`` criterion then rescores the paid ones over two
    steps (of the best :data:`LOOKAHEAD_WIDTH` by one step; the rest follow them). A
    ``grasp_paid_on_failure`` criterion prices a grasp test at its failure probability
    times its cost (``scored_on``). Ties go to the nearer, then the cheaper test, or, for
    a criterion with ``cost_blind_choices``, are ordered at random from ``ctx.rng``. A
    ``rollout`` criterion's own step is not taken here (``learner.choosing.selection.rank``).
    """
    matrix = ctx.matrix
    row_index = np.fromiter(node.rows, dtype=np.int64, count=len(node.rows))  # once: a list of 10,000 rows costs
    several_classes = len(np.unique(matrix.class_of[row_index])) > 1
    columns = np.array([j for j, t in enumerate(matrix.tests)
                        if t not in exclude and (several_classes or not t.is_grasp)], dtype=np.int64)
    if len(columns) == 0 or not node.rows:
        return []
    found = partition_columns(node.rows, matrix, columns)
    usable = found.gains > _MIN_GAIN
    if not usable.any():
        # No single test gains anything (XOR-like data), yet a split may separate the
        # classes one level down: take splitting tests anyway, ties settled as ever.
        usable = found.n_ranges >= 2
    joint = _JointGains(node, ctx, columns, found, measurements) if ctx.criterion.joint_gain else None
    move_costs: dict[tuple[Position, bool], float] = {}  # many tests share a position: price each once
    weights = node.weight_array() if ctx.criterion.grasp_paid_on_failure else None  # once, not per grasp test
    scored: list[ScoredTest] = []
    for j in np.flatnonzero(usable):
        test = matrix.tests[columns[j]]
        gain = float(found.gains[j])
        if not test.is_grasp and measured_value(test, measurements) is not None:
            target, move, sense = current, 0.0, 0.0
        else:
            target = (_anywhere(test, ctx) if ctx.criterion.cost_blind_choices else target_for(test, current, ctx))
            if (target, test.is_grasp) not in move_costs:
                move_costs[target, test.is_grasp] = (ctx.estimator.move_cost(current, target) if test.is_grasp
                                                     else sensing_cost(ctx.estimator, current, target))
            move = move_costs[target, test.is_grasp]
            sense = procedure_cost(test, ctx.knowledge)
        if not math.isfinite(move):
            continue  # no path to the test's position: the learner cannot use it
        scored_on = None
        if joint is not None and move + sense > 0 and not test.is_grasp:
            scored_on = (joint.of(test, target), move + sense)
        elif test.is_grasp and ctx.criterion.grasp_paid_on_failure:
            scored_on = (gain, _failure_share(weights, row_index, matrix, test) * (move + sense))
        score = ctx.criterion.score(*(scored_on or (gain, move + sense)))
        scored.append(ScoredTest(test, target, gain, move, sense, score, tuple(found.ranges[j]),
                                 float(matrix.errors[columns[j]]), scored_on))
    ranked = _ordered(scored, ctx)
    if ctx.criterion.lookahead:
        # the few best by one step are looked at again over two; the rest follow them,
        # in their one-step order, for reselection
        shortlist = [_two_steps(node, s, ctx, measurements, exclude) for s in ranked[:LOOKAHEAD_WIDTH]]
        ranked = _ordered(shortlist, ctx) + ranked[LOOKAHEAD_WIDTH:]
    return ranked


def _failure_share(weights: np.ndarray | None, row_index: np.ndarray, matrix: DescriptionMatrix,
                   test: Test) -> float:
    """The probability that a grasp tried as a feature fails at a node (``row_index``:
    its rows as an array, ``weights``: :meth:`Node.weight_array`): the weight of its rows whose
    grasp column is 0 (a grasp column is known for every description), each row weighted
    by how likely it came this way."""
    failing = matrix.values[row_index, matrix.column[test]] < 0.5
    if weights is None:  # every row alike: the share of rows
        return float(np.count_nonzero(failing)) / len(row_index)
    return float(weights[failing].sum())


class _JointGains:
    """The joint gain of each procedure application at a node, computed once per
    (procedure, position): every test of that application shares it."""

    def __init__(self, node: Node, ctx: Context, columns: np.ndarray, found: Split,
                 measurements: Measurements) -> None:
        self._node, self._ctx, self._found = node, ctx, found
        # a feature already measured is free anyway: it adds nothing to a new application
        self._members = [(i, ctx.matrix.tests[c]) for i, c in enumerate(columns)
                         if not ctx.matrix.tests[c].is_grasp and found.n_ranges[i] >= 2
                         and measured_value(ctx.matrix.tests[c], measurements) is None]
        self._columns = columns
        self._cache: dict[tuple[str, Position], float] = {}

    def of(self, test: Test, target: Position) -> float:
        key = (test.procedure, target)
        if key not in self._cache:
            yields = [i for i, t in self._members if t.procedure == test.procedure and t.position.covers(target)]
            self._cache[key] = joint_gain(self._node.rows, self._ctx.matrix, [int(self._columns[i]) for i in yields],
                                          [self._found.ranges[i] for i in yields],
                                          [bool(self._found.unknown[i]) for i in yields])
        return self._cache[key]


def _two_steps(node: Node, first: ScoredTest, ctx: Context, measurements: Measurements,
               exclude: frozenset[Test]) -> ScoredTest:
    """``first`` rescored on what two steps are expected to gain and cost: itself, then in
    each branch (weighted by its share of the node) the best next paid test from
    ``first``'s position, ranked by score without lookahead; free tests on the way (the
    siblings ``first``'s procedure yielded) are followed, their gain counted at no cost.
    A leaf adds nothing. ``first`` counts its own gain here, not its application's joint gain:
    the free siblings that follow it carry the rest, and must not be counted twice.

    Why: a greedy ratio favours the test that settles everything at once (a 90 s grasp
    over a 42 s sweep that leaves two of five objects to a 63 s follow-up, 67 s
    expected); over two steps the cheaper route shows its worth. A free test needs no
    lookahead: it outscores every paid one anyway.
    """
    if first.cost <= 0:
        return first
    one_step = dataclasses.replace(ctx, criterion=dataclasses.replace(ctx.criterion, lookahead=False))
    gain, cost = _after(node, first, one_step, {**measurements, **yielded(first, ctx)}, exclude | {first.test})
    gain, cost = first.gain + gain, first.cost + cost
    return dataclasses.replace(first, score=ctx.criterion.score(gain, cost), scored_on=(gain, cost))


def _after(node: Node, taken: ScoredTest, ctx: Context, measurements: Measurements,
           exclude: frozenset[Test]) -> tuple[float, float]:
    """Expected (gain, cost), over ``taken``'s branches, of the next paid test in each,
    free tests before it followed."""
    shares = partition_columns(node.rows, ctx.matrix, np.array([ctx.matrix.column[taken.test]])).mass[0]
    gain = cost = 0.0
    for share, child in zip(shares.tolist(), split(node, taken, ctx.matrix)):
        if share <= 0 or len(leaf_classes(child, ctx.matrix)) == 1:
            continue
        following = rank_by_score(child, taken.target, ctx, measurements, exclude)
        if not following:
            continue
        best = following[0]
        if best.cost > 0:
            gain += share * (best.scored_on[0] if best.scored_on is not None else best.gain)
            cost += share * best.cost
        else:
            more_gain, more_cost = _after(child, best, ctx, measurements, exclude | {best.test})
            gain += share * (best.gain + more_gain)
            cost += share * more_cost
    return gain, cost


def _anywhere(test: Test, ctx: Context) -> Position:
    """A cost-blind position for a test: each ``*`` slot drawn uniformly, a distance
    within the procedure's range, an orientation anywhere around the object."""
    lo, hi = procedure_range(test, ctx.knowledge)
    distance, orientation = test.position.distance_in, test.position.orientation_deg
    if distance is None:
        distance = float(ctx.rng.uniform(lo, hi))
    if orientation is None:
        orientation = float(ctx.rng.uniform(0.0, 360.0))
    return Position(distance, orientation)


def _ordered(scored: list[ScoredTest], ctx: Context) -> list[ScoredTest]:
    """Best first: by score, then (cost-blind) at random, or else by cost."""
    if not ctx.criterion.cost_blind_choices:
        return sorted(scored, key=functools.cmp_to_key(lambda a, b: _better(a, b) or _cheaper(a, b)))
    chance = ctx.rng.random(len(scored)).tolist()
    drawn = sorted(zip(scored, chance), key=functools.cmp_to_key(
        lambda a, b: _better(a[0], b[0]) or (-1 if a[1] < b[1] else (1 if a[1] > b[1] else 0))))
    return [s for s, _ in drawn]


def _better(a: ScoredTest, b: ScoredTest) -> int:
    """Order two scored tests by score (within 1e-9 relative is a tie, 0); free tests by
    their gain; tests scored on a shared basis (one procedure application) by their own gain."""
    if math.isinf(a.score) and math.isinf(b.score):
        if not math.isclose(a.gain, b.gain, rel_tol=1e-9, abs_tol=1e-12):
            return -1 if a.gain > b.gain else 1
    elif not math.isclose(a.score, b.score, rel_tol=1e-9, abs_tol=1e-12):
        return -1 if a.score > b.score else 1
    elif a.scored_on is not None and b.scored_on is not None and not math.isclose(
            a.gain, b.gain, rel_tol=1e-9, abs_tol=1e-12):
        return -1 if a.gain > b.gain else 1
    return 0


def _cheaper(a: ScoredTest, b: ScoredTest) -> int:
    """Ties: the nearer, then the cheaper to apply, then the test's name (repeatable)."""
    for x, y in ((a.move_cost, b.move_cost), (a.sense_cost, b.sense_cost)):
        if not math.isclose(x, y, rel_tol=1e-9, abs_tol=1e-9):
            return -1 if x < y else 1
    return -1 if a.test < b.test else (1 if b.test < a.test else 0)

