"""Distance to the optimum: every criterion's expected cost as a ratio to the exact optimum.

Noise-free, uniform prior over the library's descriptions, the learner's default move
model (2 s/in in the shipped profile), every object charged until its own grasp is
executed, failed grasps included (docs/optimum.md). The shipped library and a synthetic
one perturbed from it, from several start poses; each cell is ``policy_cost /
optimal_cost`` and, in brackets, the share of descriptions whose first executed grasp
is their own (and the share left behind by a wrong No-Grab, if any). Under each table,
the CPU time of every decision of the timed criteria, each description's session
deciding alone: the first decision of a session (where a search its later decisions
share is paid) and the later ones, max and median over every start.

With ``--noisy SEEDS`` it also runs the experiment's execution episodes (the unseen test
objects, the ``paper`` noise preset, strategies on, the library trained in the
simulator as ``csl experiment paper`` trains it) for cs-id3 against the failure-priced
rules, seeds 0..SEEDS-1, and prints mean cost per object and success per criterion.

    python bench/bench_optimum.py [--synthetic 12] [--seed 0] [--noisy 0] [--jobs 1] [--only-noisy]
                                  [--study-starts] [--criteria NAMES] [--timed NAMES] [--libraries NAMES]
"""

from __future__ import annotations

import argparse
import statistics
import sys
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT))

from executive.defaults import EXAMPLE_LIBRARY, KNOWLEDGE  # noqa: E402
from robot_profile import load_knowledge  # noqa: E402
from experiments.ablations import MEASURED, criterion  # noqa: E402
from learner.choosing.matrix import DescriptionMatrix  # noqa: E402
from learner.costs import ModelMoveCost  # noqa: E402
from learner.library.format import read_library_json  # noqa: E402
from learner.library.synthetic import synthetic_library  # noqa: E402
from learner.optimum import decision_times, optimal_cost, policy_walk  # noqa: E402
from learner.position import Position  # noqa: E402

NOISY_CRITERIA = ("cs-id3", "cs-id3-failure", "cs-id3-failure-rollout", "cs-id3-failure-search", "cs-id3-failure-exact",
                  "cs-id3-failure-search-every-row")
STARTS = [Position(d, o) for d, o in ((6, 0), (16, 90), (24, 180), (40, 270), (40, 0), (16, 180))]
STUDY_STARTS = [Position(d, o) for d, o in ((24, 0), (60, 90), (100, 180))]  # ExperimentConfig.start_poses
TIMED = ("cs-id3-failure", "cs-id3-failure-rollout", "cs-id3-failure-exact")
"""Whose every decision the bench times by default: the default, the rollout and the
exact search (the walk searches take about a second a decision: ``--timed`` adds them)."""


def table(title: str, matrix: DescriptionMatrix, estimator: ModelMoveCost, seed: int, starts: list[Position],
          names: list[str], timed: list[str]) -> None:
    print(f"\n{title}: {len(matrix.descriptions)} descriptions, {len(matrix.tests)} tests")
    print("| start | optimum s | search s | " + " | ".join(names) + " |")
    print("|---" * (3 + len(names)) + "|")
    first: dict[str, list[float]] = {name: [] for name in timed}
    later: dict[str, list[float]] = {name: [] for name in timed}
    for start in starts:
        began = time.process_time()
        best = optimal_cost(matrix, estimator, start)
        took = time.process_time() - began
        cells = []
        for name in names:
            walk = policy_walk(matrix, criterion(name), estimator, start, seed=seed)
            ratio = walk.expected_cost / best if best > 0 else float("nan")
            left = f", {walk.missed:.0%} left" if walk.missed else ""
            cells.append(f"{ratio:.3f} ({walk.right:.0%}{left})")
        print(f"| {start} | {best:.1f} | {took:.2f} | " + " | ".join(cells) + " |")
        for name in timed:
            times = decision_times(matrix, criterion(name), estimator, start, seed=seed)
            first[name] += times.first
            later[name] += times.later
    if timed:
        print("decisions, CPU ms (each description's session deciding alone, every start; max / median): "
              + "; ".join(f"{name} first {_ms(first[name])}, later {_ms(later[name])}" for name in timed))


def _ms(seconds: list[float]) -> str:
    return f"{max(seconds) * 1000:.0f} / {statistics.median(seconds) * 1000:.1f}" if seconds else "none"


def noisy(seeds: int, jobs: int) -> None:
    """cs-id3 against the failure-priced rules in the experiment's noisy execution episodes."""
    from experiments.conditions import EXECUTION_NOISE
    from experiments.episodes import EpisodeSpec
    from experiments.worker import install_worker
    from experiments.study import perform
    from experiments.runner import run_all
    from experiments.study_training import run_training
    from robot_profile import load_profile

    profile = load_profile()
    trained = run_training(profile)
    specs = [EpisodeSpec("noisy", name, seed, criterion=name, noise=EXECUTION_NOISE)
             for name in NOISY_CRITERIA for seed in range(seeds)]
    results = run_all(specs, perform, workers=jobs, group=lambda spec: spec.variant, initializer=install_worker,
                      initargs=({"trained": trained.descriptions}, profile))
    print(f"\nnoisy execution ({EXECUTION_NOISE} preset, test objects, {seeds} seeds, "
          f"{len(trained.descriptions)} trained descriptions)")
    print("| criterion | objects | success | mean cost per object, min | against cs-id3 per seed, min "
          "(mean ± sd) | seeds cheaper / dearer | seeds more / fewer successes |")
    print("|---|---|---|---|---|---|---|")

    def per_seed(name: str) -> list[tuple[float, int]]:
        """(mean minutes per object, successes) of each seed, in seed order: the same floors
        for every criterion, so seeds pair up."""
        return [(statistics.fmean(r.robot_s for r in results[spec]) / 60, sum(r.success for r in results[spec]))
                for spec in specs if spec.criterion == name]

    base = per_seed(NOISY_CRITERIA[0])
    for name in NOISY_CRITERIA:
        rows = [row for spec in specs if spec.criterion == name for row in results[spec]]
        mine = per_seed(name)
        diff = [m - b for (m, _), (b, _) in zip(mine, base)]
        spread = statistics.stdev(diff) if len(diff) > 1 else 0.0
        cheaper, dearer = sum(d < -1e-9 for d in diff), sum(d > 1e-9 for d in diff)
        more = sum(m > b for (_, m), (_, b) in zip(mine, base))
        fewer = sum(m < b for (_, m), (_, b) in zip(mine, base))
        print(f"| {name} | {len(rows)} | {sum(r.success for r in rows) / len(rows):.1%} | "
              f"{statistics.fmean(r.robot_s for r in rows) / 60:.2f} | {statistics.fmean(diff):+.2f} ± {spread:.2f} | "
              f"{cheaper} / {dearer} | {more} / {fewer} |")


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--synthetic", type=int, default=12, help="descriptions in the synthetic library (default 12)")
    ap.add_argument("--seed", type=int, default=0, help="seed of the synthetic library and of random ties")
    ap.add_argument("--noisy", type=int, default=0, metavar="SEEDS",
                    help="also run noisy execution episodes over this many seeds (default 0: none)")
    ap.add_argument("--jobs", type=int, default=1, help="worker processes for the noisy episodes (default 1)")
    ap.add_argument("--only-noisy", action="store_true", help="skip the optimum tables")
    ap.add_argument("--study-starts", action="store_true",
                    help="start from the study's poses (csl experiment paper: (24,0), (60,90), (100,180))")
    ap.add_argument("--criteria", default=",".join(MEASURED), metavar="NAMES",
                    help="the criteria walked, comma-separated (default: every measured one)")
    ap.add_argument("--timed", default=",".join(TIMED), metavar="NAMES",
                    help=f"the criteria whose every decision is timed (default {','.join(TIMED)}; '' for none)")
    ap.add_argument("--libraries", default="shipped,synthetic", metavar="NAMES",
                    help="shipped, synthetic or both (default both)")
    args = ap.parse_args()
    if args.noisy < 0 or args.jobs < 1:
        ap.error("--noisy must be >= 0 and --jobs >= 1")
    names = [n for n in args.criteria.split(",") if n]
    timed = [n for n in args.timed.split(",") if n]
    unknown = sorted(set(names + timed) - set(MEASURED))
    if unknown:
        ap.error(f"unknown criterion {', '.join(unknown)} (choose from: {', '.join(MEASURED)})")
    libraries = [n for n in args.libraries.split(",") if n]
    if not libraries or set(libraries) - {"shipped", "synthetic"}:
        ap.error(f"--libraries takes shipped and/or synthetic, got {args.libraries!r}")
    if args.noisy:
        noisy(args.noisy, args.jobs)
    if args.only_noisy:
        return
    knowledge = load_knowledge(KNOWLEDGE)
    shipped = read_library_json(EXAMPLE_LIBRARY)
    estimator = ModelMoveCost(knowledge.move)
    starts = STUDY_STARTS if args.study_starts else STARTS
    if "shipped" in libraries:
        table("shipped library", DescriptionMatrix(shipped, knowledge), estimator, args.seed, starts, names, timed)
    if "synthetic" in libraries:
        synthetic = synthetic_library(knowledge, args.synthetic, args.seed, base=shipped)
        table(f"synthetic library (seed {args.seed})", DescriptionMatrix(synthetic, knowledge), estimator, args.seed,
              starts, names, timed)


if __name__ == "__main__":
    main()
