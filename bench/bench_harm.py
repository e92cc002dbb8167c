"""Failure harm swept: what pricing a failed grasp above its seconds does to the learning
curve and to the upside-down tumbler, counted strictly (issue 32 item 4).

Each setting gives the grasps a ``failure_harm_s`` (the profile's per-grasp price of a
failure beyond its time: docs/knowledge-format.md) and runs the incremental study's
chains with it: one learner store per seed, ``--episodes`` fresh floors of the unseen
test objects, the library trained in the simulator as the experiment trains it, noise
``paper``, in the paper's conditions (no appearance) unless ``--ours``. Harm is a
decision price only: the robot minutes reported are the seconds the robot spent.

Strict (experiments.episodes.EpisodeRow.misclassified_strict): any grasp that failed,
at a leaf or tried as a feature, or a knock-over, or the object not handled. The
tumbler columns count, as the incremental study does, encounters of the upside-down
tumbler misclassified (strictly) with one more encounter after it in the same chain:
how many of those next encounters were right, and how many knocked it over.

    python bench/bench_harm.py [--harms 0,120,300,1000] [--criteria cs-id3-failure,cs-id3]
                               [--seeds 0-9] [--episodes 6] [--grasps side-effects] [--ours] [--jobs 2]
"""

from __future__ import annotations

import argparse
import sys
from collections.abc import Sequence
from concurrent.futures import ProcessPoolExecutor
from dataclasses import replace
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT))

from experiments.ablations import MEASURED  # noqa: E402
from experiments.conditions import EXECUTION_NOISE, OURS, PAPERS, Control  # noqa: E402
from experiments.config import parse_seeds  # noqa: E402
from experiments.episodes import EpisodeRow, EpisodeSpec, run_job  # noqa: E402
from experiments.study_incremental import TUMBLER, after_wrong, curve, own_grasps, strict  # noqa: E402
from experiments.study_training import run_training  # noqa: E402
from experiments.table import mean, paired  # noqa: E402
from experiments.worker import install_worker  # noqa: E402
from learner.knowledge import GraspingProcedure  # noqa: E402
from robot_profile import RobotProfile, load_profile  # noqa: E402

Chain = Sequence[EpisodeRow]


def with_harm(profile: RobotProfile, harm_s: float, grasps: str) -> RobotProfile:
    """``profile`` with ``harm_s`` of failure harm on the grasps ``grasps`` names: ``all``
    the grasps the finger sensor can confirm (the ones ever tried as features), or
    ``side-effects`` those the profile gives a side-effect penalty."""
    def harmed(g: GraspingProcedure) -> bool:
        return g.verifiable if grasps == "all" else g.side_effect_penalty_s > 0
    return replace(profile, grasping=tuple(replace(g, failure_harm_s=harm_s) if harmed(g) else g
                                           for g in profile.grasping),
                   source=f"{profile.source} (failure harm {harm_s:g} s on {grasps})")


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--harms", default="0,120,300,1000", help="failure harms to sweep, s (default 0,120,300,1000)")
    ap.add_argument("--criteria", default="cs-id3-failure,cs-id3", help="criteria (default cs-id3-failure,cs-id3)")
    ap.add_argument("--seeds", default="0-9", help="chain seeds: N, a range a-b or a list (default 0-9)")
    ap.add_argument("--episodes", type=int, default=6, help="episodes per chain (default 6)")
    ap.add_argument("--grasps", choices=("side-effects", "all"), default="side-effects",
                    help="which grasps carry the harm: those with a side-effect penalty (default), or all the "
                         "verifiable ones")
    ap.add_argument("--ours", action="store_true", help="with our defaults (the camera's appearance) instead of "
                                                         "the paper's conditions")
    ap.add_argument("--noise", default=EXECUTION_NOISE, help=f"noise preset (default {EXECUTION_NOISE})")
    ap.add_argument("--jobs", type=int, default=2, help="worker processes (default 2)")
    args = ap.parse_args()
    try:
        harms = [float(h) for h in args.harms.split(",")]
        seeds = parse_seeds(args.seeds)
    except ValueError as exc:
        ap.error(str(exc))
    criteria = args.criteria.split(",")
    unknown = [c for c in criteria if c not in MEASURED]
    if unknown or any(h < 0 for h in harms) or args.episodes < 2:
        ap.error(f"criteria from {', '.join(MEASURED)}; harms >= 0; at least 2 episodes")
    conditions = OURS if args.ours else PAPERS
    base = load_profile()
    grasps = own_grasps(TUMBLER)
    print(f"{len(seeds)} chains (seeds {args.seeds}) x {args.episodes} episodes, noise {args.noise}, "
          f"{conditions.name}, harm on {args.grasps}; paired columns: against harm {harms[0]:g}, by seed")
    print("| criterion | harm (s) | robot min / object | paired | strict misclassified by episode | paired (all "
          "episodes) | handled | tumbler strict, right next time | knocked over next time "
          "| learned as itself, right next time |")
    print("|---|---|---|---|---|---|---|---|---|---|")
    for criterion in criteria:
        first: list[Chain] | None = None
        for harm in harms:
            chains = run_chains(with_harm(base, harm, args.grasps), criterion, conditions.control(), seeds, args)
            rows = [r for c in chains for r in c]
            read = curve(chains, args.episodes, grasps)
            nxt = [after for _, after in after_wrong(chains, wrong=strict)]
            learned = read.strict_story.learned
            shares = " ".join(f"{s:.2f}" for s in read.strict_errors)
            first = first or chains
            minutes = paired([mean(r.robot_s / 60 for r in c) for c in chains],
                             [mean(r.robot_s / 60 for r in c) for c in first]) if chains is not first else "-"
            wrong = paired([mean(float(strict(r)) for r in c) for c in chains],
                           [mean(float(strict(r)) for r in c) for c in first]) if chains is not first else "-"
            print(f"| {criterion} | {harm:g} | {mean(r.robot_s for r in rows) / 60:.2f} | {minutes} | {shares} "
                  f"| {wrong} | {sum(r.success for r in rows)}/{len(rows)} | {sum(not strict(r) for r in nxt)} of "
                  f"{len(nxt)} | {sum(r.knocked_over for r in nxt)} of {len(nxt)} | {learned.right} of {learned.of} |",
                  flush=True)


def run_chains(profile: RobotProfile, criterion: str, control: Control, seeds: Sequence[int],
               args: argparse.Namespace) -> list[Chain]:
    """One chain per seed with ``profile`` (its library trained with it), in the seeds' order."""
    library = run_training(profile).descriptions
    specs = [EpisodeSpec("harm", profile.source, seed, criterion=criterion, noise=args.noise, control=control,
                         episodes=args.episodes) for seed in seeds]
    with ProcessPoolExecutor(args.jobs, initializer=install_worker, initargs=({"trained": library}, profile)) as pool:
        return list(pool.map(run_job, specs))

if __name__ == "__main__":
    main()
