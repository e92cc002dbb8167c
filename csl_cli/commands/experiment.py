"""``csl experiment paper``: reproduce the paper's results in the simulator, side by side
with baselines, noise sweeps and the optimum, into ``results.md`` and its plots."""

from __future__ import annotations

import argparse
import os
import shlex
import sys
from dataclasses import dataclass
from importlib import import_module
from pathlib import Path

from csl_cli.args import output_folder
from experiments.config import FULL_SEEDS, QUICK_SEEDS, ExperimentConfig, parse_seeds
from zenoh_rpc.argtypes import positive_int

DEFAULT_OUT = Path("csl-experiment")
"""Where ``csl experiment paper`` writes unless told: a folder of its own (in
``.gitignore``), never ``docs/``, so a run from a checkout cannot overwrite the
committed page; ``--out docs`` regenerates that page on purpose."""

SEEDS_FORMS = ": a count N (seeds 0 to N-1), a range A-B or a list A,B,C (other seeds lay other floors)"


def seeds_argument(text: str) -> str:
    """argparse type: a ``--seeds`` value that names seeds (kept as written, for the
    command line a page quotes)."""
    try:
        parse_seeds(text)
    except ValueError as exc:
        raise argparse.ArgumentTypeError(str(exc)) from None
    return text.strip()


@dataclass(frozen=True)
class Situation:
    """A ``csl experiment`` study of one changing-world situation (beyond CSL's limits):
    its module ``experiments.study_<name>`` declares its ``STUDY``; these are its
    command line's words."""

    name: str
    help: str
    description: str
    quick: str
    seeds: str


SITUATIONS = (
    Situation("disturbance", "objects moved, swapped or taken away while sensed: the camera check on and off",
              "Sweep the simulator's --disturb rate over floors of unseen test objects with the executive's "
              "camera check before sensing and grasping on and off (the camera's appearance off, so every "
              "object is sensed and can be disturbed); print success, robot minutes per "
              "object, objects reported gone and descriptions saved from disturbed attempts as a "
              "Markdown section (BENCHMARKS.md, 'Disturbances').",
              "two rates and 2 seeds", "floors per rate and setting (default 6, or 2 with --quick)"),
    Situation("battery", "low battery: the guard and the dock-detour pricing on and off, over start levels "
              "and drain rates",
              "Sweep the battery's start level, then the drain rate (a multiplier on the documented "
              "rates, from half a charge), over floors of unseen test objects with a charging dock, "
              "with the low-battery guard off, on, and on with the dock detour priced into the learner's "
              "moves; print success, robot minutes per object, dock trips, objects resumed after a "
              "charge, flat-battery failures and descriptions saved from attempts the battery cut short "
              "as a Markdown section (BENCHMARKS.md, 'Battery').",
              "two levels, drains x1 and x8, 1 seed",
              "floors per sweep point and setting (default 4, or 1 with --quick)"),
    Situation("obstacles", "people and carts crossing the floor: the safety stop and blocked-move branch on and off",
              "Sweep the number and speed of the simulator's movers (--movers N:SPEED) over floors of unseen "
              "test objects with the driver's safety stop and the executive's blocked-move branch on and "
              "off; print success, robot minutes per object, contacts, blocked moves and objects given up "
              "as a Markdown section (BENCHMARKS.md, 'Moving obstacles').",
              "0 and 3 movers, 2 seeds",
              "floors per sweep point and setting (default 6, or 2 with --quick)"),
    Situation("clutter", "objects close together: the sonar beam check on and off, over the neighbour's gap",
              "Pair every unseen test object with a neighbour GAP inches away (edge to edge; 'apart': no "
              "clutter) and run the executive with its beam check (BeamClear?) on and off; print success, "
              "robot minutes per object and the sonar readings a neighbour contaminated as a Markdown "
              "section (BENCHMARKS.md, 'Clutter').",
              "apart and 2 in, 1 seed", "floors per gap and setting (default 4, or 1 with --quick)"),
)


def _add_situation(studies: argparse._SubParsersAction, study: Situation) -> None:
    parser = studies.add_parser(study.name, help=study.help, description=study.description)
    parser.add_argument("--quick", action="store_true", help=study.quick)
    parser.add_argument("--seeds", type=seeds_argument, default=None, metavar="SEEDS", help=study.seeds + SEEDS_FORMS)
    parser.add_argument("--jobs", type=positive_int, default=os.cpu_count() or 1, metavar="J",
                        help="parallel worker processes (default: the CPU count)")
    parser.set_defaults(handler=run_situation)


def register(sub: argparse._SubParsersAction) -> None:
    experiment = sub.add_parser(
        "experiment", help="measure the method against the paper's figures, baselines and the optimum",
        description="Run experiments in the simulator and write their results as a page of tables and plots.")
    studies = experiment.add_subparsers(dest="experiment", metavar="EXPERIMENT", required=True)
    paper = studies.add_parser(
        "paper", help="the paper's experiment and every baseline, in one run",
        description=("Train on the Table 3 objects, execute on training and unseen test objects at random poses, "
                     "compare every criterion (cost-blind ID3 among them, and ablations --criterion does not offer), "
                     "the control strategies on and off, "
                     "exhaustive training, cost and noise sweeps, a learning curve and the distance to the "
                     "optimum. Writes DIR/results.md, PNG plots and the raw per-episode CSV under DIR/results/."))
    paper.add_argument("--quick", action="store_true",
                       help=f"a small run: {QUICK_SEEDS} seeds, fewer sweep points and shorter chains (its wall and CPU time "
                            "are in the header of the page it writes)")
    paper.add_argument("--seeds", type=seeds_argument, default=None, metavar="SEEDS",
                       help=f"the floors every condition runs on (default the first {FULL_SEEDS}, or {QUICK_SEEDS} "
                            f"with --quick){SEEDS_FORMS}")
    paper.add_argument("--jobs", type=positive_int, default=os.cpu_count() or 1, metavar="J",
                       help="parallel worker processes (default: the CPU count)")
    paper.add_argument("--out", type=Path, default=DEFAULT_OUT, metavar="DIR",
                       help=f"folder for results.md (plots and CSV go to its results/ folder; default ./{DEFAULT_OUT}; "
                            "--out docs regenerates a checkout's docs/results.md)")
    paper.set_defaults(handler=run_experiment_paper)
    for study in SITUATIONS:
        _add_situation(studies, study)
    onboard = studies.add_parser(
        "onboard", help="without a ceiling camera: whole onboard episodes in the simulated homes against the lab",
        description=("Run whole episodes with --perception onboard in the simulated homes (apartment, apartment-2) "
                     "under the clean, paper and harsh noise presets, each beside the ceiling-camera lab on the "
                     "same preset and seed; measure objects found, handled right, false records, robot time per "
                     "object against the lab's, the map's surface IoU and the localisation error against the "
                     "simulator's truth; check the goals under paper (at least 95% of the objects found and 95% "
                     "of those handled right, at most 1.5x the lab's robot time per object, surface IoU at "
                     "least 0.9). Writes DIR/results-onboard.md and one episode's map under DIR/results/."))
    onboard.add_argument("--quick", action="store_true", help="a small run: the apartment under paper, 1 seed")
    onboard.add_argument("--seeds", type=seeds_argument, default=None, metavar="SEEDS",
                         help="the seeds every home, preset and the lab run on (default 2, or 1 with --quick): "
                              "a count N (seeds 0 to N-1), a range A-B or a list A,B,C (other seeds draw other "
                              "noise; each home stays as its world file lays it out)")
    onboard.add_argument("--jobs", type=positive_int, default=os.cpu_count() or 1, metavar="J",
                         help="parallel worker processes (default: the CPU count)")
    onboard.add_argument("--out", type=Path, default=DEFAULT_OUT, metavar="DIR",
                         help=f"folder for results-onboard.md (the map goes to its results/ folder; default "
                              f"./{DEFAULT_OUT}; --out docs regenerates a checkout's docs/results-onboard.md)")
    onboard.set_defaults(handler=run_experiment_onboard)


def _command_line(args: argparse.Namespace) -> str:
    """The command that regenerates a page, as its header quotes it."""
    return f"csl experiment {args.experiment}" + "".join(
        [" --quick" if args.quick else "", f" --seeds {args.seeds}" if args.seeds else "",
         f" --jobs {args.jobs}", f" --out {shlex.quote(str(args.out))}"])


def run_experiment_paper(args: argparse.Namespace) -> int:
    output_folder(args.out, "--out")
    seeds = parse_seeds(args.seeds) if args.seeds else tuple(range(QUICK_SEEDS if args.quick else FULL_SEEDS))
    command = _command_line(args)
    config = ExperimentConfig(args.quick, seeds, args.jobs, args.out, command)
    from rich.console import Console

    from experiments.paper import run_paper  # the simulator and plots: only when the run starts

    console = Console(stderr=True, soft_wrap=True)
    run = run_paper(config, console)
    print(f"{run.episodes} episodes, {run.object_rows} object rows in {run.wall_s:.0f} s ({run.cpu_s:.0f} CPU s); "
          f"wrote {run.page}, {run.csv} and the plots beside it")
    sys.stdout.flush()
    return 0


def run_experiment_onboard(args: argparse.Namespace) -> int:
    """The onboard study and its page; each goal one line, met or not."""
    output_folder(args.out, "--out")
    from rich.console import Console

    from experiments.onboard_page import run_onboard  # the simulator: only when the run starts
    from experiments.study import RESULTS_DIR
    from experiments.study_onboard import STUDY

    seeds = parse_seeds(args.seeds) if args.seeds else tuple(range(STUDY.floors[0 if args.quick else 1]))
    run = run_onboard(ExperimentConfig(args.quick, seeds, args.jobs, args.out, _command_line(args)),
                      Console(stderr=True, soft_wrap=True))
    for goal in run.goals:
        print(goal.line)
    drawn = "".join(f", {args.out / RESULTS_DIR / name}" for name in run.study.plots)
    print(f"{run.episodes} episodes in {run.wall_s:.0f} s ({run.cpu_s:.0f} CPU s); wrote {run.page}{drawn}")
    sys.stdout.flush()
    return 0


def run_situation(args: argparse.Namespace) -> int:
    """One situation study: its module's ``STUDY`` run and printed as Markdown."""
    module = import_module(f"experiments.study_{args.experiment}")  # the simulator: only when it runs
    from experiments.situation import report

    print(report(module.STUDY, args.quick, args.seeds, args.jobs))
    return 0
