"""The simulated HERO 2000 as an in-process :class:`~hero_driver.interface.Driver`.

Every verb runs to completion before it returns and hands back a future that is
already done, so a behaviour tree ticking against it produces the same trace on every
run with the same seed. Besides the protocol, :meth:`SimulatedHero.truth` exposes the
world's ground truth for reports and training; the executive must not decide on it.
"""

from __future__ import annotations

from collections.abc import Callable, Sequence
from concurrent.futures import Future
from pathlib import Path
from typing import TypeVar

from hero_driver.interface import (
    BAD_REQUEST, UNAVAILABLE, CameraImage, DriverError, GraspResult, MoveResult, Pose, RobotState, SenseResult,
)
from hero_driver.sim.noise import NoiseConfig
from hero_driver.sim.world import ObjectTruth, SimWorld
from hero_driver.sim.worldfile import load_world
from robot_profile import RobotProfile

T = TypeVar("T")


class SimulatedHero:
    """A simulated HERO 2000 in a pymunk world (see docs/simulator.md).

    ``profile`` is the robot it simulates (None: the shipped HERO 2000 profile): the
    executive passes the one it plans with, so procedure times, ranges and the base's
    size and speeds agree on both sides.
    """

    def __init__(self, robot: str = "r1", world: str | Path | None = None, seed: int = 0,
                 profile: RobotProfile | None = None, noise: NoiseConfig | None = None) -> None:
        self.robot = robot
        self._sim: SimWorld | None = SimWorld(world, seed, profile, noise)

    def _live(self) -> SimWorld:
        if self._sim is None:
            raise DriverError(UNAVAILABLE, f"driver {self.robot} is closed")
        return self._sim

    def _done(self, work: Callable[[SimWorld], T]) -> Future[T]:
        """Run a verb now and return its settled future; a world that is closed or a
        verb that is refused completes the future with a DriverError."""
        future: Future[T] = Future()
        try:
            future.set_result(work(self._live()))
        except DriverError as exc:
            future.set_exception(exc)
        except ValueError as exc:  # a bad world file or name given to reset
            future.set_exception(DriverError(BAD_REQUEST, str(exc)))
        return future

    def state(self) -> RobotState:
        return self._live().state()

    def move(self, waypoints: Sequence[Pose], face: tuple[float, float] | None = None) -> Future[MoveResult]:
        return self._done(lambda sim: sim.move(list(waypoints), face))

    def sense(self, procedure: str) -> Future[SenseResult]:
        return self._done(lambda sim: sim.sense(procedure))

    def grasp(self, procedure: str) -> Future[GraspResult]:
        return self._done(lambda sim: sim.grasp(procedure))

    def release(self) -> Future[RobotState]:
        return self._done(lambda sim: sim.release())

    def camera(self) -> Future[CameraImage]:
        return self._done(lambda sim: sim.camera())

    def reset(self, world: str | None = None, seed: int | None = None) -> Future[RobotState]:
        """Restore ``world`` (None: the current one) with ``seed`` (None: the current)."""
        def work(sim: SimWorld) -> RobotState:
            spec = sim.spec if world is None else load_world(world, sim.catalogue)
            sim.load(spec, sim.seed if seed is None else seed)
            return sim.state()
        return self._done(work)

    def close(self) -> None:
        self._sim = None

    # -- in-process helpers (not part of the Driver protocol) -----------------------

    def truth(self) -> list[ObjectTruth]:
        """Ground truth of every object, for reports, training and tests."""
        return self._live().truth()

    @property
    def last_side_effect(self) -> str:
        """What the last grasp did to its object: lifted, pushed, knocked_over,
        jammed or nothing (hero_driver.sim.grasping names them)."""
        return self._live().last_effect

    @property
    def world(self) -> SimWorld:
        """The simulated world itself, for probes and tests that stage a scene."""
        return self._live()
