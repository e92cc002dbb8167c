"""A node of the tree being grown, and a test priced at it: what every chooser passes on.

The ranking by score (``learner.choosing.scoring``), the rollouts that look further
(``learner.choosing.rollout``, ``learner.choosing.rollout_walk``), the leaf rule
(``learner.choosing.leaf``) and the session share these values: the descriptions at a
node (:class:`Node`), a test priced from where the robot stands (:class:`ScoredTest`),
what scoring needs besides the node (:class:`Context`), and the few rules on them (the
rows that decide a leaf, where the robot goes for a test, what a test makes known, the
node of each branch). They sit below every chooser, so that a rollout finishes by the
ranking and the leaf rule, and the ranking rolls out, without an import circle.
"""

from __future__ import annotations

import math
from collections.abc import Mapping, Sequence
from dataclasses import dataclass, field

import numpy as np

from learner.choosing.criteria import Criterion
from learner.choosing.matrix import DescriptionMatrix, Test
from learner.choosing.partition import Range
from learner.costs import MoveCostEstimator
from learner.knowledge import Knowledge
from learner.position import Position

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


class Scratch(dict[str, object]):
    """Work a chooser keeps from one decision to the next of the same context (the exact
    search's memo: learner/choosing/exact_choice.py), valid while the context's library
    and move costs are. A session forked by a copy (``optimum.policy_walk``) shares it:
    what it holds depends on the state searched, never on the object at hand."""

    def __deepcopy__(self, memo: dict[int, object]) -> Scratch:
        return self


@dataclass(frozen=True)
class Context:
    """What scoring needs besides the node: the library, the criterion, the move costs,
    a seeded generator for the choices a criterion leaves to chance (a cost-blind
    criterion breaks ties at random), so a run is repeatable from its seed, and the
    :class:`Scratch` its choosers keep between decisions."""

    matrix: DescriptionMatrix
    criterion: Criterion
    estimator: MoveCostEstimator
    rng: np.random.Generator = field(default_factory=lambda: np.random.default_rng(0), compare=False)
    scratch: Scratch = field(default_factory=Scratch, compare=False, repr=False)

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


def yielded(test: ScoredTest, ctx: Context) -> dict[tuple[str, Position], float]:
    """What applying ``test`` makes known, without the values (NaN): every feature of its
    procedure at its position, so the siblings of the tested feature come free after it."""
    if test.test.is_grasp:
        return {}
    proc = ctx.knowledge.procedure_for(test.test.feature)
    return {(f.name, test.target): math.nan for f in proc.features}


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
