"""Choosing a test at a node: candidates, their gain and cost, and the ranking.

A *test* is a feature at a position (``Width-Degree-1°(24,0)``) or a grasp tried as a
binary feature (``Top-Pinch(6,*)``: success or failure). Candidates come from the
descriptions at the node: the learner can only test what some object was measured on.
Each is scored with the criterion on its gain and its cost *from the current position*;
the ranked list is kept so the executive can reselect the next-best test.

Gains come from ``learner.choosing.gain`` (docs/method.md §3); what a criterion does besides its
formula (cost-blind ties and ``*`` slots, joint gain, lookahead) it declares in its
registry entry, and the ranking here follows it.
"""

from __future__ import annotations

import dataclasses
import functools
import math
from collections.abc import Mapping, Sequence
from dataclasses import dataclass, field

import numpy as np

from learner.choosing.criteria import Criterion
from learner.choosing.gain import Split, joint_gain, partition_columns
from learner.choosing.matrix import DescriptionMatrix, Test
from learner.choosing.partition import Range
from learner.costs import MoveCostEstimator, sensing_cost
from learner.knowledge import Knowledge
from learner.position import Position

_MIN_GAIN = 1e-12
LOOKAHEAD_WIDTH = 8
"""How many of the best tests by one step a lookahead criterion scores again over two:
each costs a ranking per branch, and a test far down the one-step order is rarely the
best over two steps."""
_EPS = 1e-9


@dataclass(frozen=True)
class Node:
    """The descriptions at a tree node: matrix rows, and which of them were *carried*
    there only because they lacked a tested feature (they help score tests but never
    decide a leaf's class)."""

    rows: tuple[int, ...]
    carried: tuple[bool, ...]
    # each row's chance of having come this way, relative to a row measured all along:
    # ``1/k`` for every ``k``-branch test it lacked (the walk forks there); None: all 1
    likelihood: tuple[float, ...] | None = None

    def weights(self) -> tuple[float, ...]:
        """Each row's probability of being the object at hand, given the node."""
        raw = self.likelihood or (1.0,) * len(self.rows)
        total = sum(raw)
        return tuple(w / total for w in raw) if total > 0 else raw

    def weight_array(self) -> np.ndarray | None:
        """:meth:`weights` as an array, for numpy over the node's rows; None when every
        row is alike (all equally likely)."""
        if self.likelihood is None:
            return None
        raw = np.asarray(self.likelihood)
        total = float(raw.sum())
        return raw / total if total > 0 else raw

    @staticmethod
    def root(n: int, exclude: Sequence[int] = ()) -> Node:
        if not len(exclude):
            rows = tuple(range(n))
        else:  # in C: at 100,000 descriptions a grasp's rows are tens of thousands
            rows = tuple(np.setdiff1d(np.arange(n), np.fromiter(exclude, dtype=np.int64, count=len(exclude))).tolist())
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
    # the (gain, cost) the score was computed from when not (gain, cost): a procedure's
    # joint gain, or the two steps of a lookahead
    scored_on: tuple[float, float] | None = None

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


def deciding_index(node: Node) -> np.ndarray:
    """Rows whose class counts at a leaf: the genuine ones, or all when none is."""
    rows = np.asarray(node.rows, dtype=np.int64)
    genuine = rows[~np.asarray(node.carried, dtype=bool)] if len(rows) else rows
    return genuine if len(genuine) else rows


def leaf_classes(node: Node, matrix: DescriptionMatrix) -> list[str]:
    """Grasps of the deciding rows, sorted: exactly one means the node is a leaf
    (read from the matrix's classes, sorted grasp names, so no description is visited)."""
    return [matrix.classes[c] for c in np.unique(matrix.class_of[deciding_index(node)]).tolist()]


def measured_value(test: Test, measurements: Measurements) -> float | None:
    """A value already measured on this object that serves for ``test`` (free to use)."""
    for (feature, at), value in measurements.items():
        if feature == test.feature and test.position.overlaps(at):
            return value
    return None


def procedure_range(test: Test, knowledge: Knowledge) -> tuple[float, float]:
    """The distances (in) the test's procedure works at: its grasp's, or its sensing
    procedure's."""
    return knowledge.grasp(test.procedure).range_in if test.is_grasp else knowledge.procedure_for(test.feature).range_in


def procedure_cost(test: Test, knowledge: Knowledge) -> float:
    """What applying the test costs besides moving: a grasp tried as a feature is its
    time plus the side-effect penalty, a sensing test its procedure's time."""
    return (knowledge.grasp(test.procedure).feature_cost_s if test.is_grasp
            else knowledge.procedure_for(test.feature).time_s)


def target_for(test: Test, current: Position, ctx: Context) -> Position:
    """Where the robot goes for a test: ``*`` slots stay where the robot is, within range."""
    lo, hi = procedure_range(test, ctx.knowledge)
    distance = test.position.distance_in
    if distance is None:
        distance = min(max(current.distance_in if current.distance_in is not None else lo, lo), hi)
    orientation = test.position.orientation_deg
    if orientation is None:
        orientation = current.orientation_deg if current.orientation_deg is not None else 0.0
    return Position(distance, orientation)


def rank(
    node: Node,
    current: Position,
    ctx: Context,
    measurements: Measurements,
    exclude: frozenset[Test] = frozenset(),
) -> list[ScoredTest]:
    """All usable tests at a node, best first.

    A test is usable when it splits the node into two or more branches with positive
    gain (or, when none gains anything, any test that splits); grasp tests only while
    the node holds more than one grasp. Each is scored by the criterion on its gain (the
    joint gain of its procedure application, for a ``joint_gain`` criterion) and its
    cost from ``current``; a ``lookahead`` criterion then rescores the paid ones over two
    steps (of the best :data:`LOOKAHEAD_WIDTH` by one step; the rest follow them), and a
    ``rollout`` one ranks its best few by expected cost to the end (learner/choosing/rollout.py, or
    learner/choosing/rollout_walk.py). A ``grasp_paid_on_failure`` criterion prices a grasp test
    at its failure probability times its cost (``scored_on``). Ties go
    to the nearer, then the cheaper test, or, for a criterion with
    ``cost_blind_choices``, are ordered at random from ``ctx.rng``.
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
    if ctx.criterion.rollout:
        # imported here: the rollout finishes by the leaf rule (decision_tree), built on this module
        if ctx.criterion.rollout_follows_walk:
            from learner.choosing.rollout_walk import rolled_out
        else:
            from learner.choosing.rollout import rolled_out
        ranked = rolled_out(node, ranked, current, ctx, measurements, exclude)
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
    ``first``'s position, ranked without lookahead; free tests on the way (the siblings
    ``first``'s procedure yielded) are followed, their gain counted at no cost. A leaf
    adds nothing. ``first`` counts its own gain here, not its application's joint gain:
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
        following = rank(child, taken.target, ctx, measurements, exclude)
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


def yielded(test: ScoredTest, ctx: Context) -> dict[tuple[str, Position], float]:
    """What applying ``test`` makes known, without the values (NaN): every feature of its
    procedure at its position, so the siblings of the tested feature come free after it."""
    if test.test.is_grasp:
        return {}
    proc = ctx.knowledge.procedure_for(test.test.feature)
    return {(f.name, test.target): math.nan for f in proc.features}


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


def split(node: Node, scored: ScoredTest, matrix: DescriptionMatrix) -> list[Node]:
    """The node of each branch: rows in its range, plus every row lacking the value
    (carried, so it does not decide a leaf, and ``1/k`` as likely: ``Node.likelihood``).
    A value within two ranges goes to the first; rows keep the node's order."""
    k = len(scored.ranges)
    rows = np.asarray(node.rows, dtype=np.int64)
    carried = np.asarray(node.carried, dtype=bool)
    likely = np.ones(len(rows)) if node.likelihood is None else np.asarray(node.likelihood, dtype=float)
    values = matrix.values[rows, matrix.column[scored.test]] if len(rows) else np.zeros(0)
    missing = np.isnan(values)
    taken = missing.copy()
    out = []
    for lo, hi in scored.ranges:
        inside = ~taken & (values >= lo - _EPS) & (values <= hi + _EPS)
        taken |= inside
        here = inside | missing
        weights = np.where(missing, likely / k, likely)[here]
        out.append(Node(tuple(rows[here].tolist()), tuple((carried | missing)[here].tolist()),
                        None if bool((weights == 1.0).all()) else tuple(weights.tolist())))
    return out
