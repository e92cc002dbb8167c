"""The optimum's lower bound prices a grasp tried as a feature as its actions do: paid
only when it fails. Priced in full, the bound overstated a node's cost, the search pruned
the best action there, and a walk of ``cs-id3-failure-search-every-row`` came out below
the "optimum" (found by test_optimum.py's property)."""

from __future__ import annotations

import pytest

from learner.choosing.criteria import criterion
from learner.costs import ModelMoveCost
from learner.knowledge import MoveModel
from learner.optimum import optimal_cost, policy_walk
from tests.learner.fixtures import ANY, P
from tests.learner.test_optimum import d, matrix


def test_a_grasp_tried_as_a_feature_is_bounded_by_its_failure_share() -> None:
    # From (16,90), 2 s/in and 0.1 s/deg; test_optimum.py's knowledge (Sweep 10 s, grasps
    # A and B 90 s when they fail). Sweep W at (12,90): 8 + 10 = 18 s; it splits o1 (10) |
    # o2 (12) | o4 (30); o0 and o3 lack W and follow each branch with 1/3 (weight 1/15
    # each there, against 1/5 for the measured row).
    # W=10: o1, o0, o3 are all A: done. W=12 (o2 B) and W=30 (o4 B), mass 1/3 each: try B
    # as a feature, B(6,*) filled at (6,90): 12 + 90 = 102 s, paid when it fails, for o0
    # and o3: 2/15 x 102 = 13.6 s each branch. Total 18 + 13.6 + 13.6 = 45.2 s.
    # The bound that priced B(6,*) in full (102 s) or executed B at o2's own place (6,0)
    # (0.4 x (21 + 90) = 44.4 s against 0.4 x 102 = 40.8 s) pruned that action: 45.73 s.
    library = [d("o0", "A", ("H", P(6, 0), 1)),
               d("o1", "A", ("H", P(6, 0), 1), ("H", P(6, 90), 1), ("H", P(6, ANY), 1), ("W", P(ANY, 90), 10)),
               d("o2", "B", ("H", P(6, 0), 1), ("H", P(6, 90), 1), ("H", P(6, ANY), 1), ("W", P(ANY, 90), 12)),
               d("o3", "A", ("H", P(6, 0), 1)),
               d("o4", "B", ("H", P(6, 0), 1), ("H", P(6, 90), 1), ("H", P(6, ANY), 1), ("W", P(12, 90), 30),
                 at=P(6, ANY))]
    move = MoveModel(2.0, 0.1, 0.0)
    m, est = matrix(library, True, move), ModelMoveCost(move)
    walk = policy_walk(m, criterion("cs-id3-failure-search-every-row"), est, P(16, 90))
    assert [o.cost_s for o in walk.outcomes] == pytest.approx([86, 18, 18, 86, 18])
    assert walk.expected_cost == pytest.approx(45.2)
    assert optimal_cost(m, est, P(16, 90)) == pytest.approx(45.2)
