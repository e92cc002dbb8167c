"""Choosing by the exact search where few descriptions are left, by the walk rollout above.

The exact search (:mod:`learner.choosing.exact`) prices a test at a node at what it
costs plus the least expected cost below each of its branches: the optimal choice, under
docs/optimum.md's accounting. Its work grows steeply with the descriptions at the node,
but below a root a test has split them: at a node of at most :data:`EXACT_ROWS`
descriptions it takes milliseconds (bench/bench_optimum.py). So a criterion with the
``exact_search`` trait (``cs-id3-failure-exact``) chooses there by the search, every
test the one-step ranking offers priced exactly (a ``*`` test also at each other fill
of its slots the library uses, ``rollout_walk.star_fills``), and above it by its walk
rollout (learner/choosing/rollout_walk.py), whose estimate follows the session's walk.

The search works from the session's state only: the node's rows and how likely each
came this way (``Node.weights``), where the robot stands, which tests its measurements
make free and which were taken on the path or tried at the node. It expects the
session to stop where every row at the node shares a grasp, so the trait goes with
``leaf_every_row``. A candidate that cannot beat the best found so far is priced only
as far as needed to know it (a lower bound, at least the best): the list's head is the
least expected cost; the order of the rest, kept for reselection, is that of their
bounds.
"""

from __future__ import annotations

import dataclasses
import math

from learner.choosing.exact import ExactSearch, priced_all
from learner.choosing.matrix import Test
from learner.choosing.node import Context, Measurements, Node, ScoredTest
from learner.choosing.rollout import rescored
from learner.choosing.rollout_walk import WalkRollout, rolled_out, shared, star_fills
from learner.position import Position

EXACT_ROWS = 10
"""The most descriptions at a node for which the exact search chooses; above it the
walk rollout does (docs/optimum.md, "Exact below, rollout above")."""


SHORTLIST = 6
"""Above :data:`EXACT_ROWS`: how many of the tests least by the walk rollout are rolled
out again with exact tails."""
TAIL_ROWS = 6
"""Above :data:`EXACT_ROWS`, the walk rollout finishes a candidate with the one-step
rule down to nodes of at most this many descriptions and with the exact search below."""


def searched(node: Node, ranked: list[ScoredTest], current: Position, ctx: Context, measurements: Measurements,
             exclude: frozenset[Test]) -> list[ScoredTest]:
    """``ranked`` (one-step order) reordered by expected total cost: exactly at a node
    of at most :data:`EXACT_ROWS` descriptions, by the walk rollout above."""
    decide = _searched if len(node.rows) <= EXACT_ROWS else rolled_out
    return shared((ctx.criterion, node, current, frozenset(measurements), exclude),
                  lambda: decide(node, ranked, current, ctx, measurements, exclude))


class _ExactTails(WalkRollout):
    """The walk rollout, finished exactly at nodes of at most :data:`TAIL_ROWS` rows."""

    def __init__(self, ctx: Context, node: Node) -> None:
        super().__init__(ctx, node)
        self.search = ExactSearch(ctx.matrix, ctx.estimator, ctx)
        self._free: dict[frozenset[tuple[str, Position]], int] = {}

    def finish(self, node: Node, weights: tuple[float, ...], at: Position, measured: frozenset[tuple[str, Position]],
               exclude: frozenset[Test], failed: frozenset[str], depth: int = 0) -> float:
        if len(node.rows) > TAIL_ROWS:
            return super().finish(node, weights, at, measured, exclude, failed, depth)
        search = self.search
        if measured not in self._free:
            self._free[measured] = search.free_mask(dict.fromkeys(measured, math.nan))
        return search.expected(search.node_id(node.rows), weights, search.place(at), self._free[measured],
                               search.taken_mask(exclude))


def _rolled_out(node: Node, ranked: list[ScoredTest], current: Position, ctx: Context, measurements: Measurements,
                exclude: frozenset[Test]) -> list[ScoredTest]:
    """Every test (each also at every fill of its ``*`` slots) rolled out with the
    one-step rule as walked; the :data:`SHORTLIST` least of those rolled out again with
    exact tails."""
    weights = node.weights()
    measured = frozenset(measurements)
    candidates = [*ranked, *(fill for test in ranked for fill in star_fills(test, current, ctx))]
    cheap = WalkRollout(ctx, node)
    rolled = rescored(candidates, lambda test: cheap.after(node, weights, test, measured, exclude, frozenset()),
                      width=len(candidates))
    tails = _ExactTails(ctx, node)
    return rescored(rolled, lambda test: tails.after(node, weights, test, measured, exclude, frozenset()),
                    width=SHORTLIST)


def _searched(node: Node, ranked: list[ScoredTest], current: Position, ctx: Context, measurements: Measurements,
              exclude: frozenset[Test]) -> list[ScoredTest]:
    search = session_search(ctx)
    candidates = [*ranked, *(fill for test in ranked for fill in star_fills(test, current, ctx))]
    totals = priced_all(search, search.node_id(node.rows), node.weights(), candidates, search.place(current),
                        search.free_mask(measurements), search.taken_mask(exclude))
    return _ordered(candidates, totals)


def session_search(ctx: Context) -> ExactSearch:
    """The exact search this context's decisions share (``ctx.scratch``): what one
    decision searched, the next re-uses, so a session pays for the search below its
    first exact decision once. A new one when the library or the estimator changed."""
    search = ctx.scratch.get("exact")
    if not isinstance(search, ExactSearch) or search.matrix is not ctx.matrix or search.estimator is not ctx.estimator:
        search = ctx.scratch["exact"] = ExactSearch(ctx.matrix, ctx.estimator, ctx)
    return search


def _ordered(candidates: list[ScoredTest], totals: list[float]) -> list[ScoredTest]:
    """``candidates`` least total first (ties in their given order), each scored ``-total``."""
    order = sorted(range(len(candidates)), key=lambda i: totals[i])
    return [dataclasses.replace(candidates[i], score=-totals[i], scored_on=(candidates[i].gain, totals[i]))
            for i in order]
