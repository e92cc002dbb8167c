"""Run-time decision trees: test nodes over leaves, and growing them from a position.

At run time only the path the object at hand needs is grown (``learner.runtime``);
``grow`` expands every branch, for inspection (``csl tree``) and for tests. Both use
the same node rules: a node whose deciding descriptions share one grasp is a leaf
(``learner.choosing.leaf``); else the best-ranked test splits it; a node no test can
split is an *ambiguous* leaf whose grasps the executive tries one by one as binary
features.
"""

from __future__ import annotations

from dataclasses import dataclass

from learner.choosing.leaf import AmbiguousLeaf, GraspLeaf, grasp_options, leaf_at, object_ids
from learner.choosing.matrix import Test
from learner.choosing.node import Context, Measurements, Node, ScoredTest, split, yielded
from learner.choosing.partition import Range, match
from learner.choosing.selection import rank
from learner.position import Position


@dataclass(frozen=True)
class TestNode:
    """A test with its ranked alternatives and one subtree per branch range."""

    test: ScoredTest
    alternatives: tuple[ScoredTest, ...]
    branches: tuple[tuple[Range, TreeNode], ...]


TreeNode = TestNode | GraspLeaf | AmbiguousLeaf


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
