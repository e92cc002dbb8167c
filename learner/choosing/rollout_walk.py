"""A rollout whose estimate follows the walk: rows weighted, a wrong grasp rebuilds from the root.

The rollout of learner/choosing/rollout.py estimates what finishing with the one-step rule costs
from the learner's view of a node: every row counts as one, and after a wrong leaf grasp
the rows of other grasps go on from that node. The session the estimate stands for
(``RecognitionSession``, walked by learner/optimum.py) differs in two ways, and where
they matter the least estimate is not the least cost:

- a row carried down a test it lacks follows each of the ``k`` branches with ``1/k``
  (the walk forks there), so deeper down it is less likely than the rows that were
  measured there; its weight here is multiplied by ``1/k`` at every such test;
- after a wrong grasp the session rebuilds its tree from the root without that grasp's
  descriptions, the measured values re-used for free, and its choices there are made
  over every description left, also those the object's values already ruled out. Here
  too: the rebuilt root holds every row of a grasp present where the decision is made
  and not yet failed, those already ruled out at weight 0 (they steer the choices, they
  cost nothing).

The decision's node starts from what ``Node.likelihood`` records (a session's nodes come
by ``node.split``, which keeps it). What stays approximate: a row lacking a value
re-used after a rebuild is spread over the branches again rather than following its
first fork. The accounting is otherwise learner/choosing/rollout.py's: a test is paid once, its
procedure's siblings are then free, a grasp tried as a feature is paid only when it
fails, a wrong leaf grasp costs its move and ``feature_cost_s``; a wrong No-Grab, which
leaves the object behind, is priced at :data:`LEFT_BEHIND_S`.

A ``rollout_searches`` criterion (``cs-id3-failure-search``) looks wider and deeper. At
the decision it rolls out every test and every grasp test, a ``*`` test also at each
other fill of its slots that the library uses (:func:`star_fills`); the
:data:`SEARCH_SHORTLIST` least of those are then searched: at each of the next
:data:`SEARCH_DEPTH` nodes below them the least expected cost over the
:data:`SEARCH_WIDTH` best tests by one step and every grasp test (grasping now against
testing further; the session's own walk, leaf rule and rebuilds included), the one-step
rule below that. Its work is bounded: at most :data:`SEARCH_BUDGET` searched nodes per
decision, the rest finished by the one-step rule as a plain rollout.
"""

from __future__ import annotations

import contextlib
import dataclasses
import math
from collections.abc import Callable, Iterator

from learner.choosing.leaf import grasp_options, leaf_at
from learner.choosing.matrix import DescriptionMatrix, Test
from learner.choosing.node import Context, Measurements, Node, ScoredTest, procedure_range, split, yielded
from learner.choosing.rollout import one_step, rescored, shortlisted
from learner.choosing.scoring import rank_by_score
from learner.costs import sensing_cost
from learner.position import Position

_EPS = 1e-9
LEFT_BEHIND_S = 5400.0
"""What an object left behind by a wrong No-Grab is priced at: the walk stops charging
there, but the object was never grasped, and a rollout that counted it as free would
steer towards leaving objects behind. 1.5 h, what the paper reports measuring every
feature of an object costs: far above any route that grasps it."""

SEARCH_DEPTH = 3
"""How many nodes below a candidate test the search chooses by expected cost before the
one-step rule takes over (docs/optimum.md, "A search of the walk")."""
SEARCH_WIDTH = 4
"""How many of a searched node's best tests by one step are tried there."""
SEARCH_ROOT_WIDTH = 64
"""How many of the decision's best tests by one step are rolled out (with every grasp
test, and each at every fill of its ``*`` slots): in practice all of them."""
SEARCH_SHORTLIST = 6
"""How many of those, least by the rollout, are then searched."""
SEARCH_BUDGET = 400
"""Searched nodes per decision at most (each ranks its tests once and tries
:data:`SEARCH_WIDTH` of them); beyond it nodes are finished by the one-step rule, so a
decision's work stays bounded however large the library (bench/bench_optimum.py)."""

Weights = tuple[float, ...]
_Measured = frozenset[tuple[str, Position]]


_shared: list[dict[tuple[object, ...], list[ScoredTest]]] = []


@contextlib.contextmanager
def shared_decisions() -> Iterator[None]:
    """Within it, a decision already taken (same criterion, node, position, measured
    features and excluded tests) is answered again from memory: for a caller that walks
    many sessions over one matrix and one estimator whose costs do not change
    (``optimum.policy_walk`` starts one per description, all from the same root), where a
    searched decision would otherwise be worked out once per object."""
    _shared.append({})
    try:
        yield
    finally:
        _shared.pop()


def rolled_out(node: Node, ranked: list[ScoredTest], current: Position, ctx: Context, measurements: Measurements,
               exclude: frozenset[Test]) -> list[ScoredTest]:
    """``ranked`` with its best few rescored by the walk's expected total cost
    (:func:`learner.choosing.rollout.rescored`)."""
    return shared((ctx.criterion, node, current, frozenset(measurements), exclude),
                  lambda: _rolled_out(node, ranked, current, ctx, measurements, exclude))


def shared(key: tuple[object, ...], decide: Callable[[], list[ScoredTest]]) -> list[ScoredTest]:
    """``decide()``, answered from memory within :func:`shared_decisions` when a decision
    with the same ``key`` (criterion, node, position, measured, excluded) was taken."""
    if not _shared:
        return decide()
    if key not in _shared[-1]:
        _shared[-1][key] = decide()
    return list(_shared[-1][key])


def _rolled_out(node: Node, ranked: list[ScoredTest], current: Position, ctx: Context, measurements: Measurements,
                exclude: frozenset[Test]) -> list[ScoredTest]:
    rollout = WalkRollout(ctx, node)
    weights = node.weights()
    measured = frozenset(measurements)
    if not rollout.depth:
        return rescored(ranked, lambda test: rollout.after(node, weights, test, measured, exclude, frozenset()))
    # every test and grasp, also at the other fills of its * slots, rolled out; the best
    # few of those then searched
    candidates = [*shortlisted(ranked, SEARCH_ROOT_WIDTH, grasps_too=True),
                  *(fill for test in ranked[:SEARCH_ROOT_WIDTH] for fill in star_fills(test, current, ctx))]
    rolled = rescored(candidates, lambda test: rollout.after(node, weights, test, measured, exclude, frozenset()),
                      width=len(candidates))
    return rescored(rolled, lambda test: rollout.after(node, weights, test, measured, exclude, frozenset(),
                                                       rollout.depth), width=SEARCH_SHORTLIST)


def star_fills(test: ScoredTest, current: Position, ctx: Context) -> list[ScoredTest]:
    """``test`` made elsewhere than where the learner fills its ``*`` slots (where the
    robot is, ``node.target_for``): at each other value the library uses for the
    slot within the procedure's range, priced from ``current``. Where a ``*`` column is
    made decides which concrete siblings come free after it (docs/optimum.md)."""
    slot = test.test.position
    if test.cost <= 0 or (slot.distance_in is not None and slot.orientation_deg is not None):
        return []
    lo, hi = procedure_range(test.test, ctx.knowledge)
    used = _used_positions(ctx.matrix)
    distances = ([slot.distance_in] if slot.distance_in is not None
                 else sorted({p.distance_in for p in used if lo - _EPS <= p.distance_in <= hi + _EPS}))
    orientations = ([slot.orientation_deg] if slot.orientation_deg is not None
                    else sorted({p.orientation_deg for p in used}))
    fills = []
    for target in (Position(d, o) for d in distances for o in orientations):
        move = (ctx.estimator.move_cost(current, target) if test.test.is_grasp
                else sensing_cost(ctx.estimator, current, target))
        if target != test.target and math.isfinite(move):
            fills.append(dataclasses.replace(test, target=target, move_cost=move))
    return fills


def _used_positions(matrix: DescriptionMatrix) -> frozenset[Position]:
    """The concrete positions the library's tests name (``*`` slots left out)."""
    return frozenset(t.position for t in matrix.tests
                     if t.position.distance_in is not None and t.position.orientation_deg is not None)


def walk_finishing_cost(node: Node, current: Position, ctx: Context, measurements: Measurements,
                        exclude: frozenset[Test] = frozenset()) -> float:
    """Expected seconds of finishing the object at ``node`` from ``current`` with
    ``ctx``'s one-step rule, as the session would walk it (the module's accounting)."""
    return WalkRollout(ctx, node).finish(node, node.weights(), current, frozenset(measurements), exclude, frozenset())


class WalkRollout:
    """The one-step rule's expected cost as the session would walk it (searched over the
    first :attr:`depth` nodes for a ``rollout_searches`` criterion), memoised per (node,
    weights, position, measured, excluded, failed grasps, depth left) for one decision."""

    def __init__(self, ctx: Context, decision_node: Node) -> None:
        self.depth = SEARCH_DEPTH if ctx.criterion.rollout_searches else 0
        self.searched = 0  # nodes searched so far in this decision (at most SEARCH_BUDGET)
        self.ctx = one_step(ctx)
        matrix = ctx.matrix
        grasps = {matrix.descriptions[r].grasp for r in decision_node.rows}
        self.universe = tuple(r for r, d in enumerate(matrix.descriptions) if d.grasp in grasps)
        self.memo: dict[tuple[object, ...], float] = {}

    def finish(self, node: Node, weights: Weights, at: Position, measured: _Measured, exclude: frozenset[Test],
               failed: frozenset[str], depth: int = 0) -> float:
        """Expected seconds of finishing from ``node`` (its rows' probabilities
        ``weights``, summing to 1) with the one-step rule, searched ``depth`` nodes deep."""
        key = (node, tuple(round(w, 12) for w in weights), at, measured, exclude, failed, depth)
        if key not in self.memo:
            self.memo[key] = self._finish(node, weights, at, measured, exclude, failed, depth)
        return self.memo[key]

    def _finish(self, node: Node, weights: Weights, at: Position, measured: _Measured, exclude: frozenset[Test],
                failed: frozenset[str], depth: int) -> float:
        leaf = leaf_at(node, at, self.ctx)
        if leaf is None:
            ranked = rank_by_score(node, at, self.ctx, dict.fromkeys(measured, math.nan), exclude)
            if ranked and depth > 0 and self.searched < SEARCH_BUDGET:
                self.searched += 1
                return min(self.after(node, weights, test, measured, exclude, failed, depth - 1)
                           for test in shortlisted(ranked, SEARCH_WIDTH, grasps_too=True))
            if ranked:
                return self.after(node, weights, ranked[0], measured, exclude, failed)
            leaf = grasp_options(node, at, self.ctx)[0]  # ambiguous: its first option, as the session
        descriptions = self.ctx.matrix.descriptions
        wrong = sum(w for r, w in zip(node.rows, weights) if descriptions[r].grasp != leaf.grasp)
        grasp = self.ctx.knowledge.grasp(leaf.grasp)
        if wrong <= _EPS:
            return 0.0  # right for every likely row
        if not grasp.verifiable:
            return wrong * LEFT_BEHIND_S  # a wrong No-Grab leaves the object behind
        # the session rebuilds from the root without the failed grasp, keeping what was measured
        now_failed = failed | {leaf.grasp}
        rows = tuple(r for r in self.universe if descriptions[r].grasp not in now_failed)
        if not rows:
            return wrong * (leaf.move_cost + grasp.feature_cost_s)
        likely = {r: w / wrong for r, w in zip(node.rows, weights) if descriptions[r].grasp != leaf.grasp}
        root = Node(rows, (False,) * len(rows))
        again = self.finish(root, tuple(likely.get(r, 0.0) for r in rows), leaf.position, measured, frozenset(),
                            now_failed, depth)
        return wrong * (leaf.move_cost + grasp.feature_cost_s + again)

    def after(self, node: Node, weights: Weights, test: ScoredTest, measured: _Measured, exclude: frozenset[Test],
              failed: frozenset[str], depth: int = 0) -> float:
        """``test``'s expected cost at ``node`` plus, per branch, finishing (searched
        ``depth`` nodes deep, then greedily)."""
        branches = weighted_split(node, weights, test, self.ctx)
        held = [test.test.is_grasp and lo >= 1.0 for lo, _ in test.ranges]
        paid = sum(mass for (_, mass, _), h in zip(branches, held) if not h)  # a grasp that holds is not counted
        total = paid * test.cost
        if test.cost > 0:
            now_measured = measured | frozenset(yielded(test, self.ctx))
        else:  # a free re-use records just that feature where the robot stands, as the session does
            now_measured = measured | {(test.test.feature, test.target)}
        now_excluded = exclude | {test.test}
        for (child, mass, child_weights), h in zip(branches, held):
            if mass > _EPS and not h:
                total += mass * self.finish(child, child_weights, test.target, now_measured, now_excluded, failed,
                                            depth)
        return total


def weighted_split(node: Node, weights: Weights, test: ScoredTest,
                   ctx: Context) -> list[tuple[Node, float, Weights]]:
    """Each branch of ``test`` at ``node``: its node (``learner.choosing.node.split``), its
    probability, and its rows' probabilities given the branch. A row lacking the value
    goes down each of the ``k`` branches with ``1/k`` of its weight."""
    matrix = ctx.matrix
    column = matrix.column[test.test]
    own = dict(zip(node.rows, weights))
    k = len(test.ranges)
    out = []
    for child in split(node, test, matrix):
        raw = [own[r] / k if math.isnan(matrix.values[r, column]) else own[r] for r in child.rows]
        mass = sum(raw)
        out.append((child, mass, tuple(w / mass for w in raw) if mass > _EPS else tuple(raw)))
    return out
