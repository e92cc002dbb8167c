"""How a criterion chooses besides its formula: a truly cost-blind id3 (random ties, `*`
slots anywhere), joint gain of a procedure application, a one-step lookahead, and a
rollout of the one-step rule.

Every library here is hand-built so each gain, cost and expected cost is worked out in
the comments; the robot's profile is the HERO's (2 s per inch, no turning cost).
"""

from __future__ import annotations

import math

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from learner import decision_tree
from learner.choosing.criteria import CRITERIA, criterion, with_joint_gain, with_lookahead
from learner.choosing.gain import joint_gain, partition_columns
from learner.choosing.leaf import GraspLeaf
from learner.choosing.matrix import DescriptionMatrix
from learner.choosing.node import Context, Node, ScoredTest
from learner.choosing.rollout import branch_shares, finishing_cost
from learner.choosing.selection import rank
from learner.costs import ModelMoveCost
from learner.decision_tree import grow
from learner.knowledge import MoveModel
from learner.optimum import optimal_cost, policy_walk
from learner.runtime import RecognitionSession
from tests.learner.fixtures import ANY, P, context, desc, hero, three_wraps_and_a_tumbler
from tests.learner.test_optimum import SLOTS, STARTS, libraries
from tests.learner.test_optimum import matrix as optimum_matrix


CS_ID3_JOINT = with_joint_gain(CRITERIA["cs-id3"])  # forms the experiments measure, not the product's
CS_ID3_LOOKAHEAD = with_lookahead(CRITERIA["cs-id3"])


def H(*p: float) -> float:  # noqa: N802 - entropy in bits, as the paper writes it
    return -sum(x * math.log2(x) for x in p if x > 0)


# -- a truly cost-blind id3 -----------------------------------------------------------

def _dear_wide_cheap_narrow() -> list:
    """A 1° sweep from (24,0) tells all three apart; a 5° vertical sweep at 6 in only
    the cup from the other two."""
    return [
        desc("cup", "Front-Wrap", ("Width-Degree-1°", P(24, 0), 8), ("Height-Degree-5°", P(6, ANY), 30)),
        desc("box", "Front-Pinch", ("Width-Degree-1°", P(24, 0), 20), ("Height-Degree-5°", P(6, ANY), 60)),
        desc("tumbler", "Top-Pinch", ("Width-Degree-1°", P(24, 0), 30), ("Height-Degree-5°", P(6, ANY), 60)),
    ]


def test_cost_blind_and_cost_sensitive_rules_choose_differently() -> None:
    # From (6,0): the 1° sweep gains log2(3) = 1.585 bits for 18 in x 2 s + 100 s = 136 s;
    # the V-Sweep gains 1.585 - 2/3 * 1 = 0.918 bits for 0 + 42 s.
    # cs-id3: 1.585^2 / 136 = 0.0185 < 0.918^2 / 42 = 0.0201, so the V-Sweep;
    # id3 (either tie rule): the larger gain, the sweep, whatever it costs.
    lib = _dear_wide_cheap_narrow()
    gain_sweep, gain_vsweep = math.log2(3), math.log2(3) - 2 / 3
    sensitive = rank(Node.root(3), P(6, 0), context(lib, name="cs-id3", grasps=False), {})
    assert str(sensitive[0].test) == "Height-Degree-5°(6,*)" and sensitive[0].cost == 42
    assert sensitive[0].score == pytest.approx(gain_vsweep**2 / 42)
    assert sensitive[1].score == pytest.approx(gain_sweep**2 / 136)
    for name in ("id3", "id3-cost-ties"):
        blind = rank(Node.root(3), P(6, 0), context(lib, name=name, grasps=False), {})
        assert str(blind[0].test) == "Width-Degree-1°(24,0)" and blind[0].cost == 136
        assert blind[0].gain == pytest.approx(gain_sweep)


def _two_perfect_tests() -> list:
    """Both tests split the cup from the box (1 bit each): only ties can choose."""
    return [
        desc("cup", "Front-Wrap", ("Width-Degree-1°", P(24, 0), 8), ("Height-Degree-5°", P(6, ANY), 30)),
        desc("box", "Front-Pinch", ("Width-Degree-1°", P(24, 0), 20), ("Height-Degree-5°", P(6, ANY), 60)),
    ]


def _first_choice(seed: int) -> tuple[str, object]:
    k = hero()
    matrix = DescriptionMatrix(_two_perfect_tests(), k, grasps_as_features=False)
    session = RecognitionSession(matrix, criterion("id3"), ModelMoveCost(k.move), P(24, 0), seed=seed)
    first = session.decide()
    assert isinstance(first, ScoredTest) and first.gain == pytest.approx(1.0)
    return str(first.test), first.target


def test_id3_breaks_ties_at_random_repeatably_from_the_seed() -> None:
    # From (24,0) the 1° sweep costs 0 + 100 s, the V-Sweep 18 in x 2 s + 42 s = 78 s:
    # cs-id3 and id3-cost-ties settle the tie by cost; id3 by chance.
    lib = _two_perfect_tests()
    assert str(rank(Node.root(2), P(24, 0), context(lib, name="cs-id3", grasps=False), {})[0].test) \
        == "Height-Degree-5°(6,*)"  # 1/78 > 1/100
    assert str(rank(Node.root(2), P(24, 0), context(lib, name="id3-cost-ties", grasps=False), {})[0].test) \
        == "Width-Degree-1°(24,0)"  # equal gains: the nearer (no move)
    firsts = [_first_choice(seed) for seed in range(20)]
    assert {test for test, _ in firsts} == {"Width-Degree-1°(24,0)", "Height-Degree-5°(6,*)"}
    assert [_first_choice(seed) for seed in range(20)] == firsts  # the same seed, the same choices


def test_id3_fills_a_dont_care_slot_without_regard_to_cost() -> None:
    # Height-Degree-5°(6,*): the distance is fixed, the orientation is drawn anywhere
    # around the object, not kept at the robot's 0°.
    targets = {target for test, target in (_first_choice(seed) for seed in range(20))
               if test == "Height-Degree-5°(6,*)"}
    assert len(targets) >= 2
    assert all(t.distance_in == 6 and 0 <= t.orientation_deg < 360 for t in targets)
    kept = [s for s in rank(Node.root(2), P(24, 0), context(_two_perfect_tests(), name="id3-cost-ties",
                                                             grasps=False), {})
            if str(s.test) == "Height-Degree-5°(6,*)"]
    assert kept[0].target == P(6, 0)  # the cost-tie rule stays on the robot's side


def test_the_offline_tree_follows_the_same_cost_blind_rule() -> None:
    base = context(_two_perfect_tests(), name="id3", grasps=False)
    roots = set()
    for seed in range(20):
        ctx = Context(base.matrix, base.criterion, base.estimator, np.random.default_rng(seed))
        tree = grow(Node.root(2), P(24, 0), ctx)
        assert isinstance(tree, decision_tree.TestNode) and all(isinstance(b, GraspLeaf) for _, b in tree.branches)
        roots.add(str(tree.test.test))
    assert roots == {"Width-Degree-1°(24,0)", "Height-Degree-5°(6,*)"}


# -- joint gain: one procedure application, several features ----------------------------

def _one_scan_tells_all() -> list:
    """D-Scan-0.3 (84 s) yields Height and Top-Hole?, each halving the four grasps and
    together telling all four apart; H-Sweep-5° (45 s) picks out the cup alone."""
    return [
        desc("cup", "Front-Wrap", ("Height", P(6, ANY), 3), ("Top-Hole?", P(6, ANY), 0),
             ("Width-Degree-5°", P(6, ANY), 25)),
        desc("tumbler", "Top-Pinch", ("Height", P(6, ANY), 3), ("Top-Hole?", P(6, ANY), 1),
             ("Width-Degree-5°", P(6, ANY), 45)),
        desc("box", "Front-Pinch", ("Height", P(6, ANY), 9), ("Top-Hole?", P(6, ANY), 0),
             ("Width-Degree-5°", P(6, ANY), 45)),
        desc("closed", "No-Grab", ("Height", P(6, ANY), 9), ("Top-Hole?", P(6, ANY), 1),
             ("Width-Degree-5°", P(6, ANY), 45)),
    ]


def test_joint_gain_of_a_multi_feature_procedure_beats_a_single_feature_one() -> None:
    # H(C) = 2 bits. Height alone: 2 - 1 = 1 bit; Top-Hole? alone: 1 bit; the two of one
    # D-Scan together: 2 bits. Width-Degree-5°: {cup} {3 others}: 2 - 3/4 log2 3 = 0.811.
    # Scored one feature at a time, cs-id3 takes the sweep: 0.811^2 / 45 = 0.0146 > 1 / 84
    # = 0.0119, and then pays 45 + 3/4 x 84 = 108 s in expectation; scored on the joint
    # gain the scan wins, 2^2 / 84 = 0.0476, and settles all for 84 s.
    lib = _one_scan_tells_all()
    sweep_gain = 2 - 0.75 * math.log2(3)
    single = rank(Node.root(4), P(6, 0), context(lib, name="cs-id3", grasps=False), {})
    assert str(single[0].test) == "Width-Degree-5°(6,*)"
    assert single[0].score == pytest.approx(sweep_gain**2 / 45)
    joint = rank(Node.root(4), P(6, 0), context(lib, name=CS_ID3_JOINT, grasps=False), {})
    assert [str(s.test) for s in joint] == ["Height(6,*)", "Top-Hole?(6,*)", "Width-Degree-5°(6,*)"]
    assert joint[0].scored_on == pytest.approx((2.0, 84.0)) and joint[0].gain == pytest.approx(1.0)
    assert joint[0].score == pytest.approx(4 / 84)
    assert joint[2].scored_on == pytest.approx((sweep_gain, 45.0))  # one feature: its own gain
    # over two steps the scan's information is counted once: Height's own bit, then in
    # each branch Top-Hole?'s bit for free; every branch is then a leaf (I = 2, C = 84)
    ahead = rank(Node.root(4), P(6, 0), context(lib, name=CS_ID3_LOOKAHEAD, grasps=False), {})
    assert str(ahead[0].test) == "Height(6,*)" and ahead[0].scored_on == pytest.approx((2.0, 84.0))
    # the sweep: 0.811 bits, then in its branch {tumbler, box, closed} (3/4 of the node,
    # H = log2 3) the scan, whose joint I there is log2 3, for 84 s:
    # I = 0.811 + 3/4 log2 3 = 2, C = 45 + 3/4 x 84 = 108 s; 2^2 / 108 < 2^2 / 84
    sweep = next(s for s in ahead if str(s.test) == "Width-Degree-5°(6,*)")
    assert sweep.scored_on == pytest.approx((sweep_gain + 0.75 * math.log2(3), 45 + 0.75 * 84))
    # the tree: Height first, then Top-Hole? comes free from the same scan
    tree = grow(Node.root(4), P(6, 0), context(lib, name=CS_ID3_JOINT, grasps=False))
    assert isinstance(tree, decision_tree.TestNode) and str(tree.test.test) == "Height(6,*)"
    for _, child in tree.branches:
        assert isinstance(child, decision_tree.TestNode)
        assert str(child.test.test) == "Top-Hole?(6,*)" and child.test.cost == 0


def _gain_setup(lib: list, grasps: bool = False):  # noqa: ANN202
    ctx = context(lib, grasps=grasps)
    columns = np.arange(len(ctx.matrix.tests))
    rows = tuple(range(len(lib)))
    return ctx.matrix, rows, columns, partition_columns(rows, ctx.matrix, columns)


def test_joint_gain_by_hand_with_a_missing_value() -> None:
    # cup lacks Top-Hole?: spread 1/2 into each of its subsets {0} {1} (both values seen,
    # so no unknown subset). Cells of (Height, Top-Hole?): (3,0): cup/2; (3,1): tumbler +
    # cup/2; (9,0): box; (9,1): closed. Remainder = 1.5/4 x H(1/3, 2/3) = 0.344.
    lib = _one_scan_tells_all()
    lib[0] = desc("cup", "Front-Wrap", ("Height", P(6, ANY), 3))
    matrix, rows, columns, found = _gain_setup(lib)
    j = [matrix.column[t] for t in matrix.tests if t.feature in ("Height", "Top-Hole?")]
    got = joint_gain(rows, matrix, j, [found.ranges[c] for c in j], [bool(found.unknown[c]) for c in j])
    assert got == pytest.approx(2 - 1.5 / 4 * H(1 / 3, 2 / 3))


values = st.sampled_from([0.0, 1.0, 3.0, 3.4, 9.0, 20.0])


@st.composite
def scanned_libraries(draw):  # noqa: ANN001, ANN201
    """Up to seven objects with some of a D-Scan's three features (some missing)."""
    out = []
    for i in range(draw(st.integers(2, 7))):
        obs = [(f, P(6, ANY), draw(values) if f != "Top-Hole?" else draw(st.sampled_from([0.0, 1.0])))
               for f in ("Height", "Depth", "Top-Hole?") if draw(st.booleans())]
        out.append(desc(f"o{i}", draw(st.sampled_from(["Front-Wrap", "Front-Pinch", "Top-Pinch"])), *obs))
    return out


@settings(max_examples=60, deadline=None)
@given(scanned_libraries())
def test_joint_gain_is_the_single_gain_for_one_feature_and_never_below_any_member(lib) -> None:  # noqa: ANN001
    # the joint partition refines each member's (a row's weights over one feature's
    # subsets sum to 1), and refining never raises the conditional entropy
    matrix, rows, columns, found = _gain_setup(lib)
    if not len(columns):
        return
    for c in columns:
        alone = joint_gain(rows, matrix, [c], [found.ranges[c]], [bool(found.unknown[c])])
        assert alone == pytest.approx(float(found.gains[c]), abs=1e-9)
    together = joint_gain(rows, matrix, list(columns), [found.ranges[c] for c in columns],
                          [bool(found.unknown[c]) for c in columns])
    h = H(*[sum(d.grasp == g for d in lib) / len(lib) for g in {d.grasp for d in lib}])
    assert max(found.gains) - 1e-9 <= together <= h + 1e-9


# -- one-step lookahead -------------------------------------------------------------------

def _five_round_upright() -> list:
    """The five round upright objects of the shipped library, as far as these two
    sweeps go: 5° vertical at 6 in, 5° horizontal at 15 in (values from the library)."""
    return [
        desc("cup", "Front-Wrap", ("Height-Degree-5°", P(6, ANY), 30), ("Width-Degree-5°", P(15, ANY), 15)),
        desc("soda-can", "Front-Wrap", ("Height-Degree-5°", P(6, ANY), 40), ("Width-Degree-5°", P(15, ANY), 5)),
        desc("tennis-can", "Front-Wrap", ("Height-Degree-5°", P(6, ANY), 70), ("Width-Degree-5°", P(15, ANY), 15)),
        desc("tumbler-16", "Top-Pinch", ("Height-Degree-5°", P(6, ANY), 40), ("Width-Degree-5°", P(15, ANY), 15)),
        desc("tumbler-32", "Top-Pinch", ("Height-Degree-5°", P(6, ANY), 60), ("Width-Degree-5°", P(15, ANY), 15)),
    ]


def test_lookahead_takes_the_42_s_sweep_over_the_90_s_grasp() -> None:
    # Robot at (6,0); H(C) = H(3/5, 2/5) = 0.971 bits.
    # Front-Wrap tried as a feature: 60 + 30 s penalty = 90 s, settles all: 0.971 bits.
    # V-Sweep-5° at (6,*): 42 s, ranges [30] [40] [60] [70]; only [40] (soda can, tumbler)
    #   is mixed: 0.971 - 2/5 x 1 = 0.571 bits.
    # cs-id3: 0.971^2 / 90 = 0.01048 > 0.571^2 / 42 = 0.00776: the grasp, 90 s every time.
    # Lookahead: after the V-Sweep, in [40] the best next test is the 5° sweep at (15,*):
    #   9 in x 2 s + 45 s = 63 s, 1 bit. Over two steps: I = 0.571 + 2/5 x 1 = 0.971,
    #   C = 42 + 2/5 x 63 = 67.2 s: 0.971^2 / 67.2 = 0.01403 > 0.01048 (the grasp's leaves
    #   need no second step). Expected cost 67.2 s instead of 90 s.
    lib = _five_round_upright()
    h = H(0.6, 0.4)
    myopic = rank(Node.root(5), P(6, 0), context(lib, name="cs-id3"), {})[0]
    assert myopic.test.is_grasp and myopic.test.feature == "Front-Wrap" and myopic.cost == 90
    assert myopic.score == pytest.approx(h**2 / 90)
    ranked = rank(Node.root(5), P(6, 0), context(lib, name=CS_ID3_LOOKAHEAD), {})
    ahead = ranked[0]
    assert str(ahead.test) == "Height-Degree-5°(6,*)" and ahead.cost == 42 and ahead.gain == pytest.approx(h - 0.4)
    assert ahead.scored_on == pytest.approx((h, 42 + 0.4 * 63))
    assert ahead.score == pytest.approx(h**2 / 67.2)
    grasp = next(s for s in ranked if s.test.feature == "Front-Wrap")
    assert grasp.scored_on == pytest.approx((h, 90.0)) and grasp.score == pytest.approx(h**2 / 90)


def test_the_session_walks_the_lookahead_route_for_67_s_on_average() -> None:
    # per object: cup, tennis can, tumbler-32: 42 s; soda can, tumbler-16: 42 + 63 = 105 s;
    # (3 x 42 + 2 x 105) / 5 = 67.2 s, against 90 s for every object when grasping first.
    k = hero()
    lib = _five_round_upright()
    costs = []
    for obj in lib:
        truth = {(o.feature, o.position.distance_in): o.value for o in obj.observations}
        s = RecognitionSession.for_library(lib, k, CS_ID3_LOOKAHEAD.build(), ModelMoveCost(k.move), P(6, 0))
        spent = 0.0
        while isinstance(step := s.decide(), ScoredTest):
            spent += step.cost
            s.observe(step, {step.test.feature: truth[(step.test.feature, step.target.distance_in)]}, step.target)
        assert isinstance(step, GraspLeaf) and step.grasp == obj.grasp
        costs.append(spent)
    assert costs == [42, 105, 42, 105, 42]
    assert sum(costs) / 5 == pytest.approx(67.2)


def test_the_default_criterion_is_unchanged_by_the_refined_forms() -> None:
    # the myopic choice above is what cs-id3 made before lookahead and joint gain existed
    lib = _five_round_upright()
    first = rank(Node.root(5), P(6, 0), context(lib, name="cs-id3"), {})[0]
    assert first.scored_on is None and first.test.feature == "Front-Wrap"


# -- rollout: the test, then finishing with the one-step rule ---------------------------


def test_the_rollout_tries_the_grasp_the_ratio_finds_too_dear() -> None:
    # Robot at (6,0), every test at 6 in: no move. H(C) = H(3/4, 1/4) = 0.811 bits, and
    # each of the three tests gains all of it.
    # V-Sweep-5° (6,*): 42 s. Front-Wrap tried as a feature: 60 + 30 s penalty = 90 s.
    # Top-Pinch tried as a feature: 63 + 40 = 103 s.
    # cs-id3: 0.811^2 / 42 = 0.0157 > 0.811^2 / 90: the sweep, 42 s for every object.
    # Rollout, expected cost of the test and then finishing by cs-id3 (every branch is a
    # leaf whose grasp is right, so finishing is free):
    #   sweep: 42 s;
    #   Front-Wrap: paid only when it fails (the tumbler, 1/4): 1/4 x 90 = 22.5 s;
    #   Top-Pinch: fails for the three wraps: 3/4 x 103 = 77.25 s.
    lib = three_wraps_and_a_tumbler()
    h = H(0.75, 0.25)
    greedy = rank(Node.root(4), P(6, 0), context(lib, name="cs-id3"), {})
    assert str(greedy[0].test) == "Height-Degree-5°(6,*)" and greedy[0].score == pytest.approx(h**2 / 42)
    ranked = rank(Node.root(4), P(6, 0), context(lib, name="cs-id3-rollout"), {})
    totals = {str(s.test): s.scored_on[1] for s in ranked}
    assert totals == pytest.approx({"Front-Wrap(6,*)": 22.5, "Height-Degree-5°(6,*)": 42.0,
                                    "Top-Pinch(6,*)": 77.25})
    assert str(ranked[0].test) == "Front-Wrap(6,*)" and ranked[0].score == pytest.approx(-22.5)
    assert ranked[0].gain == pytest.approx(h) and ranked[0].cost == 90


def test_the_rollout_walk_costs_the_optimum_where_the_ratio_pays_twice_as_much() -> None:
    # Walked per object: cs-id3 sweeps every time, 42 s. The rollout tries Front-Wrap:
    # it holds for the three wraps (nothing counted) and fails on the tumbler (90 s), whose
    # branch is its Top-Pinch leaf: (0 + 0 + 0 + 90) / 4 = 22.5 s. No policy does better:
    # the optimum is that same blind Front-Wrap.
    k = hero()
    m, est = DescriptionMatrix(three_wraps_and_a_tumbler(), k), ModelMoveCost(k.move)
    assert policy_walk(m, criterion("cs-id3"), est, P(6, 0)).expected_cost == pytest.approx(42.0)
    for name in ("cs-id3-rollout", "idx-rollout"):
        walk = policy_walk(m, criterion(name), est, P(6, 0))
        # (the failed Front-Wrap was a test, not a leaf: every leaf's grasp is right)
        assert [o.cost_s for o in walk.outcomes] == pytest.approx([0, 0, 0, 90]) and walk.right == 1.0
    assert optimal_cost(m, est, P(6, 0)) == pytest.approx(22.5)


def test_a_wrong_leaf_is_a_failed_attempt_in_the_rollout() -> None:
    # The soda can lacks the 5° vertical sweep, so after it the cup's branch holds
    # the cup and the carried soda can, both Front-Wrap (right either way), and the
    # tumbler's branch holds the tumbler and the soda can: a Top-Pinch leaf, wrong for the
    # soda can. Shares: cup's range 1/3 + 1/3 x 1/2 = 1/2, the tumbler's the same.
    # Finishing after the sweep: 1/2 x 0 + 1/2 x (1/2 wrong x (Top-Pinch 63 + 40 s) + 0,
    # the soda can then a Front-Wrap leaf) = 25.75 s; with the sweep's 42 s, 67.75 s.
    lib = [
        desc("cup", "Front-Wrap", ("Height-Degree-5°", P(6, ANY), 30)),
        desc("soda-can", "Front-Wrap", ("Width-Degree-5°", P(15, ANY), 5)),
        desc("tumbler", "Top-Pinch", ("Height-Degree-5°", P(6, ANY), 60)),
    ]
    # (The sweep is cs-id3's only choice: the soda can's width alone makes no split.)
    ctx = context(lib, name="cs-id3", grasps=False)
    [sweep] = rank(Node.root(3), P(6, 0), ctx, {})
    assert str(sweep.test) == "Height-Degree-5°(6,*)"
    assert branch_shares(Node.root(3), sweep, ctx) == pytest.approx([0.5, 0.5])
    assert finishing_cost(Node.root(3), P(6, 0), ctx, {}) == pytest.approx(42 + 0.5 * 0.5 * 103)


def test_the_rollout_keeps_the_grasp_the_lookahead_avoids() -> None:
    # The five round upright objects (test above): the lookahead's 67.2 s V-Sweep route
    # charges the Front-Wrap grasp its full 90 s. Executed, that grasp costs only when it
    # fails: on the two tumblers (2/5), whose branch is then a Top-Pinch leaf: 2/5 x 90 =
    # 36 s. The V-Sweep then cs-id3: 42 + 2/5 x 63 (the 5° sweep at (15,*)) = 67.2 s.
    ranked = rank(Node.root(5), P(6, 0), context(_five_round_upright(), name="cs-id3-rollout"), {})
    totals = {str(s.test): s.scored_on[1] for s in ranked}
    assert ranked[0].test.feature == "Front-Wrap" and totals["Front-Wrap(6,*)"] == pytest.approx(36.0)
    assert totals["Height-Degree-5°(6,*)"] == pytest.approx(67.2)


@settings(max_examples=25, deadline=None)
@given(libraries(SLOTS), st.sampled_from(STARTS), st.booleans(), st.sampled_from(["cs-id3-rollout", "idx-rollout"]))
def test_the_rollout_is_never_worse_than_its_rule_on_its_own_estimate_nor_below_the_optimum(
        library: list, start: object, grasps: bool, name: str) -> None:
    # the rule's own first choice is a candidate, so the chosen total is at most its total;
    # and the walk is an adaptive policy under the optimum's accounting, so never below it
    move = MoveModel(2.0, 0.1, 0.0)  # test_optimum's knowledge: features H, D, W; grasps A, B, C (unconfirmable)
    m, est = optimum_matrix(library, grasps, move), ModelMoveCost(move)
    ctx = Context(m, criterion(name), est)
    ranked = rank(Node.root(len(library)), start, ctx, {})
    if ranked:
        base = rank(Node.root(len(library)), start, Context(m, criterion(name.removesuffix("-rollout")), est), {})[0]
        own = next(s for s in ranked if s.test == base.test and s.target == base.target)
        assert ranked[0].scored_on[1] <= own.scored_on[1] + 1e-9
    walk = policy_walk(m, criterion(name), est, start)
    if walk.missed == 0:
        assert optimal_cost(m, est, start) <= walk.expected_cost + 1e-9
