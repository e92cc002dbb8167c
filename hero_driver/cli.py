"""``csl driver``: run the simulated HERO as a driver process, or check any driver
process against the protocol (docs/driver-protocol.md).

Registered into ``csl`` by ``csl_cli/commands``; this module imports nothing from
the executive, so the driver side stays usable on a robot's own computer.
"""

from __future__ import annotations

import argparse
import dataclasses
import json
import sys
from pathlib import Path
from typing import TYPE_CHECKING

from hero_driver.inspect_cli import connect_endpoint, connect_options, register_inspect
from hero_driver.sim.noise import NOISE_PRESETS, NoiseConfig
from hero_driver.zenoh_link.keys import robot_keys
from zenoh_rpc.argtypes import non_negative_int, positive_seconds
from zenoh_rpc.endpoints import DRIVER_ENDPOINT, LISTEN_KEY, check_endpoint
from zenoh_rpc.options import add_zenoh_config_option, endpoint_of, open_listen_warning, reached_at, user_config

if TYPE_CHECKING:
    from hero_driver.zenoh_link.reference_check import Reference
    from robot_profile import RobotProfile

DEFAULT_CHECK_TIMEOUT_S = 30.0
# hero_driver.sim.camera.PRESETS, without importing OpenCV (a test holds them equal)
CAMERA_PRESETS = ("simple", "realistic", "realistic-lamp", "realistic-shadow", "realistic-floor", "realistic-exposure")


def disturb_preset(text: str) -> object:
    """argparse type of ``--disturb`` (hero_driver.sim.events.parse_disturb), imported
    only when the flag is given: ``csl --help`` needs no physics."""
    from hero_driver.sim.events import parse_disturb

    try:
        return parse_disturb(text)
    except ValueError as exc:
        raise argparse.ArgumentTypeError(str(exc).removeprefix("--disturb: ")) from None


def add_disturb_option(p: argparse.ArgumentParser) -> None:
    """``--disturb`` on the simulator's commands (``driver sim``; ``demo`` and ``run
    --driver sim``, whose simulator runs in-process)."""
    p.add_argument("--disturb", type=disturb_preset, default=None, metavar="KIND:P[,KIND:P]",
                   help="someone disturbs objects while the robot senses them: each object, when first "
                        "sensed, is nudged, removed or replaced with probability P (e.g. nudge:0.2; "
                        "docs/simulator.md, Disturbances; default: only the world file's events)")


def movers_preset(text: str) -> object:
    """argparse type of ``--movers`` (hero_driver.sim.movers.parse_movers), imported
    only when the flag is given."""
    from hero_driver.sim.movers import parse_movers

    try:
        return parse_movers(text)
    except ValueError as exc:
        raise argparse.ArgumentTypeError(str(exc).removeprefix("--movers: ")) from None


def add_movers_option(p: argparse.ArgumentParser) -> None:
    """``--movers`` on the simulator's commands (``driver sim``; ``demo`` and ``run
    --driver sim``, whose simulator runs in-process): people and carts crossing the
    floor."""
    p.add_argument("--movers", type=movers_preset, default=None, metavar="N[:SPEED]",
                   help="N people and carts cross the room on lines drawn from the seed, at SPEED in/s "
                        "(default 12); moves stop short of them (the blocked_moves feature; docs/simulator.md, "
                        "Moving obstacles; default: only the world file's movers)")


def register(subparsers: argparse._SubParsersAction) -> None:
    """Add the ``driver`` group and its ``sim`` and ``check`` commands."""
    group = subparsers.add_parser(
        "driver",
        help="serve the simulated robot over zenoh, or check a driver process",
        description=(
            "Driver processes serve a robot on zenoh keys hero/<robot>/... "
            "(docs/driver-protocol.md). 'sim' serves the simulated HERO 2000; 'check' runs "
            "the conformance suite against any driver, simulated or hardware."
        ),
    )
    actions = group.add_subparsers(dest="driver_command", metavar="ACTION", required=True)

    sim = actions.add_parser(
        "sim",
        help="serve the simulated HERO 2000 until interrupted",
        description=(
            "Run the simulated HERO 2000 as its own driver process: declares the liveliness "
            "token hero/<robot>/alive, publishes hero/<robot>/state at 5 Hz and after every "
            "verb, and answers hero/<robot>/rpc/<verb>. Stops cleanly on Ctrl-C or SIGTERM."
        ),
    )
    sim.add_argument("--robot", default="r1",
                     help="robot name, one key chunk of letters, digits, '_', '-', '.' (default r1)")
    sim.add_argument("--world", default=None, metavar="FILE",
                     help="world file, or the name of a shipped world such as 'lab' or "
                          "'training' (default: the lab)")
    sim.add_argument("--worlds-dir", type=Path, default=None, metavar="DIR",
                     help="the folder whose <name>.json worlds 'reset' may load by name; 'reset' takes "
                          "names only, never paths, and the --world file is also served under its file's "
                          "stem (default: the shipped worlds, hero_driver/worlds)")
    sim.add_argument("--seed", type=non_negative_int, default=0, metavar="N",
                     help="seed of the simulator's random stream (default 0)")
    sim.add_argument("--noise", default=None, choices=tuple(NOISE_PRESETS), metavar="PRESET",
                     help=f"sensor and odometry noise preset: {', '.join(NOISE_PRESETS)} "
                          "(docs/simulator.md, Noise; default: the world file's noise table, else mild)")
    sim.add_argument("--camera", default="simple", choices=CAMERA_PRESETS, metavar="PRESET",
                     help="how the overhead camera draws: simple (the grey bands) or realistic (what a real "
                          "ceiling camera shows: calibrate with 'csl camera calibrate'; docs/camera.md; "
                          "default simple); realistic-lamp, -shadow, -floor, -exposure: that room after a change "
                          "(docs/camera.md, 'When the room changes')")
    add_disturb_option(sim)
    add_movers_option(sim)
    sim.add_argument("--profile", default=None, metavar="FILE",
                     help="robot profile TOML of the robot to simulate; its name and fingerprint are "
                          "sent in the hello reply so 'csl run' refuses another robot's profile "
                          "(default: the HERO 2000's, hero_driver/profiles/hero2000.toml)")
    sim.add_argument("--listen", default=None, metavar="ENDPOINT",
                     help=f"zenoh endpoint to listen on (default {DRIVER_ENDPOINT})")
    add_zenoh_config_option(sim)
    sim.set_defaults(handler=_run_sim)

    check = actions.add_parser(
        "check",
        help="run the protocol conformance suite against a driver process",
        description=(
            "Connect to the driver serving ROBOT and exercise every verb, the liveliness "
            "token, the state publications and a set of bad requests (unknown verb, unknown "
            "procedure, malformed JSON, wrong types, missing and unknown fields, NaN, wrong "
            "protocol version, out-of-range target), the turns, durations and busy flag against "
            "the profile and the camera. Prints one PASS/FAIL line per named "
            "check; exits 0 when all pass, 1 otherwise. The robot must be free to turn in "
            "place and have nothing within contact range of its sonar after a reset (it "
            "drives 3 in straight ahead). A driver that "
            "cannot restore the simulated lab (a real robot) has its sensing and grasping checked "
            "on objects placed on its floor (--reference), or fails the check 'reference'."
        ),
    )
    check.add_argument("--robot", default="r1", help="robot name to check (default r1)")
    connect_options(check)
    check.add_argument("--timeout", type=positive_seconds, default=DEFAULT_CHECK_TIMEOUT_S, metavar="S",
                       help="seconds to wait for the driver to appear and for each reply "
                            f"(default {DEFAULT_CHECK_TIMEOUT_S:g})")
    check.add_argument("--profile", default=None, metavar="FILE",
                       help="knowledge profile of the robot: its procedures are the ones exercised, its "
                            "speeds and procedure times the ones durations are held to, and a driver "
                            "whose hello names another profile fails in one line "
                            "(default: the HERO 2000's)")
    check.add_argument("--camera-calibration", type=Path, default=None, metavar="FILE",
                       help="the driver camera's calibration ('csl camera calibrate'; the empty floor image beside "
                            "it): the camera-mapping and reset-objects checks read a real camera's images through "
                            "it, as 'csl run' does (default: band images; others are not checked; docs/camera.md)")
    check.add_argument("--reference", nargs="?", const="", default=None, metavar="ID,ID",
                       help="check sensing and grasping on objects placed on the robot's floor, even on a driver "
                            "that restores the simulated lab: the command asks you (on standard error) to place the "
                            "catalogue objects ID,ID (hero_driver/worlds/catalogue.json; at least two the shipped "
                            "library describes, one of them liftable; default closed-box-11x9x12/upright,"
                            "soda-can-12oz/upright), finds them with the camera, drives to the library's training "
                            "positions around them, compares each value with the library's, grasps one and tries a "
                            "wrong grasp on another. Without it, a driver that refuses to restore the lab (a real "
                            "robot) fails the check 'reference' unless you place the default objects when asked at "
                            "a terminal (docs/vendor-guide.md, 'The reference check')")
    check.add_argument("--placed", action="store_true",
                       help="the reference objects are already on the floor: do not ask (for scripts and tests; "
                            "with or without --reference)")
    check.add_argument("--shutdown-order", action="store_true",
                       help="after the suite, also check the liveliness order at shutdown: the command pings the "
                            "driver and asks you (on standard error) to stop it within --timeout seconds; passes "
                            "when its token went before its queryables (docs/driver-protocol.md, 'Shutdown order')")
    check.add_argument("--json", action="store_true",
                       help="print the results as one JSON document: checks (name, passed, detail), passed, failed")
    check.set_defaults(handler=_run_check)
    register_inspect(actions)


def _run_sim(args: argparse.Namespace) -> int:
    keys = robot_keys(args.robot)
    if args.listen is not None:
        check_endpoint(args.listen)
    if args.worlds_dir is not None and not args.worlds_dir.is_dir():
        raise ValueError(f"--worlds-dir {args.worlds_dir}: not a folder")
    zenoh_config = user_config(args.zenoh_config)
    listen = endpoint_of("--listen", args.listen, DRIVER_ENDPOINT, LISTEN_KEY, zenoh_config)
    warning = open_listen_warning(listen, zenoh_config)
    if warning:
        print(warning, file=sys.stderr, flush=True)
    # Imported here: the simulator pulls in pymunk and the world files, which
    # `csl --help` and `csl driver check` have no use for.
    from hero_driver.sim.events import DisturbPreset
    from hero_driver.sim.movers import MoverPreset
    from hero_driver.sim_driver import SimulatedHero
    from hero_driver.zenoh_link.node import serve
    from zenoh_rpc.serving import stop_on_signals

    from robot_profile import DEFAULT_PROFILE, load_profile, profile_stamp

    profile = load_profile(DEFAULT_PROFILE if args.profile is None else args.profile)
    noise = None if args.noise is None else NoiseConfig.preset(args.noise)
    driver = SimulatedHero(robot=args.robot, world=args.world, seed=args.seed, profile=profile, noise=noise,
                           worlds_dir=args.worlds_dir, camera=args.camera, disturb=args.disturb or DisturbPreset(),
                           movers=args.movers or MoverPreset())

    def on_ready() -> None:
        print(f"serving {keys.rpc('*')} {reached_at(listen, zenoh_config)} (Ctrl-C to stop)", flush=True)

    try:
        with stop_on_signals() as stop:
            serve(driver, listen=[listen], stop=stop, on_ready=on_ready, zenoh_config=zenoh_config,
                  profile=profile_stamp(profile))
    finally:
        driver.close()
    print(f"driver {args.robot} stopped", file=sys.stderr)
    return 0


def _reference(args: argparse.Namespace, profile: RobotProfile) -> Reference | None:
    """The reference objects of the suite's reference checks: those of ``--reference``
    (checked always), else the default ones when ``--placed`` says they lie there or a
    person at a terminal can be asked to place them (checked on a driver that cannot
    restore the lab); None when nobody can place them. A bad id is one line naming
    the flag and the id."""
    from hero_driver.zenoh_link.reference_check import DEFAULT_OBJECTS, Reference, reference_objects

    if args.reference is None and not args.placed and not sys.stdin.isatty():
        return None
    ids = [i.strip() for i in args.reference.split(",")] if args.reference else list(DEFAULT_OBJECTS)
    try:
        objects = reference_objects(ids, profile)
    except ValueError as exc:
        if args.reference is None and not args.placed:  # the default objects do not suit this robot's profile
            return None
        raise ValueError(f"--reference: {exc}") from None
    camera = None
    if args.camera_calibration is not None:
        from planner.segmentation import load_camera

        camera = load_camera(args.camera_calibration)
    return Reference(objects, profile, always=args.reference is not None,
                     ask=None if args.placed else _ask_operator, camera=camera)


def _ask_operator(prompt: str) -> bool:
    """Show ``prompt`` on standard error and wait for Enter; False when the person
    types 'skip' or standard input ends."""
    print(prompt, file=sys.stderr, flush=True)
    answer = sys.stdin.readline()
    return bool(answer) and answer.strip().lower() != "skip"


def _run_check(args: argparse.Namespace) -> int:
    robot_keys(args.robot)
    connect, _, zenoh_config = connect_endpoint(args)
    from hero_driver.zenoh_link.conformance import Procedures, format_table, run_checks
    from hero_driver.zenoh_link.motion_check import Timing

    from robot_profile import DEFAULT_PROFILE, load_profile, profile_stamp

    profile = load_profile(DEFAULT_PROFILE if args.profile is None else args.profile)
    vision = None
    if args.camera_calibration is not None:
        from hero_driver.zenoh_link.camera_check import calibrated_reader

        try:
            vision = calibrated_reader(args.camera_calibration)
        except ValueError as exc:
            raise ValueError(f"--camera-calibration: {exc}") from None
    reference = _reference(args, profile)
    results = run_checks(args.robot, [connect], timeout_s=args.timeout, procedures=Procedures.from_profile(profile),
                         zenoh_config=zenoh_config, profile=profile_stamp(profile), vision=vision,
                         timing=Timing.from_profile(profile), reference=reference)
    if args.shutdown_order and any(r.passed for r in results):  # no driver at all: the suite said so
        from hero_driver.zenoh_link.conformance import shutdown_order

        def ask() -> None:  # once the check sees the token and noops are answered: a person stops it
            print(f"shutdown-order: stop the driver of robot {args.robot} now (within {args.timeout:g} s)",
                  file=sys.stderr, flush=True)

        results = [*results, shutdown_order(args.robot, [connect], ask, timeout_s=args.timeout,
                                            zenoh_config=zenoh_config)]
    if args.json:
        failed = sum(not r.passed for r in results)
        print(json.dumps({"robot": args.robot, "checks": [dataclasses.asdict(r) for r in results],
                          "passed": len(results) - failed, "failed": failed}, indent=2, ensure_ascii=False))
    else:
        print(format_table(results))
    return 0 if all(r.passed for r in results) else 1
