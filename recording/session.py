"""A recording of one episode: a Foxglove context with its sinks (an MCAP file, a live
WebSocket server, or both), the recorder on it, and the hooks that feed it from the
executive (its driver, its episode log, its ticks, each object handled)."""

from __future__ import annotations

import threading
import time
from pathlib import Path

import foxglove
import py_trees

from behaviours.records import ObjectRecord
from behaviours.services import namespace
from executive.episode_log import EpisodeLog
from recording.driver import RecordingDriver
from recording.live_server import LiveServer
from recording.recorder import Recorder
from recording.run_metadata import RUN_METADATA, RunDescription
from hero_driver.interface import Driver
from robot_profile.model import RobotGeometry

LIVE_HOST = "127.0.0.1"
LINGER_S = 2.0
"""Wall seconds the live view stays up after the episode while a viewer watches: the
server drops what it still queues for a client when it stops, so a viewer behind by a
few messages (a loaded machine) would never see the episode's end."""


class _Viewers:
    """The live server's listener: notes when a client first subscribes to a channel."""

    def __init__(self) -> None:
        self.subscribed = threading.Event()

    def on_subscribe(self, client: object, channel: object) -> None:
        self.subscribed.set()

    def on_unsubscribe(self, client: object, channel: object) -> None:
        """A client leaving changes nothing: the episode goes on (only the first
        subscription is waited for). Without it the server logs a failed callback."""


class Recording:
    """Where an episode is recorded to; :meth:`close` finishes the MCAP file and stops
    the server."""

    def __init__(self, geometry: RobotGeometry, *, mcap: Path | None = None, live_port: int | None = None,
                 live_host: str = LIVE_HOST, live_pace_s: float = 0.0) -> None:
        """``live_pace_s``: wall seconds to wait after each tick, so that a viewer can
        follow an in-process simulator (whose verbs take no wall time)."""
        if mcap is None and live_port is None:
            raise ValueError("a recording needs an MCAP file or a live port")
        self.context = foxglove.Context()
        self.mcap = mcap
        self.live_pace_s = live_pace_s
        self._viewers = _Viewers()
        self._writer = None if mcap is None else foxglove.open_mcap(mcap, allow_overwrite=True, context=self.context)
        try:
            self.server = None if live_port is None else LiveServer(
                self.context, host=live_host, port=live_port, name="csl-executive", server_listener=self._viewers)
        except BaseException:
            if self._writer is not None:
                self._writer.close()
            raise
        self.recorder = Recorder(self.context, geometry)
        self._driver: RecordingDriver | None = None

    @property
    def live_port(self) -> int | None:
        """The port the live view listens on (the one asked for, or the one given for 0)."""
        return None if self.server is None else self.server.port

    def wait_for_viewer(self, timeout_s: float | None = None) -> bool:
        """Block until a live client subscribes to a channel (True), or ``timeout_s``
        passes (False): messages sent before anyone listens are lost."""
        return self._viewers.subscribed.wait(timeout_s)

    def describe_run(self, run: RunDescription) -> None:
        """The MCAP file's ``csl-run`` metadata record (a live view has no such record)."""
        if self._writer is not None:
            self._writer.write_metadata(RUN_METADATA, run.record())

    def attach(self, driver: Driver, log: EpisodeLog) -> RecordingDriver:
        """Record ``driver``'s verbs and ``log``'s events; the executive is to drive the
        returned driver."""
        self._driver = RecordingDriver(driver, self.recorder)
        self.recorder.watch_blackboard(f"{namespace(driver.robot)}/")
        log.listeners.append(lambda record: self.recorder.event(record, self._clock()))
        state = self._driver.known_state()
        if state is not None:
            self.recorder.state(state)
        return self._driver

    def _clock(self) -> float:
        """The robot's clock as last known (0 before the driver has said)."""
        state = self._driver.known_state() if self._driver is not None else None
        return state.clock_s if state is not None else 0.0

    def tick(self, tick: int, root: py_trees.behaviour.Behaviour) -> None:
        """After every tick: where the robot is and the tree's status."""
        state = self._driver.known_state() if self._driver is not None else None
        if state is not None:
            self.recorder.state(state)
        self.recorder.tick(tick, root, state.clock_s if state is not None else 0.0)
        if self.live_pace_s > 0:
            time.sleep(self.live_pace_s)

    def handled(self, record: ObjectRecord, label: str) -> None:
        """An object the tree is done with, where it is now, with its outcome."""
        self.recorder.handled(record.index, record.region.polygon, label, record.grasp, record.outcome, self._clock())

    def close(self) -> None:
        if self._writer is not None:
            self._writer.close()
            self._writer = None
        if self.server is not None:
            if self._viewers.subscribed.is_set():
                time.sleep(LINGER_S)
            self.server.stop()
            self.server = None
