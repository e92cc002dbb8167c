"""The simulated HERO 2000 as an in-process :class:`~hero_driver.interface.Driver`.

Every verb runs to completion before it returns and hands back a future that is
already done, so a behaviour tree ticking against it produces the same trace on every
run with the same seed. Besides the protocol, :meth:`SimulatedHero.truth` exposes the
world's ground truth for reports and training; the executive must not decide on it.
"""

from __future__ import annotations

import logging
from collections.abc import Callable, Sequence
from concurrent.futures import Future
from pathlib import Path
from typing import TypeVar

from camera_model.image import CameraImage
from hero_driver.interface import (
    BAD_REQUEST, UNAVAILABLE, DriverError, GraspResult, MoveResult, Pose, RangeScan, RobotState, SenseResult,
)
from hero_driver.sim.disturber import Happened
from hero_driver.sim.events import DisturbPreset
from hero_driver.sim.movers import MoverPreset, MoverTruth
from hero_driver.sim.noise import NoiseConfig
from hero_driver.sim.world import ObjectTruth, SimWorld
from hero_driver.sim.worldfile import WorldRefused, shelf_for
from robot_profile import RobotProfile

T = TypeVar("T")
log = logging.getLogger(__name__)


class SimulatedHero:
    """A simulated HERO 2000 in a pymunk world (see docs/simulator.md).

    ``profile`` is the robot it simulates (None: the shipped HERO 2000 profile): the
    executive passes the one it plans with, so procedure times, ranges and the base's
    size and speeds agree on both sides.

    ``world`` is trusted (it comes from whoever starts the driver) and may be a path;
    ``reset`` takes only a name from ``worlds_dir`` (None: the shipped worlds) or the
    start world's file stem (:class:`~hero_driver.sim.worldfile.WorldShelf`).

    ``camera`` is the overhead camera's preset: ``simple`` (grey bands) or
    ``realistic`` (what a real ceiling camera shows; docs/camera.md).

    ``disturb`` is the ``--disturb`` preset: objects nudged, taken away or swapped
    during their sensing (docs/simulator.md, Disturbances).

    ``movers`` is the ``--movers`` preset: people and carts crossing the floor; with
    ``stop_for_movers`` (the ``blocked_moves`` feature) a move stops short of one ahead,
    without it the base drives into them (docs/simulator.md, Moving obstacles).
    """

    def __init__(self, robot: str = "r1", world: str | Path | None = None, seed: int = 0,
                 profile: RobotProfile | None = None, noise: NoiseConfig | None = None,
                 worlds_dir: Path | None = None, camera: str = "simple",
                 disturb: DisturbPreset = DisturbPreset(), movers: MoverPreset = MoverPreset(),
                 stop_for_movers: bool = True) -> None:
        self.robot = robot
        self._sim: SimWorld | None = SimWorld(world, seed, profile, noise, camera, disturb, movers, stop_for_movers)
        self.worlds = shelf_for(world, worlds_dir)

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

    def dock(self) -> Pose | None:
        """The battery feature (:class:`~hero_driver.interface.Charger`): where the dock is."""
        return self._live().dock()

    def charge(self) -> Future[RobotState]:
        """The battery feature: charge at the dock."""
        return self._done(lambda sim: sim.charge())

    def safety_in(self) -> float | None:
        """The blocked_moves feature (:class:`~hero_driver.interface.BlockedMoves`):
        how near ahead a mover stops a move; None when this simulator ignores movers."""
        return self._live().safety_in()

    def wait(self, seconds: float) -> Future[RobotState]:
        """The blocked_moves feature: stand still while movers walk on."""
        return self._done(lambda sim: sim.wait(seconds))

    def scan(self) -> Future[RangeScan]:
        """The scan feature (:class:`~hero_driver.interface.Scanner`): one range scan of
        the profile's scanner where the robot stands."""
        return self._done(lambda sim: sim.scan())

    def reset(self, world: str | None = None, seed: int | None = None) -> Future[RobotState]:
        """Restore the world named ``world`` (None: the current one) with ``seed``
        (None: the current); a name the shelf refuses is ``bad_request``, and so is a
        negative seed, refused before anything is loaded (numpy's own refusal named no
        field, and came after the world had kept the bad seed for every later reset)."""
        def work(sim: SimWorld) -> RobotState:
            if seed is not None and seed < 0:
                raise DriverError(BAD_REQUEST, f"seed: expected a non-negative integer, got {seed}")
            spec = sim.spec if world is None else self.worlds.load(world, sim.catalogue)
            try:
                sim.load(spec, sim.seed if seed is None else seed)
            except ValueError as exc:  # the robot's start overlaps something: the message holds the path
                if world is None:
                    raise
                log.warning("world %r cannot be loaded: %s", world, exc)
                raise WorldRefused.cannot_load(world) from None
            return sim.state()
        return self._done(work)

    def close(self) -> None:
        self._sim = None

    # -- in-process helpers (not part of the Driver protocol) -----------------------

    def truth(self) -> list[ObjectTruth]:
        """Ground truth of every object, for reports, training and tests."""
        return self._live().truth()

    def disturbances(self) -> list[Happened]:
        """The disturbances that took place so far, for reports and tests."""
        return self._live().disturbances

    def movers(self) -> list[MoverTruth]:
        """Where the movers are now, for reports and tests."""
        return self._live().movers()

    @property
    def contacts(self) -> int:
        """How often the base touched anything since the last reset (ground truth)."""
        return self._live().contacts

    @property
    def last_side_effect(self) -> str:
        """What the last grasp did to its object: lifted, pushed, knocked_over,
        jammed or nothing (hero_driver.sim.grasping names them)."""
        return self._live().last_effect

    @property
    def world(self) -> SimWorld:
        """The simulated world itself, for probes and tests that stage a scene."""
        return self._live()
