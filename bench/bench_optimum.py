"""Distance to the optimum: every criterion's expected cost as a ratio to the exact optimum.

Noise-free, uniform prior over the library's descriptions, the learner's default move
model (2 s/in in the shipped profile), every object charged until its own grasp is
executed, failed grasps included (docs/optimum.md). The shipped library and a synthetic
one perturbed from it, from several start poses; each cell is ``policy_cost /
optimal_cost`` and, in brackets, the share of descriptions whose first executed grasp
is their own (and the share left behind by a wrong No-Grab, if any). Under each table,
what one root decision takes per criterion (the slowest over the start poses): the
rollouts' price.

    python bench/bench_optimum.py [--synthetic 12] [--seed 0]
"""

from __future__ import annotations

import argparse
import sys
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT))

from executive.defaults import EXAMPLE_LIBRARY, KNOWLEDGE  # noqa: E402
from executive.profile import load_knowledge  # noqa: E402
from learner.costs import ModelMoveCost  # noqa: E402
from learner.criteria import CRITERIA, criterion  # noqa: E402
from learner.library import read_library_json  # noqa: E402
from learner.matrix import DescriptionMatrix  # noqa: E402
from learner.optimum import optimal_cost, policy_walk  # noqa: E402
from learner.position import Position  # noqa: E402
from learner.runtime import RecognitionSession  # noqa: E402
from learner.synthetic import synthetic_library  # noqa: E402

STARTS = [Position(d, o) for d, o in ((6, 0), (16, 90), (24, 180), (40, 270), (40, 0), (16, 180))]


def table(title: str, matrix: DescriptionMatrix, estimator: ModelMoveCost, seed: int) -> None:
    print(f"\n{title}: {len(matrix.descriptions)} descriptions, {len(matrix.tests)} tests")
    print("| start | optimum s | search s | " + " | ".join(CRITERIA) + " |")
    print("|---" * (3 + len(CRITERIA)) + "|")
    root_ms = dict.fromkeys(CRITERIA, 0.0)
    for start in STARTS:
        for name in CRITERIA:
            began = time.perf_counter()
            RecognitionSession(matrix, criterion(name), estimator, start, seed=seed).decide()
            root_ms[name] = max(root_ms[name], (time.perf_counter() - began) * 1000)
        began = time.perf_counter()
        best = optimal_cost(matrix, estimator, start)
        took = time.perf_counter() - began
        cells = []
        for name in CRITERIA:
            walk = policy_walk(matrix, criterion(name), estimator, start, seed=seed)
            ratio = walk.expected_cost / best if best > 0 else float("nan")
            left = f", {walk.missed:.0%} left" if walk.missed else ""
            cells.append(f"{ratio:.3f} ({walk.right:.0%}{left})")
        print(f"| {start} | {best:.1f} | {took:.1f} | " + " | ".join(cells) + " |")
    print("root decision, ms: " + ", ".join(f"{name} {ms:.0f}" for name, ms in root_ms.items()))


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--synthetic", type=int, default=12, help="descriptions in the synthetic library (default 12)")
    ap.add_argument("--seed", type=int, default=0, help="seed of the synthetic library and of random ties")
    args = ap.parse_args()
    knowledge = load_knowledge(KNOWLEDGE)
    shipped = read_library_json(EXAMPLE_LIBRARY)
    estimator = ModelMoveCost(knowledge.move)
    table("shipped library", DescriptionMatrix(shipped, knowledge), estimator, args.seed)
    synthetic = synthetic_library(knowledge, args.synthetic, args.seed, base=shipped)
    table(f"synthetic library (seed {args.seed})", DescriptionMatrix(synthetic, knowledge), estimator, args.seed)


if __name__ == "__main__":
    main()
