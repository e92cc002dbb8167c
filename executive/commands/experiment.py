"""``csl experiment paper``: reproduce the paper's results in the simulator, side by side
with baselines, noise sweeps and the optimum, into ``results.md`` and its plots."""

from __future__ import annotations

import argparse
import os
import shlex
import sys
from pathlib import Path

from rich.console import Console

from executive.args import output_folder, positive_int
from executive.experiment.config import FULL_SEEDS, QUICK_SEEDS, ExperimentConfig


def register(sub: argparse._SubParsersAction) -> None:
    experiment = sub.add_parser(
        "experiment", help="measure the method against the paper's figures, baselines and the optimum",
        description="Run experiments in the simulator and write their results as a page of tables and plots.")
    studies = experiment.add_subparsers(dest="experiment", metavar="EXPERIMENT", required=True)
    paper = studies.add_parser(
        "paper", help="the paper's experiment and every baseline, in one run",
        description=("Train on the Table 3 objects, execute on training and unseen test objects at random poses, "
                     "compare every criterion (cost-blind ID3 among them), the control strategies on and off, "
                     "exhaustive training, cost and noise sweeps, a learning curve and the distance to the "
                     "optimum. Writes DIR/results.md, PNG plots and the raw per-episode CSV under DIR/results/."))
    paper.add_argument("--quick", action="store_true",
                       help=f"a small run (under two minutes on 2 cores): {QUICK_SEEDS} seeds, fewer sweep points")
    paper.add_argument("--seeds", type=positive_int, default=None, metavar="N",
                       help=f"seeds per condition (default {FULL_SEEDS}, or {QUICK_SEEDS} with --quick)")
    paper.add_argument("--jobs", type=positive_int, default=os.cpu_count() or 1, metavar="J",
                       help="parallel worker processes (default: the CPU count)")
    paper.add_argument("--out", type=Path, default=Path("docs"),
                       help="folder for results.md (plots and CSV go to its results/ folder; default docs/)")
    paper.set_defaults(handler=run_experiment_paper)
    disturbance = studies.add_parser(
        "disturbance", help="objects moved, swapped or taken away while sensed: the camera check on and off",
        description=("Sweep the simulator's --disturb rate over floors of unseen test objects with the executive's "
                     "camera check before sensing and grasping on and off; print success, robot minutes per "
                     "object, objects reported gone and descriptions saved from disturbed attempts as a "
                     "Markdown section (BENCHMARKS.md, 'Disturbances')."))
    disturbance.add_argument("--quick", action="store_true", help="two rates and 2 seeds (about 20 s on 2 cores)")
    disturbance.add_argument("--seeds", type=positive_int, default=None, metavar="N",
                             help="floors per rate and setting (default 6, or 2 with --quick)")
    disturbance.add_argument("--jobs", type=positive_int, default=os.cpu_count() or 1, metavar="J",
                             help="parallel worker processes (default: the CPU count)")
    disturbance.set_defaults(handler=run_experiment_disturbance)


def run_experiment_paper(args: argparse.Namespace) -> int:
    output_folder(args.out, "--out")
    seeds = args.seeds or (QUICK_SEEDS if args.quick else FULL_SEEDS)
    command = "csl experiment paper" + "".join(
        [" --quick" if args.quick else "", f" --seeds {args.seeds}" if args.seeds else "",
         f" --jobs {args.jobs}", f" --out {shlex.quote(str(args.out))}"])
    config = ExperimentConfig(args.quick, seeds, args.jobs, args.out, command)
    from executive.experiment.paper import run_paper  # the simulator and plots: only when the run starts

    console = Console(stderr=True, soft_wrap=True)
    run = run_paper(config, console)
    print(f"{run.episodes} episodes, {run.object_rows} object rows in {run.wall_s:.0f} s ({run.cpu_s:.0f} CPU s); "
          f"wrote {run.page}, {run.csv} and the plots beside it")
    sys.stdout.flush()
    return 0


def run_experiment_disturbance(args: argparse.Namespace) -> int:
    from executive.experiment.study_disturbance import report

    print(report(args.quick, args.seeds, args.jobs))
    return 0
