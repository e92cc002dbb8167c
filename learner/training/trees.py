"""Phase 2's decision trees (Table 6): one per set of descriptions, grown only as far as
predictions walk it.

Table 6 rebuilds the tree from all descriptions before every object of every pass, but
a tree depends only on the descriptions it is grown from (the knowledge is fixed for a
training run, the criterion is cs-id3 with nothing left to chance, and nothing moves:
every move costs 0). Most passes measure nothing new for most objects, so the same
descriptions come back again and again: on Table 3, 742 trees are asked for and 298
are distinct. And a prediction walks one path of a tree; the other branches matter
only to the objects that go down them. So each distinct tree is kept, and each of its
nodes is grown, by the rule :func:`learner.decision_tree.grow` applies to every node,
the first time a prediction reaches it: every walk meets the nodes the full tree has
on its path, and nodes no object reaches are never grown.

``reuse=False`` grows every tree whole for every prediction, as the method is written:
the reference the kept trees are checked against (tests, ``bench/bench_training.py``).
"""

from __future__ import annotations

from collections.abc import Callable, Mapping, Sequence
from dataclasses import dataclass

from learner.choosing.criteria import criterion
from learner.choosing.leaf import AmbiguousLeaf, GraspLeaf, grasp_options, leaf_at, object_ids
from learner.choosing.matrix import DescriptionMatrix, Test
from learner.choosing.node import Context, Node, ScoredTest, split, yielded
from learner.choosing.partition import Range, match, nearest
from learner.choosing.selection import rank
from learner.decision_tree import TestNode, TreeNode, grow
from learner.description import ObjectDescription
from learner.knowledge import Knowledge
from learner.position import Position

TRAINING_CRITERION = "cs-id3"  # the paper's rule: training positions as Table 6 has them (no grasps as features there)
ORIGIN = Position(0.0, 0.0)  # where a phase-2 tree is grown from; moves cost nothing there (_ZeroMove)


class _ZeroMove:
    """At one training position nothing moves: only sensing costs count."""

    def move_cost(self, start: Position, goal: Position) -> float:
        return 0.0


def _context(descriptions: Sequence[ObjectDescription], knowledge: Knowledge) -> Context:
    # grasps are what training teaches, not something to try: no grasp tests
    matrix = DescriptionMatrix(descriptions, knowledge, grasps_as_features=False)
    return Context(matrix, criterion(TRAINING_CRITERION), _ZeroMove())


@dataclass(frozen=True)
class _GrownTest:
    """A node grown on first visit: its best test and a branch per range."""

    test: ScoredTest
    branches: tuple[tuple[Range, _Unfolding], ...]


class _Unfolding:
    """A tree node not grown until a prediction reaches it (then grown once)."""

    __slots__ = ("_node", "_current", "_ctx", "_measurements", "_exclude", "_grown")

    def __init__(self, node: Node, current: Position, ctx: Context,
                 measurements: Mapping[tuple[str, Position], float], exclude: frozenset[Test]) -> None:
        self._node, self._current, self._ctx = node, current, ctx
        self._measurements, self._exclude = measurements, exclude
        self._grown: GraspLeaf | AmbiguousLeaf | _GrownTest | None = None

    def grown(self) -> GraspLeaf | AmbiguousLeaf | _GrownTest:
        """This node as :func:`~learner.decision_tree.grow` makes it, its children left to unfold."""
        if self._grown is None:
            self._grown = self._grow()
        return self._grown

    def _grow(self) -> GraspLeaf | AmbiguousLeaf | _GrownTest:
        node, current, ctx = self._node, self._current, self._ctx
        leaf = leaf_at(node, current, ctx)
        if leaf is not None:
            return leaf
        ranked = rank(node, current, ctx, self._measurements, self._exclude)
        if not ranked:
            return AmbiguousLeaf(tuple(grasp_options(node, current, ctx)), object_ids(node, ctx))
        best = ranked[0]
        below = {**self._measurements, **yielded(best, ctx)}
        return _GrownTest(best, tuple(
            (rng, _Unfolding(child, best.target, ctx, below, self._exclude | {best.test}))
            for rng, child in zip(best.ranges, split(node, best, ctx.matrix))))


PhaseTree = TreeNode | _Unfolding


def predicted_grasp(tree: PhaseTree, value_of: Callable[[str], float | None]) -> str | None:
    """Familiarize: walk ``tree`` with the values ``value_of(feature)`` gives (it measures
    what the object lacks), to a leaf's grasp; None for an ambiguous leaf or a value
    that cannot be had. A value between the branches' ranges follows the nearest."""
    node: PhaseTree | _GrownTest | TestNode = tree
    while True:
        if isinstance(node, _Unfolding):
            node = node.grown()
        if isinstance(node, GraspLeaf):
            return node.grasp
        if isinstance(node, AmbiguousLeaf):
            return None
        value = value_of(node.test.test.feature)
        if value is None:
            return None
        ranges = [r for r, _ in node.branches]
        idx = match(value, ranges, node.test.error)
        node = node.branches[nearest(value, ranges) if idx is None else idx][1]


class TrainingTrees:
    """The trees phase 2 classifies with, one per set of descriptions (module docstring);
    ``asked`` trees were asked for, ``grown`` of them were new."""

    def __init__(self, knowledge: Knowledge, reuse: bool = True) -> None:
        self.knowledge, self.reuse = knowledge, reuse
        self.asked = self.grown = 0
        self._kept: dict[tuple[ObjectDescription, ...], _Unfolding] = {}
        # the same description objects asked for again (the recorder keeps them while
        # unchanged): found without hashing every observation; the value holds the
        # descriptions, so their ids cannot pass to other objects
        self._by_identity: dict[tuple[int, ...], tuple[tuple[ObjectDescription, ...], _Unfolding]] = {}

    def tree(self, descriptions: Sequence[ObjectDescription]) -> PhaseTree:
        """The tree of ``descriptions`` (in this order: rows break ties)."""
        self.asked += 1
        key = tuple(descriptions)
        if not self.reuse:
            self.grown += 1
            return grow(Node.root(len(key)), ORIGIN, _context(key, self.knowledge))
        ids = tuple(map(id, key))
        if ids in self._by_identity:
            return self._by_identity[ids][1]
        if key not in self._kept:
            self.grown += 1
            self._kept[key] = _Unfolding(Node.root(len(key)), ORIGIN, _context(key, self.knowledge), {}, frozenset())
        self._by_identity[ids] = (key, self._kept[key])
        return self._kept[key]
