"""Running ``csl demo``, ``csl run`` and ``csl bt``: the handlers behind the arguments
that ``executive/commands/run.py`` declares.

Kept apart so that ``csl --help`` (and every other command) does not import the planner,
the behaviour tree and matplotlib just to print a usage line.
"""

from __future__ import annotations

import argparse
import sys
from dataclasses import dataclass
from pathlib import Path
from typing import TYPE_CHECKING

import py_trees
from rich.console import Console

from behaviours.records import ObjectRecord
from behaviours.services import Params
from executive import defaults
from executive.args import criterion_from_args, output_folder
from executive.episode_log import EpisodeLog
from executive.executive import EpisodeResult, Executive
from executive.exit_status import episode_status
from executive.plots import plot_behaviour_tree, plot_map, plot_object_tree
from executive.profile import knowledge_of
from executive.report import CAPTION, HEADERS, Truth, match_truth, rows, summary, table_cells
from executive.tables import print_table
from hero_driver.interface import UNAVAILABLE, CameraImage, Driver, DriverError
from hero_driver.sim.noise import NoiseConfig
from learner.criteria import Criterion
from learner.knowledge import Knowledge
from learner.library import check_library, read_library_json
from learner.service.interface import LearnerService
from learner.service.local import LocalLearner
from robot_profile import RobotProfile, load_profile, profile_stamp
from zenoh_rpc.endpoints import CONNECT_KEY, DRIVER_ENDPOINT, LEARNER_ENDPOINT
from zenoh_rpc.options import endpoint_of, user_config, where

if TYPE_CHECKING:  # zenoh is imported only when a run uses it
    from zenoh_rpc.config import UserConfig


@dataclass(frozen=True)
class Setup:
    """What the arguments choose, read and checked before anything runs: the robot's
    profile (one reading serves the learner, the planner and the simulator), the
    control parameters and the criterion."""

    profile: RobotProfile
    knowledge: Knowledge
    params: Params
    criterion: Criterion


def _setup(args: argparse.Namespace) -> Setup:
    profile = load_profile(args.knowledge)
    return Setup(profile, knowledge_of(profile),
                 Params(max_alternatives=args.alternatives, nearest_after=args.nearest_after,
                        max_steps=args.max_steps, seed=getattr(args, "seed", None) or 0,
                        use_appearance=args.appearance),
                 criterion_from_args(args))


def _only_with(args: argparse.Namespace, mode: str, value: str, options: tuple[str, ...]) -> None:
    """An option for the other mode is a mistake worth a line, not something to ignore."""
    for option in options:
        if getattr(args, option.lstrip("-").replace("-", "_")) is not None:
            raise ValueError(f"{option} goes with {mode} {value}")


def run_demo(args: argparse.Namespace) -> int:
    console = Console(stderr=True, soft_wrap=True)
    setup = _setup(args)
    knowledge = setup.knowledge
    output_folder(args.out, "--out")
    from hero_driver.sim_driver import SimulatedHero

    driver = SimulatedHero("r1", world=args.world, seed=args.seed, profile=setup.profile,
                           noise=_noise(args))  # a bad world fails first
    with console.status("training on the Table 3 objects in the simulator..."):
        from executive.sim_training import train_in_simulator  # the simulator: csl demo only

        trained = train_in_simulator(knowledge, setup.profile, args.seed)
    summary = trained.summary
    console.print(f"trained: {summary.descriptions} descriptions at distances "
                  f"{', '.join(f'{d:g}' for d in summary.distances_in)} in and orientations "
                  f"{', '.join(f'{o:g}' for o in summary.orientations_deg)}°; {summary.robot_hours:.1f} h of robot time")
    result = trained.result
    store = args.out / "library.sqlite"
    store.unlink(missing_ok=True)
    learner = LocalLearner(store, seed_library=list(result.descriptions))
    return _episode(args, driver, learner, setup, console)


def run_run(args: argparse.Namespace) -> int:
    console = Console(stderr=True, soft_wrap=True)
    setup = _setup(args)
    if args.driver == "sim":
        _only_with(args, "--driver", "zenoh", ("--connect",))
    else:
        _only_with(args, "--driver", "sim", ("--world", "--seed", "--noise"))
    if args.learner == "local":
        _only_with(args, "--learner", "zenoh", ("--learner-name", "--learner-connect"))
    else:
        _only_with(args, "--learner", "local", ("--library",))
    if args.driver == "sim" and args.learner == "local":
        _only_with(args, "--driver or --learner", "zenoh", ("--zenoh-config",))
    zenoh_config = user_config(args.zenoh_config) if "zenoh" in (args.driver, args.learner) else None
    output_folder(args.out, "--out")
    learner = _learner(args, zenoh_config)
    try:
        driver = _driver(args, setup.profile, zenoh_config)
    except BaseException:
        learner.close()
        raise
    return _episode(args, driver, learner, setup, console)


def _noise(args: argparse.Namespace) -> NoiseConfig | None:
    """The chosen preset, or None to keep the world file's own noise table."""
    return None if args.noise is None else NoiseConfig.preset(args.noise)


def _learner(args: argparse.Namespace, zenoh_config: UserConfig | None) -> LearnerService:
    if args.learner == "zenoh":
        from learner.service.zenoh_client import ZenohLearner

        connect = endpoint_of("--learner-connect", args.learner_connect, LEARNER_ENDPOINT, CONNECT_KEY, zenoh_config)
        return ZenohLearner(args.learner_name or "default", connect=[connect], zenoh_config=zenoh_config)
    path = args.library or defaults.library_db()
    if path.is_dir():
        raise ValueError(f"--library: {path} is a folder, not a library database")
    return LocalLearner(path, seed_library=read_library_json(defaults.EXAMPLE_LIBRARY))


def _driver(args: argparse.Namespace, profile: RobotProfile, zenoh_config: UserConfig | None) -> Driver:
    if args.driver == "sim":
        from hero_driver.sim_driver import SimulatedHero

        return SimulatedHero(args.robot, world=args.world or "lab", seed=args.seed or 0, profile=profile,
                             noise=_noise(args))
    from hero_driver.zenoh_link.client import ZenohDriver

    connect = endpoint_of("--connect", args.connect, DRIVER_ENDPOINT, CONNECT_KEY, zenoh_config)
    driver = ZenohDriver(args.robot, connect=[connect], discover_s=3.0, zenoh_config=zenoh_config)
    if not driver.wait_ready(5.0):  # alive, agreed on a version, and its first state published
        driver.close()
        refused = (" (or it requires credentials: --zenoh-config, docs/security.md)" if zenoh_config is None
                   else f" (or it refused the credentials of {zenoh_config.path})")
        raise DriverError(UNAVAILABLE, f"no driver is serving robot {args.robot!r} at "
                         f"{where(connect, CONNECT_KEY, zenoh_config)}{refused}; start one with "
                         f"'csl driver sim --robot {args.robot}'")
    # The robot the driver serves must be the one planned for: a larger base or other
    # procedure times would make every plan and every cost wrong without a single error.
    ours, theirs = profile_stamp(profile), driver.profile
    if theirs is None:
        print(f"csl: driver {args.robot} does not say which robot profile it serves (a driver from before "
              f"the 'profile' feature); assuming {ours.name}, as --knowledge says", file=sys.stderr)
    elif theirs.sha256 != ours.sha256:
        driver.close()
        raise ValueError(f"--knowledge {profile.source} is robot profile {ours.name} (sha256 {ours.sha256[:12]}) "
                         f"but driver {args.robot} serves {theirs.name} (sha256 {theirs.sha256[:12]}): "
                         f"run with the driver's profile or start the driver with --profile {profile.source}")
    return driver


def _episode(args: argparse.Namespace, driver: Driver, learner: LearnerService, setup: Setup,
             console: Console) -> int:
    """Run one episode and report it; the driver and learner are closed however it ends
    (an open zenoh session would keep the process alive)."""
    try:
        return _report_episode(args, driver, learner, setup, console)
    finally:
        driver.close()
        learner.close()


def _report_episode(args: argparse.Namespace, driver: Driver, learner: LearnerService, setup: Setup,
                    console: Console) -> int:
    check_library(learner.library().descriptions, setup.knowledge, "the library")  # before the robot moves
    log = EpisodeLog(args.out / "episode.jsonl")
    executive = Executive(driver, learner, profile=setup.profile, params=setup.params, criterion=setup.criterion,
                          log=log)
    first_image = driver.camera().result(timeout=60)
    start = driver.state().pose
    truths = _truths(driver, [])

    def progress(record: ObjectRecord) -> None:
        truth = match_truth(record, truths)
        console.print(f"  object {record.index}: {truth.name if truth else 'unknown'} -> "
                      f"{record.grasp or '-'} ({record.outcome}), {record.ledger.robot_s / 60:.1f} robot min")

    try:
        with console.status("approaching and recognizing objects..."):
            result = executive.run(on_object=progress)
    finally:
        executive.shutdown()
    table = rows(result.objects, _truths(driver, truths))
    print_table(HEADERS, [table_cells(r) for r in table], title="approach and recognize: one row per object",
                wrap=("object", "recoveries"), caption=CAPTION)
    print(summary(table))
    print(f"episode: {result.ticks} ticks, {result.wall_s:.1f} s wall; log: {args.out / 'episode.jsonl'}")
    if not args.no_plots:
        _plots(args.out, executive, result, first_image, [r.object for r in table], log.events,
               (start.x_in, start.y_in))
        print(f"plots: {args.out}/map.png, {args.out}/tree-*.png, {args.out}/behaviour-tree.png")
    if isinstance(learner, LocalLearner):
        print(f"library: {learner.path}")
    status, why = episode_status([record.outcome for record in result.objects])
    print(f"exit status {status}: {why}")
    return status


def _truths(driver: Driver, at_start: list[Truth]) -> list[Truth]:
    """The simulator's ground truth, when the driver is the in-process simulator (the
    only driver with a ``truth()``; a real robot does not know what it holds).

    Objects are located where they were at the start (``at_start``), but judged by what
    they are now: a cup knocked over and then grasped as a lying cup was handled right.
    """
    truth = getattr(driver, "truth", None)
    if truth is None:
        return []
    now = truth()
    out = []
    for i, t in enumerate(now):
        name = t.entry_id
        x, y = t.x_in, t.y_in
        if at_start:
            before = at_start[i]
            x, y = before.x_in, before.y_in
            if before.name != t.entry_id:
                name = f"{before.name} -> {t.entry_id.split('/')[-1]}"
        out.append(Truth(name, tuple(g.procedure for g in t.grasps), x, y))
    return out


def _plots(out: Path, executive: Executive, result: EpisodeResult, image: CameraImage, labels: list[str],
           events: list[dict[str, object]], start: tuple[float, float]) -> None:
    for old in out.glob("tree-*.png"):
        old.unlink()
    plot_map(out / "map.png", image, result.objects, events, labels, start)
    for record, label in zip(result.objects, labels):
        plot_object_tree(out / f"tree-{record.index}.png", record, label, events)
    plot_behaviour_tree(out / "behaviour-tree.png", executive.root)


def run_bt(args: argparse.Namespace) -> int:
    from executive.behaviour_tree import build_tree

    root = build_tree()
    if args.dot:
        graph = py_trees.display.dot_tree(root)
        graph.set_name("csl_executive")
        text = graph.to_string()
        if str(args.dot) == "-":
            sys.stdout.write(text)
        else:
            args.dot.write_text(text, encoding="utf-8")
            print(f"wrote {args.dot}")
        return 0
    if args.render:
        plot_behaviour_tree(args.render, root)
        print(f"wrote {args.render}")
        return 0
    text = py_trees.display.unicode_tree(root) if args.unicode else py_trees.display.ascii_tree(root)
    sys.stdout.write(text + ("\n" if not text.endswith("\n") else ""))
    return 0
