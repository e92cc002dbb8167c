"""A grasp's failure harm: a price on what a failed grasp does beyond its seconds
(a tumbler knocked over), added wherever a choice weighs a failure, never learned away.

The HERO's file prices Front-Wrap at 60 s + 30 s side-effect penalty (90 s a failure)
and Top-Pinch at 63 s + 40 s (103 s); every harm here is set by hand on top.
"""

from __future__ import annotations

import dataclasses

import pytest

from learner.choosing.criteria import criterion
from learner.choosing.leaf import AmbiguousLeaf
from learner.choosing.matrix import DescriptionMatrix
from learner.choosing.node import Context, Node
from learner.choosing.selection import rank
from learner.costs import GraspCostRecord, ModelMoveCost, with_learned_grasp_costs
from learner.knowledge import Knowledge
from learner.optimum import optimal_cost
from learner.runtime import RecognitionSession
from tests.learner import test_optimum as worked
from tests.learner.fixtures import P, desc, hero, three_wraps_and_a_tumbler


def harmed(k: Knowledge, **harm_s: float) -> Knowledge:
    """``k`` with ``failure_harm_s`` set on the grasps named (``Front_Wrap=120``)."""
    by_name = {name.replace("_", "-"): s for name, s in harm_s.items()}
    return dataclasses.replace(k, grasping=tuple(dataclasses.replace(g, failure_harm_s=by_name[g.name])
                                                 if g.name in by_name else g for g in k.grasping))


def test_learned_costs_keep_the_harm_and_learn_only_the_seconds() -> None:
    # Front-Wrap, harm 200: three failures of 300 s make its failure (3 x 90 + 900) / 6 =
    # 195 robot seconds (penalty 195 - 60 = 135); priced 195 + 200 = 395, the harm as filed
    k = harmed(hero(), Front_Wrap=200)
    learned = with_learned_grasp_costs(k, [GraspCostRecord("Front-Wrap", failures=3, failure_s=900.0)])
    wrap = learned.grasp("Front-Wrap")
    assert (wrap.time_s, wrap.side_effect_penalty_s, wrap.failure_harm_s) == pytest.approx((60.0, 135.0, 200.0))
    assert (wrap.failure_time_s, wrap.feature_cost_s) == pytest.approx((195.0, 395.0))



@pytest.mark.parametrize(("harm", "first", "grasp_cost"), [
    (0.0, "Front-Wrap(6,*)", 22.5),  # 1/4 x 90, under the 42 s sweep
    (120.0, "Height-Degree-5°(6,*)", 52.5),  # 1/4 x (90 + 120), over it
])
def test_the_failure_share_rule_charges_a_failure_its_harm(harm: float, first: str, grasp_cost: float) -> None:
    # cs-id3-failure: Front-Wrap fails on the tumbler only, at 1/4 of the rows; both it
    # and the 42 s V-Sweep-5° gain all of H(3/4, 1/4), so the cheaper wins
    k = harmed(hero(), Front_Wrap=harm)
    ctx = Context(DescriptionMatrix(three_wraps_and_a_tumbler(), k), criterion("cs-id3-failure"), ModelMoveCost(k.move))
    ranked = rank(Node.root(4), P(6, 0), ctx, {})
    assert str(ranked[0].test) == first
    wrap = next(s for s in ranked if str(s.test) == "Front-Wrap(6,*)")
    assert wrap.scored_on[1] == pytest.approx(grasp_cost)


@pytest.mark.parametrize(("harm", "first"), [(0.0, "Front-Wrap(6,*)"), (20.0, "Width(6,0)")])
def test_the_papers_rule_charges_a_grasp_test_its_harm(harm: float, first: str) -> None:
    # cs-id3: a cup and a tumbler, each test gains 1 bit; Front-Wrap tried as a feature
    # costs 90 s (+ harm), the H-Scan for Width 105 s: the grasp wins until its harm
    # passes 15 s (90 + 20 = 110 > 105)
    lib = [desc("cup", "Front-Wrap", ("Width", P(6, 0), 3.0)), desc("tumbler", "Top-Pinch", ("Width", P(6, 0), 3.7))]
    k = harmed(hero(), Front_Wrap=harm, Top_Pinch=harm)
    ctx = Context(DescriptionMatrix(lib, k), criterion("cs-id3"), ModelMoveCost(k.move))
    ranked = rank(Node.root(2), P(6, 0), ctx, {})
    assert str(ranked[0].test) == first
    assert next(s for s in ranked if str(s.test) == "Front-Wrap(6,*)").sense_cost == 90.0 + harm


def test_an_ambiguous_leaf_tries_the_less_harmful_grasp_first() -> None:
    # no test splits them: Front-Wrap 90 s before Top-Pinch 103 s; with 20 s of harm
    # Front-Wrap is priced 110 s and goes second
    lib = [desc("a", "Front-Wrap", ("Width", P(6, 0), 3)), desc("b", "Top-Pinch", ("Width", P(6, 0), 3.2))]
    order = []
    for k in (hero(), harmed(hero(), Front_Wrap=20)):
        s = RecognitionSession.for_library(lib, k, criterion("cs-id3"), ModelMoveCost(k.move), P(6, 0),
                                           grasps_as_features=False)
        leaf = s.decide()
        assert isinstance(leaf, AmbiguousLeaf)
        order.append([o.grasp for o in leaf.options])
    assert order == [["Front-Wrap", "Top-Pinch"], ["Top-Pinch", "Front-Wrap"]]


def test_the_optimum_charges_a_wrong_grasp_its_harm() -> None:
    # test_optimum's worked library, from (20,0): after the 10 s sweep, a and b remain
    # (2/3); executing A is wrong half the time at 28 s move + 90 s, 59 s expected, below
    # the 68 s scan: 10 + 2/3 x 59. With 20 s of harm on A and B it is 1/2 x 138 = 69 s,
    # above the scan: 10 + 2/3 x 68
    lib = [worked.d("a", "A", ("W", P(20, 0), 10), ("H", P(6, 0), 3)),
           worked.d("b", "B", ("W", P(20, 0), 10), ("H", P(6, 0), 5)),
           worked.d("c", "C", ("W", P(20, 0), 30), ("H", P(6, 0), 5))]
    for harm, expected in ((0.0, 10 + 2 / 3 * 59), (20.0, 10 + 2 / 3 * 68)):
        k = harmed(worked.knowledge(), A=harm, B=harm)
        assert optimal_cost(DescriptionMatrix(lib, k), worked.EST, P(20, 0)) == pytest.approx(expected)
