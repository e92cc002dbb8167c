"""Run-time decision trees: nodes, leaves, and growing them from a position.

At run time only the path the object at hand needs is grown (``learner.runtime``);
``grow`` expands every branch, for inspection (``csl tree``) and for tests. Both use
the same node rules: a node whose deciding descriptions share one grasp is a leaf; else
the best-ranked test splits it; a node no test can split is an *ambiguous* leaf whose
grasps the executive tries one by one as binary features.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from learner.choosing.matrix import Test
from learner.choosing.partition import Range, match
from learner.choosing.selection import (Context, Measurements, Node, ScoredTest, deciding_index, rank, split,
                                        target_for, yielded)
from learner.position import Position


@dataclass(frozen=True)
class GraspLeaf:
    """Execute ``grasp`` at ``position``. ``grasped``: reached by a successful grasp tried
    as a feature, so the object is already in the hand and nothing is left to pay."""

    grasp: str
    position: Position  # where the robot goes: concrete
    move_cost: float
    grasp_cost: float
    object_ids: tuple[str, ...]
    grasped: bool = False
    library_position: Position | None = None  # as the descriptions record it ("*" allowed)


@dataclass(frozen=True)
class AmbiguousLeaf:
    """No test separates these descriptions: try their grasps, cheapest first."""

    options: tuple[GraspLeaf, ...]
    object_ids: tuple[str, ...]


@dataclass(frozen=True)
class TestNode:
    """A test with its ranked alternatives and one subtree per branch range."""

    test: ScoredTest
    alternatives: tuple[ScoredTest, ...]
    branches: tuple[tuple[Range, TreeNode], ...]


TreeNode = TestNode | GraspLeaf | AmbiguousLeaf


def grasp_options(node: Node, current: Position, ctx: Context) -> list[GraspLeaf]:
    """One leaf per grasp of the deciding rows, at its cheapest position, cheapest first.

    A leaf of a large library holds tens of thousands of rows, so their grasps, grasp
    positions and ids are read as arrays (``DescriptionMatrix.labels``), not row by row.
    """
    matrix = ctx.matrix
    labels = matrix.labels
    deciding = deciding_index(node)
    classes = matrix.class_of[deciding]
    options = []
    for c in np.unique(classes).tolist():
        grasp = matrix.classes[c]
        rows = deciding[classes == c]
        proc = ctx.knowledge.grasp(grasp)
        ids = tuple(np.sort(labels.object_id[rows]).tolist())
        best: GraspLeaf | None = None
        for position in sorted(labels.positions[i] for i in np.unique(labels.grasp_position[rows]).tolist()):
            target = target_for(Test(grasp, position, grasp, is_grasp=True), current, ctx)
            move = ctx.estimator.move_cost(current, target)
            if best is None or move < best.move_cost:
                best = GraspLeaf(grasp, target, move, proc.time_s, ids, library_position=position)
        assert best is not None
        options.append(best)

    def as_feature(o: GraspLeaf) -> tuple[bool, float, str]:
        # tried as binary features, so ranked by that cost (time + side-effect penalty);
        # a grasp the finger sensor cannot confirm (No-Grab) proves nothing: last
        g = ctx.knowledge.grasp(o.grasp)
        return (not g.verifiable, o.move_cost + g.feature_cost_s, o.grasp)

    return sorted(options, key=as_feature)


def leaf_at(node: Node, current: Position, ctx: Context) -> GraspLeaf | None:
    """The leaf this node is, when its deciding descriptions share one grasp (for a
    ``leaf_every_row`` criterion: when every description at it does, carried included)."""
    rows = np.asarray(node.rows, dtype=np.int64) if ctx.criterion.leaf_every_row else deciding_index(node)
    if len(np.unique(ctx.matrix.class_of[rows])) == 1:
        return grasp_options(node, current, ctx)[0]
    return None


def object_ids(node: Node, ctx: Context) -> tuple[str, ...]:
    """The distinct object ids of the deciding rows, sorted."""
    return tuple(np.unique(ctx.matrix.labels.object_id[deciding_index(node)]).tolist())


def grow(
    node: Node,
    current: Position,
    ctx: Context,
    measurements: Measurements | None = None,
    exclude: frozenset[Test] = frozenset(),
) -> TreeNode:
    """The whole tree from ``current``, every branch expanded.

    Each test moves the robot, so a subtree is grown from its parent test's position.
    A procedure yields all its features at once, so below a test its siblings at the
    same position are free; their values are unknown here (NaN), only that they are
    measured matters. The rule is the session's (``rank``), chance included: a
    cost-blind criterion draws from ``ctx.rng`` as the tree grows, so it repeats from
    its seed.
    """
    measurements = measurements or {}
    leaf = leaf_at(node, current, ctx)
    if leaf is not None:
        return leaf
    ranked = rank(node, current, ctx, measurements, exclude)
    if not ranked:
        return AmbiguousLeaf(tuple(grasp_options(node, current, ctx)), object_ids(node, ctx))
    best = ranked[0]
    children: list[tuple[Range, TreeNode]] = []
    for rng, child in zip(best.ranges, split(node, best, ctx.matrix)):
        if best.test.is_grasp and rng[0] >= 1.0:
            sub: TreeNode = GraspLeaf(best.test.feature, best.target, 0.0, 0.0, object_ids(child, ctx), grasped=True,
                                      library_position=best.test.position)
        else:
            sub = grow(child, best.target, ctx, {**measurements, **yielded(best, ctx)}, exclude | {best.test})
        children.append((rng, sub))
    return TestNode(best, tuple(ranked[1:]), tuple(children))


def classify(tree: TreeNode, values: dict[Test, float]) -> list[str]:
    """Follow ``tree`` with known test values (a grasp test's value: 1 for its grasp).

    Returns the grasps the reached leaf offers (one for a grasp leaf); an unmatched or
    missing value returns the empty list.
    """
    node = tree
    while isinstance(node, TestNode):
        value = values.get(node.test.test)
        if value is None:
            return []
        idx = match(value, [r for r, _ in node.branches], node.test.error)
        if idx is None:
            return []
        node = node.branches[idx][1]
    if isinstance(node, GraspLeaf):
        return [node.grasp]
    return [o.grasp for o in node.options]
