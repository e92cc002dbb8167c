"""Choosing by the exact search where few descriptions are left, the walk rollout above, one step beyond.

The exact search (:mod:`learner.choosing.exact`) prices a test at a node at what it
costs plus the least expected cost below each of its branches: the optimal choice, under
docs/optimum.md's accounting. Its work grows steeply with the descriptions at the node
(the camera's appearance often leaves under ten, a test splits them further), and what
it found serves the session's later decisions. So a criterion with the ``exact_search``
trait (``cs-id3-failure-exact``) chooses by the search where it is cheap enough
(:func:`exact_here`), every test the one-step ranking offers priced exactly (a ``*``
test also at each other fill of its slots the library uses, ``rollout_walk.star_fills``);
above it, at a node of tens of descriptions, by its walk rollout
(learner/choosing/rollout_walk.py), whose estimate follows the session's walk; at a node
of more (:data:`ROLLOUT_ROWS`), where the rollout's walks would take hundreds of
milliseconds, by the one-step ranking alone. A state an earlier decision searched to
the end keeps its best action, which a later decision there takes at once.

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

from learner.choosing.exact import ExactSearch, priced_all
from learner.costs import estimator_generation
from learner.choosing.matrix import Test
from learner.choosing.node import Context, Measurements, Node, ScoredTest
from learner.choosing.rollout_walk import rolled_out, shared, star_fills
from learner.position import Position

EXACT_ROWS = 14
"""The most descriptions at the first node a session chooses at for which the exact
search chooses there (its whole search then serves the session's later decisions)."""
COLD_ROWS = 8
"""The most descriptions at a later node for which a session that has not searched a
node as large yet starts the search there; above it the walk rollout chooses."""
ROLLOUT_ROWS = 50
"""The most descriptions at a node where the exact search does not choose for which the
walk rollout chooses; above it the one-step ranking alone, whose decisions stay fast at
any library size where the rollout's do not. Above the largest node the rollout met in
the paper's conditions, so the rule there is unchanged (docs/optimum.md, "A rule above
the exact search")."""


def searched(node: Node, ranked: list[ScoredTest], current: Position, ctx: Context, measurements: Measurements,
             exclude: frozenset[Test]) -> list[ScoredTest]:
    """``ranked`` (one-step order) reordered by expected total cost: exactly where the
    search is cheap (:func:`exact_here`), by the walk rollout at a node of up to
    :data:`ROLLOUT_ROWS` descriptions, left in its one-step order above."""
    if not exact_here(len(node.rows), ctx):
        if len(node.rows) > ROLLOUT_ROWS:
            return ranked
        return rolled_out(node, ranked, current, ctx, measurements, exclude)
    return shared((ctx.criterion, node, current, frozenset(measurements), exclude),
                  lambda: _searched(node, ranked, current, ctx, measurements, exclude))


def exact_here(rows: int, ctx: Context) -> bool:
    """Whether the exact search chooses at a node of ``rows`` descriptions: at the
    context's first choice up to :data:`EXACT_ROWS`; later up to :data:`COLD_ROWS`, or
    up to the largest node already searched (whose search the later ones re-use).
    Bounded so that a first decision stays within a few hundred milliseconds and a later
    one within tens (bench/bench_optimum.py measures both)."""
    first = "searched_rows" not in ctx.scratch
    largest = ctx.scratch.setdefault("searched_rows", 0)
    assert isinstance(largest, int)
    exact = rows <= COLD_ROWS or rows <= largest or (first and rows <= EXACT_ROWS)
    if exact:
        ctx.scratch["searched_rows"] = max(largest, rows)
    return exact


def _searched(node: Node, ranked: list[ScoredTest], current: Position, ctx: Context, measurements: Measurements,
              exclude: frozenset[Test]) -> list[ScoredTest]:
    search = session_search(ctx)
    here, weights, at = search.node_id(node.rows), node.weights(), search.place(current)
    free, taken = search.free_mask(measurements), search.taken_mask(exclude)
    candidates = [*ranked, *(fill for test in ranked for fill in star_fills(test, current, ctx))]
    solved = search.solved(here, weights, at, free, taken)
    if solved is not None:  # an earlier decision searched this state to the end: its best action is known
        total, column, target = solved
        where = search.positions[target]
        best = next((i for i, t in enumerate(candidates) if ctx.matrix.column[t.test] == column
                     and (t.target == where or t.cost <= 0)), None)
        if best is not None:
            rest = [t for i, t in enumerate(ranked) if i != best]  # for reselection, in one-step order
            return [dataclasses.replace(candidates[best], score=-total, scored_on=(candidates[best].gain, total)),
                    *rest]
    return _ordered(candidates, priced_all(search, here, weights, candidates, at, free, taken))


def session_search(ctx: Context) -> ExactSearch:
    """The exact search this context's decisions share (``ctx.scratch``): what one
    decision searched, the next re-uses, so a session pays for the search below its
    first exact decision once. (A context's library and estimator are fixed; a forked
    session's copy of the estimator prices as the original does.) An estimator whose
    prices changed (its ``generation``: the object moved) gets a search afresh, since the
    old one's subtrees are priced with the old moves."""
    search = ctx.scratch.get("exact")
    generation = estimator_generation(ctx.estimator)
    if not isinstance(search, ExactSearch) or search.matrix is not ctx.matrix \
            or ctx.scratch.get("exact_generation") != generation:
        search = ctx.scratch["exact"] = ExactSearch(ctx.matrix, ctx.estimator, ctx)
        ctx.scratch["exact_generation"] = generation
    return search


def _ordered(candidates: list[ScoredTest], prices: list[tuple[float, bool]]) -> list[ScoredTest]:
    """``candidates`` least price first, an exact price before a bound of the same value
    (ties otherwise in their given order), each scored ``-price``."""
    order = sorted(range(len(candidates)), key=lambda i: (prices[i][0], not prices[i][1]))
    return [dataclasses.replace(candidates[i], score=-prices[i][0], scored_on=(candidates[i].gain, prices[i][0]))
            for i in order]
