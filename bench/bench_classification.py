"""Classification cost of the learned trees, by evaluation function (the paper's
"for classification alone, cost-sensitive trees were at least 30% cheaper").

Each criterion grows its whole tree from the same pose over the shipped library; every
Table 3 training object then walks it with its true values (the simulator's probe, no
noise), paying each test's move and sensing cost (a grasp tried as a feature pays its
cost too, as a degenerate sensor) until a leaf. Side by side in one process.

    python bench/bench_classification.py [--pose 60,0] [--no-grasp-features] [--exhaustive]

``--exhaustive`` replaces the shipped (CSL-trained, already cheap) library with one in
which every procedure was applied at every training position: the criterion alone then
decides what the tree measures, as in the paper's comparison.
"""

from __future__ import annotations

import argparse
import statistics
import sys
from functools import lru_cache
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT))

from executive.defaults import EXAMPLE_LIBRARY, KNOWLEDGE  # noqa: E402
from robot_profile import load_knowledge  # noqa: E402
from executive.training_sources import catalogue_objects  # noqa: E402
from hero_driver.sim.probe import probe  # noqa: E402
from experiments.ablations import MEASURED, criterion  # noqa: E402
from learner.choosing.leaf import AmbiguousLeaf, GraspLeaf  # noqa: E402
from learner.choosing.matrix import DescriptionMatrix  # noqa: E402
from learner.choosing.node import Context, Node  # noqa: E402
from learner.choosing.partition import match, nearest  # noqa: E402
from learner.costs import ModelMoveCost  # noqa: E402
from learner.decision_tree import TestNode, grow  # noqa: E402
from learner.library.format import read_library_json  # noqa: E402
from learner.position import parse_position  # noqa: E402


@lru_cache(maxsize=None)
def true_values(entry: str, procedure: str, distance: float, orientation: float) -> dict:
    return dict(probe(entry, procedure, distance, orientation).values)


def walk(tree, entry: str, grasp: str) -> tuple[float, bool]:  # noqa: ANN001
    """Classification cost and whether the leaf reached names the object's grasp."""
    cost, node = 0.0, tree
    while isinstance(node, TestNode):
        t = node.test
        cost += t.move_cost + t.sense_cost
        if t.test.is_grasp:
            if t.test.feature == grasp:
                return cost, True
            value = 0.0
        else:
            value = true_values(entry, t.test.procedure, t.target.distance_in, t.target.orientation_deg)[t.test.feature]
        ranges = [r for r, _ in node.branches]
        idx = match(value, ranges, t.error) if value is not None else None
        node = node.branches[nearest(value or 0.0, ranges) if idx is None else idx][1]
    if isinstance(node, GraspLeaf):
        return cost, node.grasp == grasp
    assert isinstance(node, AmbiguousLeaf)
    return cost, bool(node.options) and node.options[0].grasp == grasp


def exhaustive_library(objects, knowledge, distances=(6.0, 15.0, 23.0), orientations=(0.0, 90.0, 180.0, 270.0)):  # noqa: ANN001, ANN201
    """Every procedure at every training position, for every object."""
    from learner.description import ObjectDescription, Observation
    from learner.position import Position

    out = []
    for o in objects:
        obs = []
        for d in distances:
            for theta in ((0.0,) if o.round else orientations):
                for proc in knowledge.sensing:
                    if proc.applicable_at(d):
                        for f, v in true_values(o.object_id, proc.name, d, theta).items():
                            if v is not None:
                                obs.append(Observation(f, Position(d, None if o.round else theta), float(v)))
        out.append(ObjectDescription(o.object_id, o.grasp, o.grasp_position, tuple(sorted(obs))))
    return out


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--pose", default="60,0")
    ap.add_argument("--no-grasp-features", action="store_true")
    ap.add_argument("--exhaustive", action="store_true")
    args = ap.parse_args()
    k = load_knowledge(KNOWLEDGE)
    objects = catalogue_objects("training")
    library = exhaustive_library(objects, k) if args.exhaustive else read_library_json(EXAMPLE_LIBRARY)
    start = parse_position(args.pose)
    results = {}
    for name in MEASURED:
        ctx = Context(DescriptionMatrix(library, k, not args.no_grasp_features), criterion(name), ModelMoveCost(k.move))
        tree = grow(Node.root(len(library)), start, ctx)
        results[name] = [walk(tree, o.object_id, o.grasp) for o in objects]
    base = statistics.mean(c for c, _ in results["id3"])
    print(f"{len(objects)} Table 3 objects, tree grown from {args.pose}, grasps as features: "
          f"{not args.no_grasp_features}, library: {'exhaustive' if args.exhaustive else 'shipped'}")
    print("| criterion | classification cost s (mean) | median | right grasp | vs id3 |")
    print("|---|---|---|---|---|")
    for name, rs in results.items():
        mean = statistics.mean(c for c, _ in rs)
        print(f"| {name} | {mean:.0f} | {statistics.median(c for c, _ in rs):.0f} | "
              f"{sum(ok for _, ok in rs)}/{len(rs)} | {mean / base:.2f} |")


if __name__ == "__main__":
    main()
