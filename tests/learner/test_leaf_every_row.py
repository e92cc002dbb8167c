"""The ``leaf_every_row`` trait: a node is a leaf only when every description at it,
carried ones included, shares one grasp (``leaf.leaf_at``).

The hand-worked library uses tests/learner/test_optimum.py's knowledge: Scan 40 s at
6 in yields H and D; grasps A and B cost 90 s when they fail; from (6,0), with no
grasp tried as a feature (``grasps=False``), every test at 6 in costs its time only.
"""

from __future__ import annotations

import dataclasses

import pytest

from executive.defaults import EXAMPLE_LIBRARY, KNOWLEDGE
from robot_profile import load_knowledge
from learner.choosing.criteria import CRITERIA, criterion, with_walk_search
from learner.choosing.leaf import leaf_at
from learner.choosing.matrix import DescriptionMatrix
from learner.choosing.node import Context, Node
from learner.costs import ModelMoveCost
from learner.library.format import read_library_json
from learner.library.synthetic import synthetic_library
from learner.optimum import optimal_cost, policy_walk
from learner.position import Position
from tests.learner.fixtures import P
from tests.learner.test_optimum import EST, d, matrix


def _a_carried_row_of_another_grasp() -> list:
    """o1 lacks H(6,0); o2 (grasp B) has H = 1, o0 (grasp A) H = 3; D(6,0) tells o1 from o2."""
    return [d("o0", "A", ("D", P(6, 0), 3), ("H", P(6, 0), 3)),
            d("o1", "A", ("D", P(6, 0), 1), ("W", P(20, 0), 1)),
            d("o2", "B", ("D", P(6, 0), 3), ("H", P(6, 0), 1))]


def test_the_old_leaf_rule_grasps_blind_where_the_new_one_tests_first() -> None:
    # I^2/C makes the Scan's H(6,0) first (40 s; D(6,0) comes free). Its H=1 branch holds
    # o2 (B) and o1, carried (it lacks H; as the object at hand it goes down each branch
    # with 1/2).
    # Old rule: only o2 decides, a B leaf, wrong for o1's half: o1 pays 40 + 1/2 x 90 =
    #   85 s, o0 and o2 40 s: (40 + 85 + 40) / 3 = 55 s.
    # New rule: o1 (A) and o2 (B) are not one grasp, so the node tests on: the free D(6,0)
    #   tells them apart (1 against 3): every object 40 s, 40 s.
    # (The optimum executes A blind at once: wrong for o2 only, 1/3 x 90 = 30 s.)
    m = matrix(_a_carried_row_of_another_grasp(), grasps=False)
    old = criterion("cs-id3")
    new = dataclasses.replace(old, leaf_every_row=True)
    h_is_1 = Node((1, 2), (True, False))  # o1 carried, o2 measured
    leaf = leaf_at(h_is_1, P(6, 0), Context(m, old, EST))
    assert leaf is not None and leaf.grasp == "B"
    assert leaf_at(h_is_1, P(6, 0), Context(m, new, EST)) is None
    assert leaf_at(Node((0, 1), (False, True)), P(6, 0), Context(m, new, EST)).grasp == "A"  # o0, o1 both A
    walked_old, walked_new = (policy_walk(m, c, EST, P(6, 0)) for c in (old, new))
    assert [o.cost_s for o in walked_old.outcomes] == pytest.approx([40, 85, 40])
    assert walked_old.expected_cost == pytest.approx(55.0) and walked_old.right == pytest.approx(5 / 6)
    assert [o.cost_s for o in walked_new.outcomes] == pytest.approx([40, 40, 40])
    assert walked_new.expected_cost == pytest.approx(40.0) and walked_new.right == 1.0
    assert optimal_cost(m, EST, P(6, 0)) == pytest.approx(30.0)


def _ratios(descriptions: list, start: Position) -> dict[str, float]:
    knowledge = load_knowledge(KNOWLEDGE)
    m, estimator = DescriptionMatrix(descriptions, knowledge), ModelMoveCost(knowledge.move)
    best = optimal_cost(m, estimator, start)
    searched = with_walk_search(CRITERIA["cs-id3-failure"])  # the experiments' ablation: every-row without its leaf
    return {spec.name: policy_walk(m, spec.build(), estimator, start).expected_cost / best
            for spec in (searched, CRITERIA["cs-id3-failure-search-every-row"])}


@pytest.mark.slow
def test_at_the_optimum_where_the_search_grasped_blind() -> None:
    # The quick study's shipped library (its first 10 descriptions) from (24,0), the
    # study's start the search missed: it walks 1.074 (a Front-Pinch grasped blind below
    # the Width-5° sweep, docs/optimum.md); with carried rows deciding leaves, 1.000
    # (measured). The whole shipped library from the three study starts, 1.000 each, is
    # checked by bench/bench_optimum.py --study-starts (about 5 s a start: too slow here).
    ratios = _ratios(read_library_json(EXAMPLE_LIBRARY)[:10], P(24, 0))
    assert ratios["cs-id3-failure-search"] > 1.05
    assert 1.0 - 1e-9 <= ratios["cs-id3-failure-search-every-row"] <= 1.02


@pytest.mark.slow
def test_the_six_description_regression_closes() -> None:
    # Six descriptions perturbed from the shipped ones (seed 0), from (16,90): the search
    # walked 1.151 x the optimum (one object in eight grasped blind first); every row
    # deciding, 1.000.
    knowledge = load_knowledge(KNOWLEDGE)
    library = synthetic_library(knowledge, 6, 0, base=read_library_json(EXAMPLE_LIBRARY))
    ratios = _ratios(library, P(16, 90))
    assert ratios["cs-id3-failure-search"] > 1.1
    assert 1.0 - 1e-9 <= ratios["cs-id3-failure-search-every-row"] <= 1.02
