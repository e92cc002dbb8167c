"""Incremental learning under a chosen noise preset: the learning curve and the paper's
upside-down cup story, as `csl experiment paper`'s incremental study counts them.

The study itself runs under the `paper` preset only; this runs the same chains (one
learner store per chain, 6 fresh floors of the unseen test objects, the library trained
in the simulator as the experiment trains it) under any preset, so the story can be
read without sonar noise too: with noise off, a miss after a right lesson is the
method's, not a misread value's.

    python bench/bench_incremental.py [--noise off] [--chains 20] [--episodes 6] [--jobs 2]
"""

from __future__ import annotations

import argparse
import sys
from concurrent.futures import ProcessPoolExecutor
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT))

from experiments.episodes import EpisodeSpec, run_job  # noqa: E402
from experiments.worker import install_worker  # noqa: E402
from experiments.study_incremental import TUMBLER, lenient, own_grasps, tumbler_story  # noqa: E402
from experiments.study_training import run_training  # noqa: E402
from robot_profile import load_profile  # noqa: E402


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--noise", default="off", help="noise preset of the chains (default off)")
    ap.add_argument("--chains", type=int, default=20, help="chains, seeds 0..N-1 (default 20)")
    ap.add_argument("--episodes", type=int, default=6, help="episodes per chain (default 6)")
    ap.add_argument("--jobs", type=int, default=2, help="worker processes (default 2)")
    args = ap.parse_args()
    profile = load_profile()
    library = run_training(profile).descriptions
    specs = [EpisodeSpec("incremental", f"chain of {args.episodes}", seed, noise=args.noise, episodes=args.episodes)
             for seed in range(args.chains)]
    with ProcessPoolExecutor(args.jobs, initializer=install_worker, initargs=({"trained": library}, profile)) as pool:
        chains = list(pool.map(run_job, specs))
    print(f"{args.chains} chains of {args.episodes} episodes, noise {args.noise}")
    print("| episode | misclassified | handled | robot min per object | library size |")
    print("|---|---|---|---|---|")
    for episode in range(args.episodes):
        rows = [r for chain in chains for r in chain if r.episode == episode]
        print(f"| {episode + 1} | {sum(lenient(r) for r in rows)}/{len(rows)} "
              f"| {sum(r.success for r in rows)}/{len(rows)} | {sum(r.robot_s for r in rows) / len(rows) / 60:.2f} "
              f"| {sum(r.library_size for r in rows) / len(rows):.1f} |")
    story = tumbler_story(chains, own_grasps(TUMBLER))
    print(f"upside-down tumbler right at the next encounter: learned as itself {story.learned.right} of "
          f"{story.learned.of}, however it ended {story.any_end.right} of {story.any_end.of}")


if __name__ == "__main__":
    main()
