"""Choosing a test at a node: the tests ranked by score, and for a rollout criterion its
best few ranked again by the expected cost of finishing the object.

:func:`rank` is the choice the session, the grown tree and training make. The score
(gain, cost and the criterion's formula, a lookahead included) is
``learner.choosing.scoring``'s; a ``rollout`` criterion then ranks its best few by
expected cost to the end (learner/choosing/rollout.py, or learner/choosing/rollout_walk.py
for one that follows the session's walk). A rollout finishes each candidate with the
ranking by score and the leaf rule, so it sits between the two: scoring below it, this
module above.
"""

from __future__ import annotations

from learner.choosing import exact_choice, rollout, rollout_walk
from learner.choosing.matrix import Test
from learner.choosing.node import Context, Measurements, Node, ScoredTest
from learner.choosing.scoring import rank_by_score
from learner.position import Position


def rank(node: Node, current: Position, ctx: Context, measurements: Measurements,
         exclude: frozenset[Test] = frozenset()) -> list[ScoredTest]:
    """All usable tests at a node, best first: by the criterion's score
    (:func:`learner.choosing.scoring.rank_by_score`), and for a ``rollout`` criterion its
    best few then by expected cost to the end."""
    ranked = rank_by_score(node, current, ctx, measurements, exclude)
    if ranked and ctx.criterion.exact_search:
        ranked = exact_choice.searched(node, ranked, current, ctx, measurements, exclude)
    elif ranked and ctx.criterion.rollout:
        rolled_out = rollout_walk.rolled_out if ctx.criterion.rollout_follows_walk else rollout.rolled_out
        ranked = rolled_out(node, ranked, current, ctx, measurements, exclude)
    return ranked
