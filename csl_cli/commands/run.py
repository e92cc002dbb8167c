"""``csl demo``, ``csl run`` and ``csl bt``: their arguments. The handlers live in
``csl_cli/commands/episode.py`` (``csl bt``'s in ``csl_cli/commands/bt.py``) and are
imported only when one of these commands runs.
"""

from __future__ import annotations

import argparse
from pathlib import Path

from executive import defaults
from csl_cli.args import (add_criterion_options, add_learned_grasp_costs_option, add_perception_option,
                            add_recording_options, add_retrain_option, add_verb_timeout_option, battery_level,
                            endpoint, non_negative_seconds)
from csl_cli.commands import modes
from hero_driver.cli import CAMERA_PRESETS, add_disturb_option, add_movers_option
from hero_driver.sim.noise import NOISE_PRESETS
from zenoh_rpc.argtypes import non_negative_int, positive_int, positive_seconds
from zenoh_rpc.endpoints import DRIVER_ENDPOINT, LEARNER_ENDPOINT
from zenoh_rpc.options import add_zenoh_config_option


def _executive_options(p: argparse.ArgumentParser) -> None:
    choosing = p.add_argument_group("recognition (the learner's choices and the control strategies)")
    choosing.add_argument("--knowledge", type=Path, default=defaults.KNOWLEDGE,
                          help="the robot's knowledge TOML (default: the shipped HERO 2000 profile)")
    add_criterion_options(choosing)
    choosing.add_argument("--alternatives", type=positive_int, default=3, metavar="N",
                          help="alternatives tried at a node before backtracking (the paper's N, default 3)")
    choosing.add_argument("--nearest-after", type=positive_int, default=None, metavar="K",
                          help="switch to nearest neighbour after K unreliable values (default: only as the last "
                               "resort)")
    choosing.add_argument("--appearance", action=argparse.BooleanOptionalAction, default=None,
                          help="let what the overhead camera measured (footprint area and elongation) rule out "
                               "unlike descriptions before any test, for free (docs/library-format.md; default on "
                               "with --perception ceiling; off with onboard, where no camera measures it, and "
                               "--appearance is then refused)")
    choosing.add_argument("--max-steps", type=positive_int, default=40, metavar="N",
                          help="recognition steps per object before it is reported failed (default 40)")
    add_learned_grasp_costs_option(choosing)
    robot = p.add_argument_group("the robot's perception, battery and camera")
    add_perception_option(robot, PERCEPTION_HELP)
    robot.add_argument("--battery-low", type=battery_level, default=0.2, metavar="LEVEL",
                       help="below this battery level the robot drives to its dock and charges, then resumes "
                            "(default 0.2; 0 turns the guard off; needs the driver's battery feature)")
    robot.add_argument("--camera-calibration", type=Path, default=None, metavar="FILE",
                       help="the overhead camera's calibration (written by 'csl camera calibrate', the empty floor "
                            "image beside it): vision reads real images through it (docs/camera.md; default: "
                            "band images)")
    output = p.add_argument_group("output and watching")
    output.add_argument("--out", type=Path, default=Path("csl-out"),
                        help="folder for the episode log, the plots and (demo) the demo's own library (default ./csl-out)")
    output.add_argument("--no-plots", action="store_true", help="skip the PNG plots")
    output.add_argument("--json", action="store_true",
                        help="print one JSON document on standard output instead of the tables (for scripts)")
    add_recording_options(output)


PERCEPTION_HELP = (
    "how the robot sees its floor: ceiling, the overhead camera that sees the whole room at once (the paper's); or "
    "onboard, no ceiling camera: the robot explores the home with its own range scans (the driver's scan feature: "
    "a lidar or the sonar swept in place), builds a map of it, finds object candidates in the scans and plans on "
    "that map (docs/mapping.md). Onboard writes map.png as the map built beside the true one (the simulator's; the "
    "built map alone for another driver) with the route driven and the objects found, and prints the exploration's "
    "robot time and candidates; objects the simulator placed that were never found fail the run (exit 1). "
    "--appearance, --camera and --camera-calibration are the overhead camera's: they go with ceiling. With onboard, "
    "a driver that offers no scans is refused in one line (exit 2); with ceiling, so is a robot or world with no "
    "ceiling camera, the line saying to add --perception onboard. Default ceiling")


def register(sub: argparse._SubParsersAction) -> None:
    demo = sub.add_parser(
        "demo", help="the main job: train in the simulated lab, then retrieve the test objects",
        description=("Train on the paper's Table 3 objects in the simulator, then let the executive locate, "
                     "recognize and grasp the unseen test objects in the built-in lab. Prints a table per "
                     "object and writes the episode log and plots (map, each object's run-time tree, the "
                     "behaviour tree) to --out, with the demo's own library (library.sqlite, made anew each "
                     "time): csl library and csl tree read the last demo's library while the robot's, "
                     "$CSL_HOME/library.sqlite (csl run's), does not exist. A home without a ceiling camera "
                     "(--world apartment, apartment-2 or two-rooms) takes --perception onboard: the training "
                     "objects are then seen by the robot's own scans too, the robot explores the home, and "
                     "map.png shows the map it built beside the true one."))
    demo.add_argument("--seed", type=non_negative_int, default=0, help="simulator seed (default 0)")
    demo.add_argument("--world", default="lab",
                      help="world name or file (default: the built-in lab; the homes apartment, apartment-2 and "
                           "two-rooms have no ceiling camera: give --perception onboard; docs/simulator.md)")
    _noise_option(demo)
    _camera_option(demo)
    add_disturb_option(demo)
    add_movers_option(demo)
    add_retrain_option(demo)
    _executive_options(demo)
    demo.set_defaults(handler=_handler("run_demo"))

    run = sub.add_parser(
        "run", help="run the executive against any driver (simulated in-process, or over zenoh)",
        description=("Locate, recognize and grasp every object the robot's camera sees, learning into the "
                     "library. --driver sim runs the simulated HERO in this process; --driver zenoh talks to "
                     "the driver process serving hero/ROBOT/... (csl driver sim, or a hardware driver). "
                     "--perception onboard drives a driver that offers range scans (the scan feature) without "
                     "a ceiling camera: the robot explores first, then handles the objects it found."))
    link = run.add_argument_group("the robot and the learner")
    link.add_argument("--driver", choices=("sim", "zenoh"), default="sim", help="which driver (default sim)")
    link.add_argument("--robot", default="r1", help="robot name (zenoh keys hero/ROBOT/...)")
    link.add_argument("--learner", choices=("local", "zenoh"), default="local",
                      help="learner service: in this process, or shared over zenoh (csl learner serve)")
    sim = modes.ModeGroup(run, "the simulator in this process", modes.SIMULATOR)
    sim.add_argument("--world", default=None, help="world name or file (default: the lab)")
    sim.add_argument("--seed", type=non_negative_int, default=None, help="simulator seed (default 0)")
    _noise_option(sim)
    _camera_option(sim)
    add_disturb_option(sim)
    add_movers_option(sim)
    zenoh_driver = modes.ModeGroup(run, "a driver over zenoh", modes.ZENOH_DRIVER)
    zenoh_driver.add_argument("--connect", type=endpoint, default=None, metavar="ENDPOINT",
                              help=f"zenoh endpoint of the driver node (default {DRIVER_ENDPOINT})")
    add_verb_timeout_option(zenoh_driver)
    zenoh_driver.add_argument(
        "--wait-driver", type=non_negative_seconds, default=0.0, metavar="SECONDS",
        help="when the driver's liveliness token disappears, pause the object in hand and wait up to SECONDS for a "
             "driver under the same robot name, then locate the objects again from a new camera image (those "
             "already handled stay handled) and go on; no driver in time: one line, exit status 3 (default 0: "
             "stop at once; docs/reliability.md)")
    local = modes.ModeGroup(run, "the learner in this process", modes.LOCAL_LEARNER)
    local.add_argument("--library", type=Path, default=None,
                       help="the library store (SQLite; default $CSL_HOME/library.sqlite, seeded with the example)")
    shared = modes.ModeGroup(run, "a shared learner service", modes.SHARED_LEARNER)
    shared.add_argument("--learner-name", default=None, help="name of the zenoh learner service (default 'default')")
    shared.add_argument("--learner-connect", type=endpoint, default=None, metavar="ENDPOINT",
                        help=f"zenoh endpoint of the learner service (default {LEARNER_ENDPOINT})")
    shared.add_argument("--learner-timeout", type=positive_seconds, default=5.0, metavar="S",
                        help="seconds the learner service is given to be found and to answer each request (a "
                             "fleet starting at once against a large library wants more; default 5)")
    shared.add_argument("--outbox", type=Path, default=None, metavar="FILE",
                        help="where learned descriptions wait while the learner service is unreachable (SQLite; "
                             "default $CSL_HOME/outbox.sqlite)")
    add_zenoh_config_option(modes.ModeGroup(run, "any zenoh session", modes.ANY_ZENOH))
    _executive_options(run)
    run.set_defaults(handler=_handler("run_run"))
    modes.guarded(run)  # --world with --driver zenoh, --library with --learner zenoh...: one line, exit 2

    bt = sub.add_parser("bt", help="show the behaviour tree",
                        description="Print the executive's behaviour tree, render it to a PNG, or export it "
                                    "as Graphviz DOT through py_trees' own dot export.")
    bt.add_argument("--render", type=Path, metavar="PNG", help="write the tree as a PNG picture")
    bt.add_argument("--dot", type=Path, metavar="FILE",
                    help="write the tree as Graphviz DOT (py_trees.display.dot_tree; '-' for standard output); "
                         "render with e.g. 'dot -Tsvg FILE'")
    bt.add_argument("--unicode", action="store_true", help="draw with py_trees' unicode symbols (default: ascii)")
    add_perception_option(bt, "the tree for ceiling perception (default) or onboard: with onboard, the branch "
                              "'explore the home' (look around, more to see?, go to the view, until mapped) runs "
                              "before the objects are located")
    bt.set_defaults(handler=_run_bt)




def _noise_option(p: argparse.ArgumentParser) -> None:
    p.add_argument("--noise", choices=tuple(NOISE_PRESETS), default=None, metavar="PRESET",
                   help=f"the simulator's sensor and odometry noise: {', '.join(NOISE_PRESETS)} (default: "
                        "the world file's noise table, else mild; docs/simulator.md)")


def _camera_option(p: argparse.ArgumentParser) -> None:
    p.add_argument("--camera", choices=CAMERA_PRESETS, default=None, metavar="PRESET",
                   help="the simulator's overhead camera: simple (grey bands) or realistic (a real ceiling "
                        "camera's image; calibrated from the world's marker board on the first image unless "
                        "--camera-calibration is given; docs/camera.md) (default simple); realistic-lamp, "
                        "-shadow, -floor, -exposure: the room changed after a calibration on the plain one "
                        "(docs/camera.md, 'When the room changes')")


def _run_bt(args: argparse.Namespace) -> int:
    """``csl bt``'s handler (csl_cli/commands/bt.py), imported when called."""
    from csl_cli.commands.bt import run_bt

    return run_bt(args)


def _handler(name: str):  # noqa: ANN202
    """The handler ``name`` of ``csl_cli.commands.episode``, imported when called; what
    the command makes in ``--out`` is taken back if it fails before its episode starts
    (csl_cli/run_output.py)."""

    def handle(args: argparse.Namespace) -> int:
        from csl_cli.commands import episode
        from csl_cli.run_output import taken_back_unless_started

        out: Path = args.out
        with taken_back_unless_started(out, out / "episode.jsonl", [args.record] if args.record else []):
            return getattr(episode, name)(args)

    return handle
