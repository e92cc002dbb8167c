"""Running episodes: build the tree around a driver and a learner, tick it to the end.

The executive knows the robot only through its ``Driver`` and the library only through
a ``LearnerService``: the same code runs the in-process simulator, a driver process
over zenoh, or a hardware driver.
"""

from __future__ import annotations

import time
from collections.abc import Callable
from dataclasses import dataclass, field

import py_trees
from py_trees.common import Status

from behaviours.base import DriverAction
from behaviours.localisation import CameraLocalised
from behaviours.overdue import OverdueRobot
from behaviours.records import ObjectRecord, reset_blackboard
from behaviours.reconnect import LocateAgain, WaitForDriver
from behaviours.services import LibraryMatrix, Params, Services, namespace
from executive.battery_cost import navigator_for
from executive.episode_log import EpisodeLog
from executive.grasp_attempts import LearnedGraspCosts
from executive.narration import tell_outcome
from executive.onboard import OnboardPerception
from executive.verb_log import VerbLog
from executive.behaviour_tree import build_tree
from hero_driver.interface import Driver, Scanner
from learner.choosing.criteria import CRITERIA, DEFAULT_CRITERION, Criterion
from learner.service.interface import KeepsGraspCosts, LearnerService
from planner.calibration import MarkerBoard
from planner.segmentation import Camera
from robot_profile import ProfileStamp, RobotProfile, load_profile

CEILING, ONBOARD = "ceiling", "onboard"
PERCEPTIONS = (CEILING, ONBOARD)
"""How the robot sees its floor: the overhead camera, or its own range scans."""

ONBOARD_PLAN_S = 2.0
"""Seconds a path may take to plan on the onboard map: a home's doorways are narrow
passages for a sampling planner (a lab's quarter second finds few of them), and one
move between rooms takes the robot minutes."""

OVERDUE_WAIT_S = 900.0
"""After a verb went unanswered, how long the executive waits for the robot to take
verbs again (:mod:`behaviours.overdue`): longer than a move's, sensing's or grasp's
bound on the driver's side (docs/driver-protocol.md, "Bounds"), so the robot finishing
what it was told never fails the next object."""


@dataclass
class EpisodeResult:
    """What one episode did: a record per object, the tick count, and the trace."""

    objects: list[ObjectRecord]
    ticks: int
    status: str
    trace: list[str] = field(default_factory=list)
    wall_s: float = 0.0


class Executive:
    """One robot's behaviour tree over a driver and a learner service."""

    def __init__(self, driver: Driver, learner: LearnerService, *, profile: RobotProfile | None = None,
                 params: Params = Params(), criterion: Criterion | None = None, log: EpisodeLog | None = None,
                 on_tick: Callable[[int, py_trees.behaviour.Behaviour], None] | None = None,
                 camera: Camera | None = None, board: MarkerBoard | None = None,
                 perception: str = CEILING) -> None:
        """``profile``: the robot (default: the shipped HERO 2000); the planner plans for
        its ``[robot]`` table and the learner knows its procedures, both from this one
        reading. ``on_tick(tick, root)`` sees the tree after every tick (a recording
        of its status). ``camera``: the calibrated overhead camera when the driver's
        images are real ones, or ``board`` to calibrate it from the first image
        (docs/camera.md); neither for band images. ``perception``: ``ceiling`` (the
        overhead camera, the paper's) or ``onboard`` (the robot's own scans, for a
        driver with the ``scan`` feature and no ceiling camera: ``executive.onboard``)."""
        if perception not in PERCEPTIONS:
            raise ValueError(f"perception must be one of {', '.join(PERCEPTIONS)}, got {perception!r}")
        onboard = perception == ONBOARD
        if onboard and not isinstance(driver, Scanner):
            raise ValueError(f"perception onboard: the driver for robot {driver.robot} offers no scans "
                             f"(the `scan` feature, docs/driver-protocol.md)")
        self.log = log or EpisodeLog()
        self.on_tick = on_tick
        profile = profile or load_profile()
        knowledge = profile.knowledge()
        driver = VerbLog(driver)  # each verb sent and its reply time, on the log (csl -v)
        # a verb refused busy after a timeout is sent again (behaviours.overdue); poses are
        # the overhead camera's, the driver's dead reckoning corrected (behaviours.localisation)
        localised = CameraLocalised(driver) if params.localise else driver
        navigator = navigator_for(profile.robot, localised, knowledge, params, camera=camera, board=board,
                                  **({"time_limit_s": ONBOARD_PLAN_S} if onboard else {}))
        self.perception = OnboardPerception(driver, navigator) if onboard else None  # scans in the driver's frame
        self.services = Services(
            driver=OverdueRobot(localised, OVERDUE_WAIT_S),
            navigator=navigator,
            perception=self.perception,  # type: ignore[arg-type]  # None: the ceiling camera
            learner=learner,
            knowledge=knowledge,
            criterion=criterion or CRITERIA[DEFAULT_CRITERION].build(), params=params, log=self.log,
            library=LibraryMatrix(learner, knowledge), served=_served(driver))
        self.grasp_costs = (  # docs/method.md §5.7: priced by what grasps cost, recorded after each object
            LearnedGraspCosts(learner, knowledge, self.services.library, self.log.events, self.log, driver.robot)
            if params.learned_grasp_costs and isinstance(learner, KeepsGraspCosts) else None)
        self.namespace = namespace(driver.robot)
        self.root = build_tree(driver.robot, explore=onboard)
        self.tree = py_trees.trees.BehaviourTree(self.root)
        self.tree.setup(services=self.services)
        self._snapshot = py_trees.visitors.SnapshotVisitor()
        self.tree.add_visitor(self._snapshot)

    def run(self, max_ticks: int | None = None, trace: bool = False,
            on_object: Callable[[ObjectRecord], None] | None = None) -> EpisodeResult:
        """Tick until the tree finishes (every object ends within ``Params.max_steps``
        steps, so no tick limit is needed; ``max_ticks`` is for tests). ``trace`` keeps
        one line per tick listing every behaviour ticked and its status (the snapshot
        tests' compact trace). A tree that did not finish is stopped, which cancels any
        verb still in flight."""
        reset_blackboard(self.services.driver.robot)
        lines: list[str] = []
        began = time.perf_counter()
        reported = 0
        tick = 0

        def report_finished(last: bool = False) -> list[ObjectRecord]:
            """Report each object once it is settled (a grasp verified by the camera:
            ``GraspVerified?``); at the ``last``, each one done."""
            nonlocal reported
            results = py_trees.blackboard.Blackboard.get(f"{self.namespace}/results")
            while reported < len(results) and (results[reported].settled or last and results[reported].done):
                if self.grasp_costs is not None:
                    self.grasp_costs.finished(results[reported])
                tell_outcome(results[reported])
                if on_object is not None:
                    on_object(results[reported])
                reported += 1
            return results

        try:
            while max_ticks is None or tick < max_ticks:
                tick += 1
                finished = self._tick(tick, trace, lines)
                report_finished()
                if finished:
                    break
        finally:
            if self.root.status == Status.RUNNING:
                self.root.stop(Status.INVALID)
        results = report_finished(last=True)
        self.log.event("episode_end", status=self.root.status.value, ticks=tick)
        return EpisodeResult(list(results), tick, self.root.status.value, lines, time.perf_counter() - began)

    def _tick(self, tick: int, trace: bool, lines: list[str]) -> bool:
        """One tick; True when the tree has finished."""
        self.log.tick = tick
        self.tree.tick()
        if self.on_tick is not None:
            self.on_tick(tick, self.root)
        if trace:
            lines.append(self._trace_line(tick))
        if self.root.status != Status.RUNNING:
            return True
        tip = self.root.tip()
        if isinstance(tip, (DriverAction, WaitForDriver, LocateAgain)) and tip.status == Status.RUNNING:
            time.sleep(0.001)  # a real robot is busy, or a driver is awaited: do not spin the CPU
        return False

    def _trace_line(self, tick: int) -> str:
        visited = self._snapshot.visited
        leaves = [b for b in self.root.iterate() if b.id in visited and not b.children]
        return f"{tick:4d} " + " ".join(f"{b.name}:{visited[b.id].value[0]}" for b in leaves)

    def shutdown(self) -> None:
        self.tree.shutdown()
        self.log.close()


def _served(driver: Driver) -> ProfileStamp | None:
    """The robot profile the driver says it serves (the zenoh client's ``profile``), to
    hold a driver that comes back to it; None when it does not say."""
    stamp = getattr(driver, "profile", None)
    return stamp if isinstance(stamp, ProfileStamp) else None
