"""Learner speed: choosing one test, and growing a whole run-time path.

Workload (issue "Core 1"): 1,000 descriptions over 100 feature-positions of the HERO
profile, 6 grasps, ~40% of values missing. The baseline is the same choice computed the
plain way, description by description in Python (tests/learner/reference.py's gain),
run side by side in this process; figures are medians.

    python bench/bench_learner.py [--descriptions 1000] [--repeat 30]
"""

from __future__ import annotations

import argparse
import platform
import random
import statistics
import sys
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT))

from robot_profile import load_knowledge  # noqa: E402
from learner.choosing.criteria import criterion  # noqa: E402
from learner.choosing.leaf import AmbiguousLeaf, GraspLeaf  # noqa: E402
from learner.choosing.matrix import DescriptionMatrix  # noqa: E402
from learner.choosing.node import Context, Node  # noqa: E402
from learner.choosing.partition import partition  # noqa: E402
from learner.choosing.selection import rank  # noqa: E402
from learner.costs import ModelMoveCost  # noqa: E402
from learner.description import ObjectDescription, Observation  # noqa: E402
from learner.position import Position  # noqa: E402
from learner.runtime import RecognitionSession  # noqa: E402
from tests.learner.reference import information_gain  # noqa: E402

KNOWLEDGE = ROOT / "hero_driver" / "profiles" / "hero2000.toml"
GRASPS = ["Front-Pinch", "Front-Wrap", "Top-Pinch", "Top-Vert-Grip", "Top-Hor-Grip", "No-Grab"]


def feature_positions(knowledge) -> list[tuple[str, Position]]:  # noqa: ANN001
    out = []
    for proc in knowledge.sensing:
        distances = [6.0] if proc.range_in[1] <= 6 else [6.0, 16.0, 24.0, 30.0, 40.0]
        for f in proc.features:
            for d in distances:
                for o in (0.0, 90.0, 181.0, 272.0):
                    out.append((f.name, Position(d, o)))
    random.Random(1).shuffle(out)
    return out[:100]


def library(knowledge, n: int, rng: random.Random) -> list[ObjectDescription]:  # noqa: ANN001
    fps = feature_positions(knowledge)
    prototypes = {g: {fp: rng.uniform(0, 60) for fp in fps} for g in GRASPS}
    out = []
    for i in range(n):
        g = GRASPS[i % len(GRASPS)]
        obs = []
        for name, pos in fps:
            if rng.random() < 0.6:
                spec = knowledge.feature(name)
                v = float(rng.random() < 0.5) if spec.binary else round(prototypes[g][(name, pos)] + rng.gauss(0, 4), 1)
                obs.append(Observation(name, pos, v))
        out.append(ObjectDescription(f"o{i}", g, Position(6.0, None), tuple(sorted(obs))))
    return out


def baseline_choice(descriptions, knowledge, start, estimator, crit):  # noqa: ANN001, ANN201
    """The plain way: for each feature-position, look every description's value up."""
    tests = sorted({(o.feature, o.position) for d in descriptions for o in d.observations})
    best = None
    for feature, pos in tests:
        spec = knowledge.feature(feature)
        known, missing = [], []
        for d in descriptions:
            v = d.value_at(feature, pos)
            (missing.append(d.grasp) if v is None else known.append((d.grasp, v)))
        ranges = partition([v for _, v in known], spec.error)
        if len(ranges) < 2:
            continue
        idx = [(c, next(i for i, (lo, hi) in enumerate(ranges) if lo <= v <= hi)) for c, v in known]
        gain = information_gain(idx, missing, len(ranges), not spec.covered_by(ranges))
        proc = knowledge.procedure_for(feature)
        move = estimator.move_cost(start, Position(pos.distance_in, pos.orientation_deg))
        score = crit.score(gain, move + proc.time_s)
        if best is None or score > best[0]:
            best = (score, feature, pos)
    return best


def timed(fn, repeat: int) -> list[float]:  # noqa: ANN001
    out = []
    for _ in range(repeat):
        t = time.perf_counter()
        fn()
        out.append(time.perf_counter() - t)
    return out


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--descriptions", type=int, default=1000)
    ap.add_argument("--repeat", type=int, default=30)
    args = ap.parse_args()
    k = load_knowledge(KNOWLEDGE)
    rng = random.Random(0)
    lib = library(k, args.descriptions, rng)
    est = ModelMoveCost(k.move)
    crit = criterion("cs-id3")
    start = Position(60.0, 0.0)

    build = timed(lambda: DescriptionMatrix(lib, k), 3)
    ctx = Context(DescriptionMatrix(lib, k), crit, est)
    n_tests = sum(not t.is_grasp for t in ctx.matrix.tests)
    choice = timed(lambda: rank(Node.root(len(lib)), start, ctx, {}), args.repeat)
    base = timed(lambda: baseline_choice(lib, k, start, est, crit), 3)
    fast_best = rank(Node.root(len(lib)), start, ctx, {})[0]
    slow_best = baseline_choice(lib, k, start, est, crit)
    agree = (fast_best.test.feature, fast_best.test.position) == (slow_best[1], slow_best[2]) or fast_best.test.is_grasp

    probe = library(k, 60, random.Random(7))

    def grow_paths() -> int:
        steps = 0
        for d in probe[:10]:
            s = RecognitionSession(ctx.matrix, crit, est, start)
            for _ in range(40):
                decision = s.decide()
                if isinstance(decision, (GraspLeaf, AmbiguousLeaf)) or not hasattr(decision, "test"):
                    break
                steps += 1
                if decision.test.is_grasp:
                    s.grasp_as_feature(decision, decision.test.feature == d.grasp, decision.target)
                    if decision.test.feature == d.grasp:
                        break
                    continue
                v = d.value_at(decision.test.feature, decision.test.position)
                values = {decision.test.feature: v if v is not None else decision.ranges[0][0]}
                if not hasattr(s.observe(decision, values, decision.target), "branch"):
                    s.follow_nearest()
        return steps

    steps = grow_paths()
    paths = timed(grow_paths, 3)
    med = statistics.median
    print(f"machine: {platform.machine()} {platform.processor() or ''} python {platform.python_version()}, "
          f"{args.descriptions} descriptions, {n_tests} feature-positions")
    print("| measure | median |")
    print("|---|---|")
    print(f"| build description matrix (once per library change) | {med(build) * 1e3:.1f} ms |")
    print(f"| choose one test (vectorised) | {med(choice) * 1e3:.2f} ms |")
    print(f"| choose one test (baseline, per description) | {med(base) * 1e3:.1f} ms |")
    print(f"| speed-up over baseline | {med(base) / med(choice):.0f}x (same choice: {agree}) |")
    print(f"| grow a full run-time path (10 objects, {steps} tests, library matrix shared) | "
          f"{med(paths) / 10 * 1e3:.1f} ms per object |")


if __name__ == "__main__":
    main()
