"""Distance to the optimum: every criterion's expected cost as a ratio to the exact optimum.

Noise-free, uniform prior over the library's descriptions, the learner's default move
model (2 s/in in the shipped profile), every object charged until its own grasp is
executed, failed grasps included (docs/optimum.md). The shipped library and a synthetic
one perturbed from it, from several start poses; each cell is ``policy_cost /
optimal_cost`` and, in brackets, the share of descriptions whose first executed grasp
is their own (and the share left behind by a wrong No-Grab, if any). Under each table,
the CPU time of every decision of the timed criteria, each description's session
deciding alone: the first decision of a session (where a search its later decisions
share is paid), as the first session over the library (the exact search's nodes
forgotten) and after the others (the nodes the sessions over one library share), and
the later ones, max and median over every start.

With ``--noisy SEEDS`` (a count, or a range A-B) it also runs the experiment's execution
episodes (the unseen test objects, strategies on, the library trained in the simulator
as ``csl experiment paper`` trains it) for ``--noisy-criteria`` (default cs-id3 and the
failure-priced rules) on the same floors, under each ``--noise`` (default ``paper``) with
the camera's appearance ``--appearance`` on, off or both, and prints per criterion the
robot minutes per object (sensing, moving, grasping), success, grasps tried as features,
and the paired difference per seed from the first criterion (mean ± standard error).
With ``--timed-episodes`` it also times, in CPU ms, every ranking a recognition session
of those episodes decides by (a session's first, where a search its later ones share is
paid, and its later ones; max / p90 / median per criterion and camera condition): what a
criterion costs the robot per decision on a real map, where every move is priced by the
planner. The episodes then run in this process (``--jobs 1``).

    python bench/bench_optimum.py [--synthetic 12] [--seed 0] [--noisy SEEDS] [--noise NAMES]
                                  [--appearance on|off|both] [--noisy-criteria NAMES] [--jobs 1] [--only-noisy]
                                  [--study-starts] [--criteria NAMES] [--timed NAMES] [--libraries NAMES]
                                  [--timed-episodes]
"""

from __future__ import annotations

import argparse
import math
import statistics
import sys
import time
from collections import defaultdict
from collections.abc import Callable
from pathlib import Path
from types import TracebackType
from typing import TYPE_CHECKING, TypeVar

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT))

from executive.defaults import EXAMPLE_LIBRARY, KNOWLEDGE  # noqa: E402
from robot_profile import load_knowledge  # noqa: E402
from experiments.ablations import MEASURED, criterion  # noqa: E402
from learner.choosing.matrix import DescriptionMatrix  # noqa: E402
from learner.costs import ModelMoveCost  # noqa: E402
from learner.library.format import read_library_json  # noqa: E402
from learner.library.synthetic import synthetic_library  # noqa: E402
from learner import runtime  # noqa: E402
from learner.optimum import decision_times, optimal_cost, policy_walk  # noqa: E402
from learner.position import Position  # noqa: E402
from experiments.conditions import noise_names  # noqa: E402

if TYPE_CHECKING:
    from experiments.episodes import EpisodeSpec, Results
    from learner.choosing.node import Context

R = TypeVar("R")
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
    alone: dict[str, list[float]] = {name: [] for name in timed}
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
            times = decision_times(matrix, criterion(name), estimator, start, seed=seed, cold=True)
            alone[name] += times.first
            later[name] += times.later
            first[name] += decision_times(matrix, criterion(name), estimator, start, seed=seed).first
    if timed:
        print("decisions, CPU ms (each description's session deciding alone, every start; max / median): "
              + "; ".join(f"{name} first {_ms(alone[name])} as the library's first session, {_ms(first[name])} "
                          f"after others, later {_ms(later[name])}" for name in timed))


def _ms(seconds: list[float]) -> str:
    return f"{max(seconds) * 1000:.0f} / {statistics.median(seconds) * 1000:.1f}" if seconds else "none"


class RankingClock:
    """CPU seconds of every ranking a recognition session decides by in the episodes run
    in this process, per episode label: each session's first ranking and its later ones.

    While on, ``learner.runtime``'s ``rank`` (the session's call of
    ``learner.choosing.selection.rank``) is wrapped: what the rollouts and the search
    rank inside a decision is that decision's time, and the training stage, which ranks
    through its own import, is not timed.
    """

    def __init__(self) -> None:
        self.first: dict[str, list[float]] = defaultdict(list)
        self.later: dict[str, list[float]] = defaultdict(list)
        self.label = ""
        self._sessions: dict[int, object] = {}  # id of a session's scratch -> the scratch (kept: ids stay unique)
        self._rank = runtime.rank

    def __enter__(self) -> RankingClock:
        runtime.rank = self._timed  # type: ignore[assignment]
        return self

    def __exit__(self, kind: type[BaseException] | None, error: BaseException | None,
                 trace: TracebackType | None) -> None:
        runtime.rank = self._rank

    def run(self, label: str, episode: Callable[[], R]) -> R:
        """Run ``episode`` with its rankings counted under ``label``."""
        self.label, self._sessions = label, {}
        return episode()

    def _timed(self, node: object, current: Position, ctx: Context, *args: object) -> object:
        began = time.process_time()
        try:
            return self._rank(node, current, ctx, *args)  # type: ignore[arg-type]
        finally:
            took = time.process_time() - began
            seen = id(ctx.scratch) in self._sessions
            self._sessions[id(ctx.scratch)] = ctx.scratch
            (self.later if seen else self.first)[self.label].append(took)


def noisy(seeds: list[int], jobs: int, names: list[str], noises: list[str], appearances: list[bool],
          timed: bool = False) -> None:
    """``names`` in the experiment's execution episodes (the unseen test objects, the
    strategies on, the library trained as ``csl experiment paper`` trains it), on the same
    floors for every criterion, per noise and camera condition: where each spends its
    robot time, and its paired difference from the first of ``names``; ``timed``: and the
    CPU time of their decisions (:class:`RankingClock`, in this process)."""
    from experiments.conditions import Control
    from experiments.episodes import EpisodeSpec
    from experiments.worker import install_worker
    from experiments.study import perform
    from experiments.runner import run_all
    from experiments.study_training import run_training
    from robot_profile import load_profile

    profile = load_profile()
    trained = run_training(profile)
    specs = [EpisodeSpec("noisy", f"{name}, {noise}, appearance {'on' if seen else 'off'}", seed, criterion=name,
                         noise=noise, control=Control(appearance=seen))
             for noise in noises for seen in appearances for name in names for seed in seeds]
    args = {"group": lambda spec: spec.criterion, "initializer": install_worker,
            "initargs": ({"trained": trained.descriptions}, profile)}
    if timed:
        with RankingClock() as clock:
            results = run_all(specs, lambda spec: clock.run(spec.variant, lambda: perform(spec)), workers=1,
                              **args)
    else:
        results = run_all(specs, perform, workers=jobs, **args)
    for noise in noises:
        for seen in appearances:
            mine = [spec for spec in specs if spec.noise == noise and spec.control.appearance == seen]
            _noisy_table(noise, seen, seeds, names, mine, results, len(trained.descriptions))
    if timed:
        print(f"\ndecisions in the episodes above, CPU ms (every ranking a session decides by; max / p90 / median "
              f"(count); seeds {seeds[0]}-{seeds[-1]}, {len(seeds)} floors)")
        print("| criterion, noise, camera | a session's first decision | later decisions |")
        print("|---|---|---|")
        for label in dict.fromkeys(spec.variant for spec in specs):
            print(f"| {label} | {_spread(clock.first[label])} | {_spread(clock.later[label])} |")


def _spread(seconds: list[float]) -> str:
    """Max / p90 / median in ms (the p90 by nearest rank), and how many."""
    if not seconds:
        return "none"
    ordered = sorted(seconds)
    p90 = ordered[math.ceil(0.9 * len(ordered)) - 1]
    return (f"{ordered[-1] * 1000:.0f} / {p90 * 1000:.0f} / {statistics.median(ordered) * 1000:.1f} "
            f"({len(ordered)})")


def _noisy_table(noise: str, seen: bool, seeds: list[int], names: list[str], specs: list[EpisodeSpec],
                 results: Results, trained: int) -> None:
    print(f"\nnoisy execution ({noise} noise, camera appearance {'on' if seen else 'off'}, test objects, "
          f"{len(seeds)} seeds {seeds[0]}-{seeds[-1]}, {trained} trained descriptions; minutes per object; "
          f"against {names[0]}: the paired difference per seed, mean ± standard error)")
    print("| criterion | objects | success | robot | sensing | moving | grasping | grasps as features (failed) | "
          f"against {names[0]} | seeds cheaper / dearer |")
    print("|---|---|---|---|---|---|---|---|---|---|")

    def per_seed(name: str) -> list[float]:
        """Mean robot minutes per object of each seed, in seed order: the same floors for
        every criterion, so seeds pair up."""
        return [statistics.fmean(r.robot_s for r in results[spec]) / 60 for spec in specs if spec.criterion == name]

    base = per_seed(names[0])
    for name in names:
        rows = [row for spec in specs if spec.criterion == name for row in results[spec]]
        diff = [m - b for m, b in zip(per_seed(name), base)]
        error = statistics.stdev(diff) / len(diff) ** 0.5 if len(diff) > 1 else float("nan")
        cheaper, dearer = sum(d < -1e-9 for d in diff), sum(d > 1e-9 for d in diff)

        def minutes(field: str) -> str:
            return f"{statistics.fmean(getattr(r, field) for r in rows) / 60:.2f}"

        print(f"| {name} | {len(rows)} | {statistics.fmean(r.success for r in rows):.1%} | {minutes('robot_s')} | "
              f"{minutes('sensing_s')} | {minutes('moving_s')} | {minutes('grasping_s')} | "
              f"{statistics.fmean(r.grasps_as_features for r in rows):.2f} "
              f"({statistics.fmean(r.failed_features for r in rows):.2f}) | "
              f"{statistics.fmean(diff):+.2f} ± {error:.2f} | {cheaper} / {dearer} |")


def _seeds(text: str) -> list[int]:
    """``--noisy``: a count N (seeds 0..N-1), or a range A-B, inclusive."""
    first, dash, last = text.partition("-")
    if not first.isdigit() or (dash and not last.isdigit()):
        raise argparse.ArgumentTypeError(f"expected a count N or a range A-B of seeds, got {text!r}")
    seeds = list(range(int(first), int(last) + 1)) if last else list(range(int(first)))
    if last and int(last) < int(first):
        raise argparse.ArgumentTypeError(f"the range {text!r} is empty")
    return seeds


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--synthetic", type=int, default=12, help="descriptions in the synthetic library (default 12)")
    ap.add_argument("--seed", type=int, default=0, help="seed of the synthetic library and of random ties")
    ap.add_argument("--noisy", type=_seeds, default=[], metavar="SEEDS",
                    help="also run noisy execution episodes over this many seeds, or the seeds A-B (default: none)")
    ap.add_argument("--noise", default="paper", metavar="NAMES",
                    help="the noisy episodes' noise, comma-separated (default paper; e.g. clean,paper)")
    ap.add_argument("--appearance", choices=("on", "off", "both"), default="on",
                    help="the noisy episodes' camera appearance: on (our defaults), off (the paper's conditions)")
    ap.add_argument("--noisy-criteria", default=",".join(NOISY_CRITERIA), metavar="NAMES",
                    help="the criteria of the noisy episodes, the first the others are paired against "
                         f"(default {','.join(NOISY_CRITERIA)})")
    ap.add_argument("--jobs", type=int, default=1, help="worker processes for the noisy episodes (default 1)")
    ap.add_argument("--only-noisy", action="store_true", help="skip the optimum tables")
    ap.add_argument("--timed-episodes", action="store_true",
                    help="also time every decision of the noisy episodes (CPU; runs them in this process)")
    ap.add_argument("--study-starts", action="store_true",
                    help="start from the study's poses (csl experiment paper: (24,0), (60,90), (100,180))")
    ap.add_argument("--criteria", default=",".join(MEASURED), metavar="NAMES",
                    help="the criteria walked, comma-separated (default: every measured one)")
    ap.add_argument("--timed", default=",".join(TIMED), metavar="NAMES",
                    help=f"the criteria whose every decision is timed (default {','.join(TIMED)}; '' for none)")
    ap.add_argument("--libraries", default="shipped,synthetic", metavar="NAMES",
                    help="shipped, synthetic or both (default both)")
    args = ap.parse_args()
    if args.jobs < 1:
        ap.error("--jobs must be >= 1")
    if args.timed_episodes and (args.jobs != 1 or not args.noisy):
        ap.error("--timed-episodes times the --noisy episodes in this process: give --noisy SEEDS and --jobs 1")
    names = [n for n in args.criteria.split(",") if n]
    timed = [n for n in args.timed.split(",") if n]
    noisy_names = [n for n in args.noisy_criteria.split(",") if n]
    unknown = sorted(set(names + timed + noisy_names) - set(MEASURED))
    if unknown:
        ap.error(f"unknown criterion {', '.join(unknown)} (choose from: {', '.join(MEASURED)})")
    libraries = [n for n in args.libraries.split(",") if n]
    if not libraries or set(libraries) - {"shipped", "synthetic"}:
        ap.error(f"--libraries takes shipped and/or synthetic, got {args.libraries!r}")
    noises = [n for n in args.noise.split(",") if n]
    if not noises or set(noises) - set(noise_names()):
        ap.error(f"--noise takes names from {', '.join(noise_names())}, got {args.noise!r}")
    if args.noisy:
        if not noisy_names:
            ap.error("--noisy-criteria names no criterion")
        appearances = {"on": [True], "off": [False], "both": [True, False]}[args.appearance]
        noisy(args.noisy, args.jobs, noisy_names, noises, appearances, timed=args.timed_episodes)
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
