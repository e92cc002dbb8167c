"""Shared pieces of the zenoh link tests: driver subprocesses that are
always killed, and small fake drivers (good, broken, slow, tokenless).

Run as ``python -m tests.hero_driver.test_zenoh_support KIND ROBOT ENDPOINT`` it
serves one fake in its own process until SIGTERM, so tests can talk to a driver
that really is another process. It holds no tests itself.
"""

from __future__ import annotations

import os
import signal
import subprocess
import sys
import threading
from collections.abc import Callable, Sequence
from concurrent.futures import Future
from pathlib import Path
from typing import TypeVar

import numpy as np
import zenoh

from camera_model.image import CameraImage
from hero_driver.interface import (
    NO_TARGET, UNKNOWN_PROCEDURE, DriverError, GraspResult, MoveResult, Pose, RobotState, SenseResult,
)
from hero_driver.zenoh_link.keys import robot_keys
from hero_driver.zenoh_link.node import serve
from zenoh_rpc.config import open_session

REPO = Path(__file__).resolve().parents[2]
START_TIMEOUT_S = 20.0  # a cold interpreter importing numpy, cv2 and zenoh on a busy box
T = TypeVar("T")


class DriverProcess:
    """A driver in a child process; :meth:`stop` or :meth:`kill` ends it, and leaving
    the ``with`` block always does."""

    def __init__(self, argv: Sequence[str]) -> None:
        env = {**os.environ, "PYTHONPATH": os.pathsep.join(filter(None, [str(REPO), os.environ.get("PYTHONPATH")]))}
        self.process = subprocess.Popen([sys.executable, *argv], cwd=REPO, env=env,
                                        stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)

    @classmethod
    def sim(cls, endpoint: str, robot: str = "r1") -> DriverProcess:
        return cls(["-m", "csl_cli", "driver", "sim", "--robot", robot, "--listen", endpoint])

    @classmethod
    def fake(cls, kind: str, endpoint: str, robot: str = "r1") -> DriverProcess:
        return cls(["-m", "tests.hero_driver.test_zenoh_support", kind, robot, endpoint])

    def ready(self) -> str:
        """Wait for the process's ready line (it prints one once every key is declared)."""
        line = self.process.stdout.readline() if self.process.stdout else ""
        if not line:
            self.process.wait(START_TIMEOUT_S)
            raise RuntimeError(f"driver process exited: {self.process.stderr.read() if self.process.stderr else ''}")
        return line

    def stop(self, signum: int = signal.SIGTERM) -> int:
        """Ask the driver to stop (SIGTERM, as a service manager would); its exit status."""
        if self.process.poll() is None:
            self.process.send_signal(signum)
        return self.process.wait(10)

    def kill(self) -> None:
        """SIGKILL: the process vanishes without undeclaring anything."""
        if self.process.poll() is None:
            self.process.kill()
        self.process.wait(10)

    def __enter__(self) -> DriverProcess:
        return self

    def __exit__(self, *_exc: object) -> None:
        self.kill()
        for stream in (self.process.stdout, self.process.stderr):
            if stream:
                stream.close()


# ------------------------------------------------------------------------ fake drivers


def done(value: T) -> Future[T]:
    future: Future[T] = Future()
    future.set_result(value)
    return future


def failed(error: Exception) -> Future[object]:
    future: Future[object] = Future()
    future.set_exception(error)
    return future


class FakeHero:
    """A deterministic driver: moves teleport, the sonar sees nothing in front."""

    SENSING = {"H-Sweep-5°": ("Width-Degree-5°", 45.0), "V-Sweep-5°": ("Height-Degree-5°", 42.0),
               "S-Sweep-1°": ("Depth-Degree-1°", 70.0)}
    GRASPING = {"Front-Pinch": 45.0}

    def __init__(self, robot: str = "r1") -> None:
        self.robot = robot
        self.pose = Pose(30.0, 30.0, 0.0)
        self.clock_s = 0.0

    def state(self) -> RobotState:
        return RobotState(self.pose, self.clock_s, 1.0)

    def move(self, waypoints: Sequence[Pose], face: tuple[float, float] | None = None) -> Future[MoveResult]:
        self.pose = waypoints[-1]
        self.clock_s += 10.0
        return done(MoveResult(self.pose, 10.0, False, face is not None))

    def sense(self, procedure: str) -> Future[SenseResult]:
        if procedure not in self.SENSING:
            raise DriverError(UNKNOWN_PROCEDURE, f"sense: unknown sensing procedure '{procedure}'")
        if self.pose.x_in > 100:  # far along: an object is in front
            feature, time_s = self.SENSING[procedure]
            self.clock_s += time_s
            return done(SenseResult(procedure, {feature: 31.5}, time_s, 20.0))
        return failed(DriverError(NO_TARGET, f"{procedure}: no object in front of the sonar"))

    def grasp(self, procedure: str) -> Future[GraspResult]:
        if procedure not in self.GRASPING:
            raise DriverError(UNKNOWN_PROCEDURE, f"grasp: unknown grasping procedure '{procedure}'")
        return failed(DriverError(NO_TARGET, f"{procedure}: no object in front of the hand"))

    def release(self) -> Future[RobotState]:
        return done(self.state())

    def camera(self) -> Future[CameraImage]:
        pixels = np.full((24, 32), 30, dtype=np.uint8)
        pixels[5:9, 10:14] = 220
        return done(CameraImage(pixels, 0.8, 0.0, 19.2, clock_s=self.clock_s, meta={"world": "fake"}))

    def reset(self, world: str | None = None, seed: int | None = None) -> Future[RobotState]:
        self.pose = Pose(30.0, 30.0, 0.0)
        self.clock_s = 0.0
        return done(self.state())

    def close(self) -> None:
        pass


class BrokenHero(FakeHero):
    """Breaks the protocol in three ways the conformance suite must name: sensing
    yields text instead of numbers, an unknown procedure crashes instead of being
    refused, and reset does not restart the clock."""

    def sense(self, procedure: str) -> Future[SenseResult]:
        self.SENSING[procedure]  # KeyError for an unknown procedure
        return done(SenseResult(procedure, {"Width-Degree-5°": "wide"}, 45.0, 20.0))  # type: ignore[dict-item]

    def reset(self, world: str | None = None, seed: int | None = None) -> Future[RobotState]:
        self.pose = Pose(30.0, 30.0, 0.0)
        return done(self.state())


class SlowHero(FakeHero):
    """Moves finish only when the test says so (:meth:`finish_move`)."""

    def __init__(self, robot: str = "r1") -> None:
        super().__init__(robot)
        self.moving: Future[MoveResult] | None = None

    def move(self, waypoints: Sequence[Pose], face: tuple[float, float] | None = None) -> Future[MoveResult]:
        self.moving = Future()
        self.pose = waypoints[-1]
        return self.moving

    def finish_move(self) -> None:
        assert self.moving is not None
        self.moving.set_result(MoveResult(self.pose, 10.0, False, False))


class HangingHero(FakeHero):
    """The first ``sense`` never completes by itself: a driver whose sonar hung. Its
    future stays pending (cancellable, so the node's bound can cancel it) unless
    ``running`` marks it started, as a driver that cannot stop its action would."""

    def __init__(self, robot: str = "r1", running: bool = False) -> None:
        super().__init__(robot)
        self.running = running
        self.hung: Future[SenseResult] | None = None

    def sense(self, procedure: str) -> Future[SenseResult]:
        if self.hung is not None:
            return super().sense(procedure)
        self.hung = Future()
        if self.running:
            self.hung.set_running_or_notify_cancel()
        return self.hung


class HangingSim:
    """The simulated HERO whose first ``sense`` never completes by itself (a driver that
    never answers one sense); every other verb is the simulator's."""

    def __new__(cls, robot: str = "r1") -> object:
        from hero_driver.sim_driver import SimulatedHero  # pymunk: only in the process that serves it

        class Hanging(SimulatedHero):
            hung: Future[SenseResult] | None = None

            def sense(self, procedure: str) -> Future[SenseResult]:
                if self.hung is None:
                    self.hung = Future()
                    return self.hung
                return super().sense(procedure)

        return Hanging(robot)


def serve_tokenless(robot: str, endpoint: str, stop: threading.Event, on_ready: Callable[[], None]) -> None:
    """A hand-written driver that forgets the liveliness token and the state
    publications but answers ``noop`` properly: what a first hardware attempt in
    another language might look like."""
    with open_session(listen=[endpoint]) as session:
        def on_query(query: zenoh.Query) -> None:
            query.reply(query.key_expr, b'{"v":1}', encoding=zenoh.Encoding.APPLICATION_JSON)

        queryable = session.declare_queryable(robot_keys(robot).rpc("noop"), on_query)
        on_ready()
        stop.wait()
        queryable.undeclare()


FAKES: dict[str, Callable[[str], object]] = {"good": FakeHero, "broken": BrokenHero, "hang": HangingHero,
                                                "sim-hang": HangingSim}


def main(argv: Sequence[str]) -> int:
    """``KIND ROBOT ENDPOINT [SENSE_BOUND_S]``: the optional bound overrides the node's
    bound on ``sense`` (the "hang" fake with a bound longer than the client's timeout
    is a driver that never answers one sense, as far as the client can tell)."""
    kind, robot, endpoint, *bound = argv
    stop = threading.Event()
    signal.signal(signal.SIGTERM, lambda *_: stop.set())

    def on_ready() -> None:
        print("ready", flush=True)

    if kind == "tokenless":
        serve_tokenless(robot, endpoint, stop, on_ready)
    else:
        serve(FAKES[kind](robot), listen=[endpoint], stop=stop, on_ready=on_ready,  # type: ignore[arg-type]
              bounds={"sense": float(bound[0])} if bound else None)
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
