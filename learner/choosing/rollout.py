"""A rollout lookahead: score a test by the expected cost of finishing with the one-step rule.

A greedy ratio such as ``I^2 / C`` looks one test ahead; the optimum (learner/optimum.py)
looks all the way. A rollout sits between them and costs far less than the search: for
each of the :data:`ROLLOUT_WIDTH` best tests by the one-step rule it computes the test's
cost plus the expected cost, over its branches, of finishing the object *with the
one-step rule itself*, noise-free, and ranks the candidates by that total. The greedy
test is among the candidates, so on its own estimate the rollout is never worse than the
rule it starts from; re-planned at every node, it is the classic rollout policy
(Bertsekas, Tsitsiklis & Wu 1997).

The estimate uses the accounting of docs/optimum.md as far as the learner sees it:

- every row at a node is equally likely (the learner's view: a carried row counts as
  one like the others); a row lacking the tested value follows each branch with ``1/k``;
- a test costs its move and its procedure's time, once; its procedure's siblings at its
  position are free after it (``node.yielded``);
- a grasp tried as a feature is paid (move plus ``feature_cost_s``) only when it fails;
  when it holds, the object's own grasp has been executed and nothing more is counted;
- at a leaf (or the first option of an ambiguous one, as the session takes it) the
  grasp is executed: free when right; when wrong, a failed attempt (move plus
  ``feature_cost_s``), after which the rows of other grasps go on from the grasp's
  position, as a fresh node with what was measured still free. This is where the
  estimate simplifies: the session rebuilds its tree from the root instead, re-using the
  measured values for free, which reaches the same rows by free tests in the common case.
  A wrong No-Grab (which the finger sensor cannot confirm) is not counted further: the
  object is left behind.
"""

from __future__ import annotations

import dataclasses
import math
from collections.abc import Callable

import numpy as np

from learner.choosing.leaf import grasp_options, leaf_at
from learner.choosing.matrix import Test
from learner.choosing.node import Context, Measurements, Node, ScoredTest, split, yielded
from learner.choosing.scoring import rank_by_score
from learner.position import Position

ROLLOUT_WIDTH = 8
"""How many of the best tests by one step are rolled out: each costs a run of the greedy
rule over its whole subtree, and rolling out every test changed no shipped-library cell
of bench/bench_optimum.py (4 instead of 8 added 0.001-0.019 to the ratios there)."""
_EPS = 1e-9

_Key = tuple[Node, Position, frozenset[tuple[str, Position]], frozenset[Test]]


def rolled_out(node: Node, ranked: list[ScoredTest], current: Position, ctx: Context, measurements: Measurements,
               exclude: frozenset[Test]) -> list[ScoredTest]:
    """``ranked`` (one-step order, from ``current``) with its best few rescored by
    their expected total cost (:func:`rescored`)."""
    rollout = _Rollout(ctx)
    measured = frozenset(measurements)
    return rescored(ranked, lambda test: rollout.after(node, test, measured, exclude))


def rescored(ranked: list[ScoredTest], total_of: Callable[[ScoredTest], float], *, width: int = ROLLOUT_WIDTH,
             grasps_too: bool = False) -> list[ScoredTest]:
    """The best ``width`` of ``ranked`` (and, with ``grasps_too``, every grasp test:
    grasping now weighed against testing further) rescored by their expected total cost
    ``total_of(test)`` (score ``-total``, ``scored_on`` = (gain, total)), least first;
    the rest follow in their one-step order."""
    chosen = shortlisted(ranked, width, grasps_too=grasps_too)
    shortlist = []
    for test in chosen:
        total = total_of(test)
        shortlist.append(dataclasses.replace(test, score=-total, scored_on=(test.gain, total)))
    shortlist.sort(key=lambda s: -s.score)  # stable: ties keep the one-step order
    taken = {id(t) for t in chosen}
    return shortlist + [t for t in ranked if id(t) not in taken]


def shortlisted(ranked: list[ScoredTest], width: int, *, grasps_too: bool = False) -> list[ScoredTest]:
    """The ``width`` best of ``ranked`` by one step, with ``grasps_too`` followed by every
    grasp test below them: a one-step ratio can rank a grasp tried as a feature low even
    where trying it now is the cheapest way to finish (its gain is small, its failure
    cost far away)."""
    return ranked[:width] + ([t for t in ranked[width:] if t.test.is_grasp] if grasps_too else [])


def one_step(ctx: Context) -> Context:
    """``ctx`` with its criterion's rollout off: the one-step rule a rollout finishes with."""
    return dataclasses.replace(ctx, criterion=dataclasses.replace(ctx.criterion, rollout=False))


def finishing_cost(node: Node, current: Position, ctx: Context, measurements: Measurements,
                   exclude: frozenset[Test] = frozenset()) -> float:
    """Expected seconds of finishing the object at ``node`` from ``current`` with
    ``ctx``'s one-step rule (the module's accounting)."""
    return _Rollout(ctx).finish(node, current, frozenset(measurements), exclude)


class _Rollout:
    """The greedy rule's expected cost, memoised per (node, position, measured, excluded)
    for one decision: candidates' subtrees share many nodes (a failed grasp's rest, a
    free sibling taken in either order)."""

    def __init__(self, ctx: Context) -> None:
        self.ctx = one_step(ctx)
        self.memo: dict[_Key, float] = {}

    def finish(self, node: Node, at: Position, measured: frozenset[tuple[str, Position]],
               exclude: frozenset[Test]) -> float:
        key = (node, at, measured, exclude)
        if key not in self.memo:
            self.memo[key] = self._finish(node, at, measured, exclude)
        return self.memo[key]

    def _finish(self, node: Node, at: Position, measured: frozenset[tuple[str, Position]],
                exclude: frozenset[Test]) -> float:
        leaf = leaf_at(node, at, self.ctx)
        if leaf is None:
            ranked = rank_by_score(node, at, self.ctx, dict.fromkeys(measured, math.nan), exclude)
            if ranked:
                return self.after(node, ranked[0], measured, exclude)
            leaf = grasp_options(node, at, self.ctx)[0]  # ambiguous: its first option, as the session
        matrix = self.ctx.matrix
        rest = tuple(r for r in node.rows if matrix.descriptions[r].grasp != leaf.grasp)
        grasp = self.ctx.knowledge.grasp(leaf.grasp)
        if not rest or not grasp.verifiable:
            return 0.0  # right for every row; or a wrong No-Grab leaves the object behind
        wrong = len(rest) / len(node.rows)
        again = self.finish(Node(rest, (False,) * len(rest)), leaf.position, measured, frozenset())
        return wrong * (leaf.move_cost + grasp.feature_cost_s + again)

    def after(self, node: Node, test: ScoredTest, measured: frozenset[tuple[str, Position]],
              exclude: frozenset[Test]) -> float:
        """``test``'s expected cost at ``node`` plus, per branch, finishing greedily."""
        shares = branch_shares(node, test, self.ctx)
        held = [test.test.is_grasp and lo >= 1.0 for lo, _ in test.ranges]
        paid = sum(s for s, h in zip(shares, held) if not h)  # a grasp that holds is not counted
        total = paid * test.cost
        now_measured = measured | frozenset(yielded(test, self.ctx))
        now_excluded = exclude | {test.test}
        for child, share, h in zip(split(node, test, self.ctx.matrix), shares, held):
            if share > _EPS and not h:
                total += share * self.finish(child, test.target, now_measured, now_excluded)
        return total


def branch_shares(node: Node, test: ScoredTest, ctx: Context) -> list[float]:
    """Each branch's probability at ``node``: rows equally likely, a row lacking the
    value spread evenly over the ``k`` branches (as the walk of learner/optimum.py forks)."""
    values = ctx.matrix.values[list(node.rows), ctx.matrix.column[test.test]]
    known = values[~np.isnan(values)]
    spread = (len(values) - len(known)) / len(test.ranges)
    counts = [float(np.count_nonzero((known >= lo - _EPS) & (known <= hi + _EPS))) + spread for lo, hi in test.ranges]
    return [c / len(values) for c in counts]
