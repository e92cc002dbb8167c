"""The leaf rule: when a node is a leaf, and the grasps a leaf offers.

A node whose deciding descriptions (its genuine rows, or all when none is genuine)
share one grasp is a leaf: execute that grasp, from its cheapest position. A node no
test can split is an *ambiguous* leaf whose grasps the executive tries one by one as
binary features, cheapest first. The grown tree, the session and the rollouts all stop
by this rule, so it sits below the ranking (a rollout finishes a candidate by it).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from learner.choosing.matrix import Test
from learner.choosing.node import Context, Node, deciding_index, target_for
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
