"""A sensing position priced apart from a grasp position (``sensing_move_cost``).

The robot stands at (60,0) facing the object; moves cost 0.5 s/in and nothing else. Both
sweeps tell the cup from the box (1 bit each): H-Sweep-5° from (6,0) costs
54 x 0.5 + 45 = 72 s, H-Sweep-1° from (39,0) 21 x 0.5 + 100 = 110.5 s, so the near one
wins (tests/learner/test_position_choice.py). An estimator that knows the sound from
(6,0) would meet a neighbour prices sensing there at ``inf``: the near sweep is skipped,
the far one picked, and a grasp made from the very same (6,0) is still priced by
``move_cost`` (54 x 0.5 = 27 s).
"""

from __future__ import annotations

import math

import pytest

from learner.choosing.criteria import criterion
from learner.choosing.leaf import AmbiguousLeaf
from learner.choosing.node import Context, Node
from learner.choosing.selection import rank
from learner.costs import ModelMoveCost, sensing_cost
from learner.decision_tree import grow
from learner.knowledge import MoveModel
from learner.position import Position
from learner.runtime import RecognitionSession
from tests.learner.fixtures import P, context, desc, four_objects, hero

START = P(60, 0)
NEAR, FAR = "Width-Degree-5°(6,0)", "Width-Degree-1°(39,0)"
MOVES = MoveModel(seconds_per_inch=0.5, seconds_per_degree=0.0, overhead_s=0.0)


class BlockedSensing(ModelMoveCost):
    """The knowledge file's moves, but no reading from ``blocked`` is the object's alone."""

    def __init__(self, blocked: frozenset[Position]) -> None:
        super().__init__(MOVES)
        self.blocked = blocked

    def sensing_move_cost(self, start: Position, goal: Position) -> float:
        return math.inf if goal in self.blocked else self.move_cost(start, goal)


def _cup_and_box() -> list:
    return [
        desc("cup", "Front-Wrap", ("Width-Degree-5°", P(6, 0), 25), ("Width-Degree-1°", P(39, 0), 4)),
        desc("box", "Front-Pinch", ("Width-Degree-5°", P(6, 0), 45), ("Width-Degree-1°", P(39, 0), 13)),
    ]


def _with(estimator: ModelMoveCost, grasps: bool) -> Context:
    ctx = context(_cup_and_box(), grasps=grasps, move=MOVES)
    return Context(ctx.matrix, ctx.criterion, estimator)


def test_sensing_cost_falls_back_to_move_cost_without_the_optional_method() -> None:
    plain = ModelMoveCost(MOVES)
    assert sensing_cost(plain, START, P(6, 0)) == pytest.approx(27.0)
    assert sensing_cost(BlockedSensing(frozenset({P(6, 0)})), START, P(6, 0)) == math.inf
    assert sensing_cost(BlockedSensing(frozenset({P(6, 0)})), START, P(39, 0)) == pytest.approx(10.5)


def test_a_blocked_sensing_position_is_skipped_and_the_next_test_picked() -> None:
    ranked = rank(Node.root(2), START, _with(BlockedSensing(frozenset()), grasps=False), {})
    assert [str(s.test) for s in ranked] == [NEAR, FAR]  # unblocked: the near sweep (72 s < 110.5 s)

    ranked = rank(Node.root(2), START, _with(BlockedSensing(frozenset({P(6, 0)})), grasps=False), {})
    assert [str(s.test) for s in ranked] == [FAR]
    assert ranked[0].cost == pytest.approx(110.5)
    assert all(math.isfinite(s.score) for s in ranked)


def test_a_grasp_at_the_blocked_pose_is_still_priced_by_move_cost() -> None:
    ranked = rank(Node.root(2), START, _with(BlockedSensing(frozenset({P(6, 0)})), grasps=True), {})
    by_test = {str(s.test): s for s in ranked}
    assert NEAR not in by_test and FAR in by_test
    grasps = [s for s in ranked if s.test.is_grasp]
    assert grasps, "the grasps are still candidates"
    for s in grasps:
        assert s.target == P(6, 0)
        assert s.move_cost == pytest.approx(27.0)
    assert all(math.isfinite(s.score) for s in ranked)


def test_a_node_whose_every_sensing_test_is_blocked_falls_to_its_grasps() -> None:
    ctx = _with(BlockedSensing(frozenset({P(6, 0), P(39, 0)})), grasps=False)
    assert rank(Node.root(2), START, ctx, {}) == []
    tree = grow(Node.root(2), START, ctx)
    assert isinstance(tree, AmbiguousLeaf)
    assert sorted(o.grasp for o in tree.options) == ["Front-Pinch", "Front-Wrap"]
    assert all(math.isfinite(o.move_cost) for o in tree.options)


def test_the_discriminating_value_after_a_wrong_grasp_skips_a_blocked_position() -> None:
    # the tumbler (Top-Pinch) has Width-Degree-1°(24,0), Height(6,*) and Top-Hole?(6,*):
    # from (6,0) the D-Scan there (84 s, no move) is the cheapest (tests/learner/test_runtime.py);
    # with sensing from (6,0) blocked, the sweep from (24,0) is what is left
    k = hero()

    class Blocked(ModelMoveCost):
        def sensing_move_cost(self, start: Position, goal: Position) -> float:
            return math.inf if goal == P(6, 0) else self.move_cost(start, goal)

    s = RecognitionSession.for_library(four_objects(), k, criterion("cs-id3"), Blocked(k.move), P(6, 0))
    disc = s.discriminating_test("Top-Pinch")
    assert disc is not None and str(disc.test) == "Width-Degree-1°(24,0)" and disc.target == P(24, 0)
    assert disc.move_cost == pytest.approx(ModelMoveCost(k.move).move_cost(P(6, 0), P(24, 0)))
