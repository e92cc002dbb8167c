"""Running ``csl demo`` and ``csl run``: the handlers behind the arguments
that ``csl_cli/commands/run.py`` declares (with ``--perception onboard``, what a robot
without a ceiling camera adds is in ``csl_cli/onboard.py``).

Kept apart so that ``csl --help`` (and every other command) does not import the planner,
the behaviour tree and matplotlib just to print a usage line.
"""

from __future__ import annotations

import argparse
import dataclasses
import sys
from dataclasses import dataclass
from pathlib import Path
from typing import TYPE_CHECKING

from rich.console import Console

from behaviours.events import Event
from behaviours.records import ObjectRecord
from behaviours.services import Params
from camera_model.board import MarkerBoard, load_board
from camera_model.image import CameraImage
from executive import defaults
from csl_cli import onboard
from csl_cli.args import ONBOARD, criterion_from_args, library_path, output_folder
from csl_cli.commands.learner_cmd import report_quarantined
from csl_cli.library_choice import demo_library_line
from executive.episode_log import EpisodeLog
from executive.executive import EpisodeResult, Executive
from executive.exit_status import run_status
from reporting.history import append_run, default_history, episode_run
from reporting.plots import plot_behaviour_tree, plot_map, plot_object_tree
from csl_cli.recording_options import check_recording_options, open_recording
from recording.run_metadata import describe_run
from recording.status import status_tree
from reporting.report import Row, Truth, episode_json, match_truth, print_report, rows
from reporting.tables import print_json
from hero_driver.interface import TIMEOUT, UNAVAILABLE, Driver, DriverError
from hero_driver.sim.noise import NoiseConfig
from learner.choosing.criteria import Criterion
from learner.description import ObjectDescription
from learner.knowledge import Knowledge
from learner.library.checks import check_library
from learner.library.format import read_library_json
from learner.service.interface import LearnerService
from learner.service.local import LocalLearner
from planner.segmentation import Camera, load_camera
from robot_profile import RobotProfile, load_profile, profile_stamp
from zenoh_rpc.endpoints import CONNECT_KEY, DRIVER_ENDPOINT, LEARNER_ENDPOINT
from zenoh_rpc.options import endpoint_of, user_config, where

if TYPE_CHECKING:  # zenoh is imported only when a run uses it
    from hero_driver.zenoh_link.client import VerbTimeouts
    from zenoh_rpc.config import UserConfig


@dataclass(frozen=True)
class Setup:
    """What the arguments choose, read and checked before anything runs: the robot's
    profile (one reading serves the learner, the planner and the simulator), the
    control parameters and the criterion; for real camera images the calibrated
    ``camera`` (--camera-calibration), or the ``board`` to calibrate it from on the
    first image (--camera realistic without a file; docs/camera.md)."""

    profile: RobotProfile
    knowledge: Knowledge
    params: Params
    criterion: Criterion
    camera: Camera | None = None
    board: MarkerBoard | None = None


def _setup(args: argparse.Namespace) -> Setup:
    check_recording_options(args)  # before training or robot time
    onboard.check_options(args)  # the overhead camera's options with --perception onboard
    profile = load_profile(args.knowledge)
    # the appearance is what the overhead camera measured: on with it unless turned off, off without it
    appearance = args.appearance if args.appearance is not None else args.perception != ONBOARD
    return Setup(profile, profile.knowledge(),
                 Params(max_alternatives=args.alternatives, nearest_after=args.nearest_after,
                        max_steps=args.max_steps, seed=args.seed or 0,
                        use_appearance=appearance, battery_low=args.battery_low,
                        wait_driver_s=getattr(args, "wait_driver", 0.0),  # csl run only
                        learned_grasp_costs=args.learned_grasp_costs),
                 criterion_from_args(args), *_camera(args, profile))


def _camera(args: argparse.Namespace, profile: RobotProfile) -> tuple[Camera | None, MarkerBoard | None]:
    """The calibration file, read and checked now (a bad one is one line, before any
    training or robot time); else, for the simulator's realistic camera, the board of
    the world it prints (the first image calibrates it), or, for a scene change
    (``realistic-lamp`` ...), a calibration on the room before the change."""
    if args.camera_calibration is not None:
        try:
            return load_camera(args.camera_calibration), None
        except ValueError as exc:
            raise ValueError(f"--camera-calibration: {exc}") from None
    if not (args.camera or "simple").startswith("realistic"):
        return None, None
    saved = _saved_camera(args)
    if saved is not None:
        return saved, None
    from hero_driver.sim.render_board import board_path

    try:
        board = load_board(board_path(args.world or "lab"))
    except ValueError as exc:
        raise ValueError(f"--camera {args.camera}: {exc}; or give --camera-calibration FILE") from None
    if args.camera != "realistic":
        return _calibrated_before_the_change(args, profile, board), None
    return None, board


def _calibrated_before_the_change(args: argparse.Namespace, profile: RobotProfile, board: MarkerBoard) -> Camera:
    """A scene change of the simulator's realistic camera (docs/camera.md, "When the room
    changes") is the room changed after it was calibrated: the calibration is made on
    the plain realistic room's first image, as 'csl camera calibrate' would have been
    before the lamp went on, and the run then meets the changed room."""
    from hero_driver.sim.camera import before_change
    from hero_driver.sim_driver import SimulatedHero
    from planner.segmentation import calibrated_camera

    before = SimulatedHero("calibration", world=args.world or "lab", seed=args.seed or 0, profile=profile,
                           camera=before_change(args.camera))
    try:
        return calibrated_camera(before.camera().result().pixels, board)
    finally:
        before.close()


def _saved_camera(args: argparse.Namespace) -> Camera | None:
    """The robot's calibration as ``csl camera calibrate`` saved it
    ($CSL_HOME/camera/ROBOT.json), said in one line; None when there is none."""
    from csl_cli.commands.camera import default_calibration

    path = default_calibration(getattr(args, "robot", "r1"))
    if not path.exists():
        return None
    try:
        camera = load_camera(path)
    except ValueError as exc:
        raise ValueError(f"the saved camera calibration: {exc}; calibrate again with 'csl camera calibrate'") from None
    print(f"camera: reading images through the saved calibration {path} (or give --camera-calibration FILE)",
          file=sys.stderr)
    return camera


def _camera_of_driver(args: argparse.Namespace, driver: Driver, setup: Setup) -> Setup:
    """A driver over zenoh whose images are not band images (a real camera's) is read
    through the robot's saved calibration; without one, one line naming the command
    that makes it (exit 2) before the robot moves."""
    if getattr(args, "driver", "sim") != "zenoh" or setup.camera is not None:
        return setup
    from camera_model.bands import looks_like_bands

    if looks_like_bands(_first_image(driver).pixels):
        return setup
    camera = _saved_camera(args)
    if camera is None:
        from csl_cli.commands.camera import default_calibration

        raise ValueError(f"driver {args.robot}'s camera gives real images (no grey bands) and no calibration is "
                         f"saved at {default_calibration(args.robot)}: run 'csl camera calibrate --robot "
                         f"{args.robot}' first, or give --camera-calibration FILE (docs/camera.md)")
    return dataclasses.replace(setup, camera=camera)


def _first_image(driver: Driver) -> CameraImage:
    """The overhead camera's image; a robot with no ceiling camera is one line saying to
    add --perception onboard (exit 2), any other error the robot's."""
    try:
        return driver.camera().result(timeout=60)
    except DriverError as exc:
        refused = onboard.camera_refused(exc, driver)
        if refused is None:
            raise
        raise refused from None


def _check_camera(camera: Camera | None, image: CameraImage, args: argparse.Namespace) -> None:
    """A calibration is for one camera: an image of another size is another camera; and
    for one room: an image whose floor no longer matches the calibration's empty floor
    stops here with the one line of ``planner.scene_check`` (exit 2), before any robot
    or training time is spent."""
    if camera is None:
        return
    height, width = image.pixels.shape[:2]
    if (width, height) != camera.calibration.image_size:
        given = args.camera_calibration or "the saved calibration"
        raise ValueError(f"--camera-calibration: {given} is for {camera.calibration.image_size[0]}x"
                         f"{camera.calibration.image_size[1]} images, the driver's camera gives {width}x{height} "
                         "(another camera, or the simulator without --camera realistic)")
    from planner.vision import look

    look(image, camera)  # raises SceneChanged


def run_demo(args: argparse.Namespace) -> int:
    console = Console(stderr=True, soft_wrap=True)
    setup = _setup(args)
    knowledge = setup.knowledge
    output_folder(args.out, "--out")
    if (args.out / "library.sqlite").resolve() == defaults.library_db().resolve():
        raise ValueError(f"--out: {args.out} is where your robot's library is kept ($CSL_HOME), and a demo makes "
                         "its own library anew in --out: choose another folder")
    driver = _simulator(args, "r1", setup.profile)  # a bad world fails first
    try:
        onboard.check_world_camera(driver, args)  # a home with --perception ceiling: before training
    except BaseException:
        driver.close()
        raise
    if setup.camera is not None:  # a calibration of another camera or room: said before training
        try:
            _check_camera(setup.camera, driver.camera().result(), args)
        except BaseException:
            driver.close()
            raise
    with console.status("training on the Table 3 objects in the simulator..."):
        from csl_cli.demo_library import trained_library  # the simulator: csl demo only

        trained = trained_library(knowledge, setup.profile, args.world, args.seed,
                                  retrain=args.retrain, say=console.print, perception=args.perception)
    summary = trained.summary
    console.print(f"trained: {summary.descriptions} descriptions at distances "
                  f"{', '.join(f'{d:g}' for d in summary.distances_in)} in and orientations "
                  f"{', '.join(f'{o:g}' for o in summary.orientations_deg)}°; {summary.robot_hours:.1f} h of robot time")
    store = args.out / "library.sqlite"
    store.unlink(missing_ok=True)
    learner = LocalLearner(store, seed_library=list(trained.descriptions))
    return _episode(args, driver, learner, setup, console)


def run_run(args: argparse.Namespace) -> int:
    """``csl run``; its options out of their mode were refused before it (commands/modes.py)."""
    console = Console(stderr=True, soft_wrap=True)
    setup = _setup(args)
    timeouts = _verb_timeouts(args)  # a bad verb name fails before anything connects
    zenoh_config = user_config(args.zenoh_config) if "zenoh" in (args.driver, args.learner) else None
    output_folder(args.out, "--out")
    learner = _learner(args, zenoh_config, setup)
    try:
        driver = _driver(args, setup.profile, zenoh_config, timeouts)
    except BaseException:
        learner.close()
        raise
    try:
        onboard.check_world_camera(driver, args)  # the simulator's home with --perception ceiling
    except BaseException:
        driver.close()
        learner.close()
        raise
    return _episode(args, driver, learner, setup, console)


def _simulator(args: argparse.Namespace, robot: str, profile: RobotProfile) -> Driver:
    """The in-process simulator the options describe (``csl demo``, ``csl run --driver sim``)."""
    from hero_driver.sim_driver import SimulatedHero

    from hero_driver.sim.events import DisturbPreset
    from hero_driver.sim.movers import MoverPreset

    return SimulatedHero(robot, world=args.world or "lab", seed=args.seed or 0, profile=profile, noise=_noise(args),
                         camera=args.camera or "simple", disturb=args.disturb or DisturbPreset(),
                         movers=args.movers or MoverPreset())


def _noise(args: argparse.Namespace) -> NoiseConfig | None:
    """The chosen preset, or None to keep the world file's own noise table."""
    return None if args.noise is None else NoiseConfig.preset(args.noise)


def _learner(args: argparse.Namespace, zenoh_config: UserConfig | None, setup: Setup) -> LearnerService:
    if args.learner == "zenoh":
        from learner.service.outbox import Outbox, OutboxLearner
        from learner.service.zenoh_client import ZenohLearner

        connect = endpoint_of("--learner-connect", args.learner_connect, LEARNER_ENDPOINT, CONNECT_KEY, zenoh_config)
        name = args.learner_name or "default"
        outbox = Outbox(args.outbox or defaults.library_db().with_name("outbox.sqlite"))  # a bad file fails first
        try:
            service = ZenohLearner(name, connect=[connect], timeout_s=args.learner_timeout, zenoh_config=zenoh_config)
        except BaseException:
            outbox.close()
            raise
        return OutboxLearner(service, outbox, name)
    path = library_path(args.library, "--library")
    args.library_created = not path.exists()  # said in the report: a run that fails still says one line
    learner = LocalLearner(path, seed_library=_seed_library(args, setup) if args.library_created else None)
    report_quarantined(learner, "local")  # rows kept in the file but not used, each named
    return learner


def _seed_library(args: argparse.Namespace, setup: Setup) -> list[ObjectDescription]:
    """What a new library starts from: the shipped example when it serves the robot
    (the HERO 2000's), else a library trained for the robot in the simulator, as
    ``csl demo`` trains it and kept under the same hash (csl_cli/demo_library.py)."""
    example = read_library_json(defaults.EXAMPLE_LIBRARY)
    try:
        check_library(example, setup.knowledge, "the example library")
    except ValueError:
        from csl_cli.demo_library import trained_library  # the simulator: only for another robot

        trained = trained_library(setup.knowledge, setup.profile, "lab", 0,
                                  say=lambda line: print(line, file=sys.stderr, flush=True))
        robot = profile_stamp(setup.profile).name
        args.library_seed = f"a library trained for {robot} in the simulator ({trained.key[:12]})"
        return list(trained.descriptions)
    args.library_seed = defaults.EXAMPLE_LIBRARY.name
    return example


def _verb_timeouts(args: argparse.Namespace) -> VerbTimeouts | None:
    """The ``--verb-timeout VERB=SECONDS`` pairs as the zenoh client's timeouts (None:
    the protocol's defaults). The in-process simulator finishes every verb before it
    returns, so there a timeout could never fire: the flag goes with --driver zenoh."""
    given = args.verb_timeout
    if not given:
        return None
    from hero_driver.zenoh_link.client import VerbTimeouts

    try:
        return VerbTimeouts.of_verbs(given)
    except ValueError as exc:
        raise ValueError(f"--verb-timeout: {exc}") from None


def _driver(args: argparse.Namespace, profile: RobotProfile, zenoh_config: UserConfig | None,
            timeouts: VerbTimeouts | None = None) -> Driver:
    if args.driver == "sim":
        return _simulator(args, args.robot, profile)
    from hero_driver.zenoh_link.client import VerbTimeouts, ZenohDriver

    connect = endpoint_of("--connect", args.connect, DRIVER_ENDPOINT, CONNECT_KEY, zenoh_config)
    driver = ZenohDriver(args.robot, connect=[connect], discover_s=3.0, zenoh_config=zenoh_config,
                         timeouts=timeouts or VerbTimeouts())
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
        try:
            driver.close()
        finally:  # the learner is closed even when the driver's close fails
            learner.close()
            _report_outbox(learner)


def _report_outbox(learner: LearnerService) -> None:
    """Say how many learned descriptions still wait for the learner service, if any."""
    from learner.service.outbox import OutboxLearner

    if isinstance(learner, OutboxLearner) and learner.waiting_at_close:
        print(f"outbox: {learner.waiting_at_close} learned descriptions wait in {learner.outbox.path} for learner "
              f"{learner.learner!r}; the next run delivers them", file=sys.stderr, flush=True)
    if isinstance(learner, OutboxLearner) and learner.grasp_records_lost:
        print(f"grasp costs: {learner.grasp_records_lost} objects' grasp attempts were not recorded (learner "
              f"{learner.learner!r} unreachable or without grasp costs; docs/learner-protocol.md)",
              file=sys.stderr, flush=True)


def _report_episode(args: argparse.Namespace, driver: Driver, learner: LearnerService, setup: Setup,
                    console: Console) -> int:
    check_library(learner.library().descriptions, setup.knowledge, "the library")  # before the robot moves
    scans = args.perception == ONBOARD
    if scans:
        onboard.check_scans(driver, args)
    else:
        setup = _camera_of_driver(args, driver, setup)
    log = EpisodeLog(args.out / "episode.jsonl")
    recording = open_recording(args, setup.profile)  # --record/--live (docs/recording.md)
    if recording is not None:
        recording.describe_run(describe_run(driver.robot, setup.profile, setup.criterion.name, setup.params.seed))
        driver = recording.attach(driver, log)
    executive = Executive(driver, learner, profile=setup.profile, params=setup.params, criterion=setup.criterion,
                          log=log, on_tick=None if recording is None else recording.tick,
                          camera=setup.camera, board=setup.board, perception=args.perception)
    _say_battery_guard(driver, setup.params.battery_low)
    _say_blocked_branch(driver, setup.params.blocked_tries)
    first_image = None if scans else _first_image(driver)  # onboard: the scans are the looks
    start = driver.state().pose
    truths = _truths(driver, [])

    def progress(record: ObjectRecord) -> None:
        truth = match_truth(record, truths)
        label = truth.name if truth else "unknown"
        console.print(f"  object {record.index}: {label} -> "
                      f"{record.grasp or '-'} ({record.outcome}), {record.ledger.robot_s / 60:.1f} robot min"
                      + (f"; {CLUSTER_NOTICE}" if record.clustered else ""))
        if recording is not None:
            recording.handled(record, label)
        if args.show_status:  # on stderr when stdout carries the --json document
            stream = sys.stderr if args.json else sys.stdout
            print(status_tree(executive.root, colour=stream.isatty()), file=stream, flush=True)

    try:
        if first_image is not None:
            _check_camera(setup.camera, first_image, args)  # before the robot moves
        with console.status("approaching and recognizing objects..."):
            result = executive.run(on_object=progress)
    finally:
        executive.shutdown()
        if recording is not None:
            recording.close()
    table = rows(result.objects, _truths(driver, truths))
    as_json = args.json  # --json: one document on stdout, after the plots
    explored = onboard.exploration(log.events) if scans else None
    missing = onboard.never_found(result.objects, truths) if scans else []
    left_there = onboard.still_there(result.objects, truths, _on_floor(driver)) if scans else []
    if not as_json:
        print_report(table)
        if explored is not None:
            print(explored.line())
        print(f"episode: {result.ticks} ticks, {result.wall_s:.1f} s wall; log: {args.out / 'episode.jsonl'}")
        if recording is not None and recording.mcap is not None:
            print(f"recording: {recording.mcap} (Foxglove; docs/recording.md)")
    if not args.no_plots:
        labels = [r.object for r in table]
        _plots(args.out, executive, result, labels, log.events)
        if first_image is None:  # onboard: the map the scans built, beside the true one
            if not onboard.plot_map(args.out / "map.png", executive, driver, result.objects, labels, truths,
                                    log.events) and not as_json:
                print("map: no scan was read, so no map was built: map.png is not written")
        else:
            plot_map(args.out / "map.png", _as_mapped(first_image, executive.services.navigator.camera),
                     result.objects, log.events, labels, (start.x_in, start.y_in),
                     base_radius_in=setup.profile.robot.geometry.base_radius_in)
        if not as_json:
            print(f"plots: {args.out}/map.png, {args.out}/tree-*.png, {args.out}/behaviour-tree.png")
    library = learner.path if isinstance(learner, LocalLearner) else None
    created = getattr(args, "library_created", False)  # run's --library (or the default) did not exist
    unanswered = _unanswered(log.events)
    # a cluster left (no grasp held) is two or more objects the robot could not tell apart,
    # not a No-Grab object: a failure
    clusters_left = [r.index for r in result.objects if r.clustered and r.outcome == "left"]
    outcomes = ["failed" if record.index in unanswered or record.index in clusters_left else record.outcome
                for record in result.objects]
    # the zenoh link refuses state publications nothing it asked explains (hero_driver/zenoh_link/state_check.py)
    status, why, doubts = run_status(outcomes, log.events, driver.robot, getattr(driver, "refused_states", 0))
    status, why = onboard.judged(status, why, missing, truths, left_there)  # never found, or wrongly gone: failed
    history = _append_history(args, setup, learner, library, outcomes, table, log.events)
    for index, message in unanswered.items():
        print(f"csl: object {index} not handled: the robot did not answer in time ({message})", file=sys.stderr)
    for index in clusters_left:
        print(f"csl: object {index} not handled: touching objects the camera saw as one region (a cluster), "
              "left on the floor when no grasp held", file=sys.stderr)
    for line in doubts:  # what the robot said that was checked and found wanting (executive/exit_status.py)
        print(f"csl: {line}", file=sys.stderr)
    if missing:
        print(onboard.never_found_line(missing, truths), file=sys.stderr)
    if left_there:
        print(onboard.still_there_line(left_there), file=sys.stderr)
    if as_json:
        document = episode_json(table, ticks=result.ticks, wall_s=result.wall_s, out=args.out,
                                plots=not args.no_plots, library=library, library_created=created, status=status,
                                why=why)
        if scans:
            document["exploration"] = None if explored is None else dataclasses.asdict(explored)
            document["never_found"] = [t.name for t in missing] if truths else None
            document["gone_but_there"] = [t.name for t in left_there] if truths else None
        print_json(document)
        return status
    if library is not None and args.command == "demo":
        print(demo_library_line(library))
    elif library is not None:
        print(f"library: {library}{f' (new, seeded with {args.library_seed})' if created else ''}")
    print(f"history: {history} (csl library history)")
    print(f"exit status {status}: {why}")
    return status


def _append_history(args: argparse.Namespace, setup: Setup, learner: LearnerService, library: Path | None,
                    outcomes: list[str | None], table: list[Row], events: list[dict[str, object]]) -> Path:
    """One row for the learning history (reporting/history.py), whatever the exit status:
    a run that failed objects is a point on the curve too."""
    simulated = args.command == "demo" or args.driver == "sim"
    run = episode_run(command=args.command, robot=getattr(args, "robot", "r1"),
                      world=(args.world or "lab") if simulated else None, seed=(args.seed or 0) if simulated else None,
                      criterion=setup.criterion.name, outcomes=outcomes, robot_s=sum(r.robot_s for r in table),
                      events=events, library_size=len(learner.library().descriptions), library=library)
    path = default_history()
    append_run(path, run)
    return path


CLUSTER_NOTICE = ("the camera saw touching objects as one region (a cluster, docs/planner.md \"Clutter\"): "
                  "handled by grasping, no sonar")


def _say_battery_guard(driver: Driver, threshold: float) -> None:
    """One line when the low-battery guard cannot act: the driver has no battery
    feature (no charging dock it reports, or no ``charge`` verb)."""
    from behaviours.battery import dock_of

    if threshold > 0 and dock_of(driver) is None:
        print(f"battery: driver {driver.robot} has no battery feature (no charging dock): the low-battery "
              f"guard is off", file=sys.stderr)


def _say_blocked_branch(driver: Driver, tries: int) -> None:
    """One line when the blocked-move branch cannot act: the driver has no
    ``blocked_moves`` feature, so a move into a person or cart ends collided."""
    from behaviours.blocked import branch_off_notice

    notice = branch_off_notice(driver, tries)
    if notice is not None:
        print(notice, file=sys.stderr)


def _unanswered(events: list[dict[str, object]]) -> dict[int, str]:
    """Objects during which a verb timed out, with the first such verb's message.

    Whatever the tree decided after a verb the robot never answered rests on a
    measurement or a grasp that did not happen, so such an object is not handled,
    whatever its outcome says (exit status 1, not 0)."""
    found: dict[int, str] = {}
    for event in events:
        if event.get("event") == Event.DRIVER_ERROR and event.get("code") == TIMEOUT:
            index = event.get("object")
            if isinstance(index, int):
                found.setdefault(index, str(event.get("message")))
    return found


def _on_floor(driver: Driver) -> list[tuple[float, float] | None]:
    """Where each object the simulator holds is now, None for one that left the floor
    (held or put away); empty for a driver that is not the in-process simulator."""
    truth = getattr(driver, "truth", None)
    if truth is None:
        return []
    return [None if t.held or t.binned else (t.x_in, t.y_in) for t in truth()]


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
        name, ended_as = t.entry_id, None
        x, y = t.x_in, t.y_in
        if at_start:
            before = at_start[i]
            x, y = before.x_in, before.y_in
            if before.name != t.entry_id:
                name, ended_as = before.name, t.entry_id
        out.append(Truth(name, tuple(g.procedure for g in t.grasps), x, y, ended_as))
    return out


def _as_mapped(image: CameraImage, camera: Camera | None) -> CameraImage:
    """The image the map is drawn on: a real camera's rectified onto the floor, where
    the nominal mapping holds (the raw image is inches off at the corners)."""
    if camera is None:
        return image
    flat = camera.calibration.rectify(image.pixels)
    return CameraImage(pixels=flat.pixels, inches_per_pixel=flat.inches_per_pixel, origin_x_in=flat.origin_x_in,
                       origin_y_in=flat.origin_y_in, clock_s=image.clock_s, meta=image.meta)


def _plots(out: Path, executive: Executive, result: EpisodeResult, labels: list[str],
           events: list[dict[str, object]]) -> None:
    """Each object's run-time tree and the behaviour tree (the map is the perception's)."""
    for old in out.glob("tree-*.png"):
        old.unlink()
    for record, label in zip(result.objects, labels):
        plot_object_tree(out / f"tree-{record.index}.png", record, label, events)
    plot_behaviour_tree(out / "behaviour-tree.png", executive.root)
