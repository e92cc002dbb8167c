"""The exact search made faster (issue 32) finds what it found before.

Its nodes' facts and branchings are worked out once per matrix and shared by every
search over it, a child's from its parent's useful columns only, and a node's bound is
priced from per-position tables; none of it may change a price. Compared with the
search as it was (tests/learner/reference_exact.py) on random small libraries: the same
optimum, and at the root the same candidates in the same order at the same prices (the
head is the choice; the rest is the reselection order)."""

from __future__ import annotations

import gc
import weakref

from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from learner.choosing import exact
from learner.choosing.criteria import criterion
from learner.choosing.node import Context, Node
from learner.choosing.rollout_walk import star_fills
from learner.choosing.selection import rank
from learner.costs import ModelMoveCost
from learner.knowledge import MoveModel
from learner.position import Position
from tests.learner import reference_exact
from tests.learner.fixtures import P
from tests.learner.test_optimum import SLOTS, STARTS, d, libraries, matrix


def _root_prices(module, m, est, start: Position) -> tuple[float, list[tuple[float, bool]]]:  # noqa: ANN001
    """(the optimum from ``start``, every root candidate's price as the session's first
    decision asks for them) by the search of ``module``."""
    ctx = Context(m, criterion("cs-id3-failure-exact"), est)
    root = Node.root(len(m.descriptions))
    ranked = rank(root, start, Context(m, criterion("cs-id3-failure"), est), {})
    candidates = [*ranked, *(fill for test in ranked for fill in star_fills(test, start, ctx))]
    search = module.ExactSearch(m, est, ctx)
    here, at = search.node_id(root.rows), search.place(start)
    prices = module.priced_all(search, here, root.weights(), candidates, at, 0, 0)
    alone = module.ExactSearch(m, est, ctx)
    n = len(m.descriptions)
    best = alone.expected(alone.node_id(root.rows), (1.0 / n,) * n, alone.place(start), 0, 0)
    return best, prices


@settings(max_examples=60, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(libraries(SLOTS), st.sampled_from(STARTS), st.booleans(), st.booleans())
def test_the_fast_search_prices_as_the_reference_does(library: list, start: Position, grasps: bool,
                                                      shared: bool) -> None:
    move = MoveModel(2.0, 0.1, 0.0)
    m, est = matrix(library, grasps, move), ModelMoveCost(move)
    if shared:  # a table another search already filled, from another start
        _root_prices(exact, m, est, P(40, 180))
    else:
        exact.forget_nodes(m)
    assert _root_prices(exact, m, est, start) == _root_prices(reference_exact, m, est, start)


def test_searches_over_one_matrix_share_its_nodes_and_let_it_go() -> None:
    lib = [d("a", "A", ("W", P(20, 0), 10), ("H", P(6, 0), 3)),
           d("b", "B", ("W", P(20, 0), 10), ("H", P(6, 0), 5)),
           d("c", "C", ("W", P(20, 0), 30), ("H", P(6, 0), 5))]
    m, est = matrix(lib), ModelMoveCost(MoveModel(2.0, 0.0, 0.0))
    first = exact.ExactSearch(m, est, Context(m, criterion("cs-id3-failure-exact"), est))
    first.expected(first.node_id((0, 1, 2)), (1 / 3,) * 3, first.place(P(20, 0)), 0, 0)
    second = exact.ExactSearch(m, est, Context(m, criterion("cs-id3-failure-exact"), est))
    assert second.table is first.table and len(second.rows) > 1  # the nodes the first searched
    # the table is the matrix's memo: it does not keep a dropped library alive
    gone = weakref.ref(m)
    del m, first, second
    gc.collect()
    assert gone() is None


def test_a_table_past_its_size_is_started_anew(monkeypatch) -> None:  # noqa: ANN001
    # every session adds the positions the robot stood at: a table grown past
    # TABLE_ENTRIES is replaced at the next search, a search under way keeps its own
    lib = [d("a", "A", ("W", P(20, 0), 10)), d("b", "B", ("W", P(20, 0), 30))]
    m, est = matrix(lib), ModelMoveCost(MoveModel(2.0, 0.0, 0.0))
    ctx = Context(m, criterion("cs-id3-failure-exact"), est)
    monkeypatch.setattr(exact, "TABLE_ENTRIES", 3)
    first = exact.ExactSearch(m, est, ctx)
    for k in range(3):
        first.place(P(6 + k, 0))
    assert exact.ExactSearch(m, est, ctx).table is first.table  # three positions: not past it yet
    first.place(P(30, 0))
    later = exact.ExactSearch(m, est, ctx)
    assert later.table is not first.table and later.table.positions == []
    assert first.expected(first.node_id((0, 1)), (0.5, 0.5), first.place(P(20, 0)), 0, 0) == 10.0  # W(20,0) alone
