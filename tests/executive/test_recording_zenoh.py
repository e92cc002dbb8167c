"""A recording over zenoh: the driver's replies arrive on zenoh's threads, and the file
still holds every move, reading and event in robot-time order."""

from __future__ import annotations

import json
from pathlib import Path

import pytest
from mcap.reader import make_reader

from executive.defaults import EXAMPLE_LIBRARY
from executive.episode_log import EpisodeLog
from executive.executive import Executive
from recording import topics
from recording.session import Recording
from hero_driver.zenoh_link.client import ZenohDriver
from learner.library.format import read_library_json
from learner.service.local import LocalLearner
from robot_profile import load_profile
from tests.hero_driver.test_zenoh_support import DriverProcess
from tests.zenoh_rpc.support import free_endpoint

REPO = Path(__file__).resolve().parents[2]
pytestmark = pytest.mark.zenoh


def _two_objects(folder: Path) -> Path:
    """The lab with its first two objects: a short episode, several moves and readings."""
    lab = json.loads((REPO / "hero_driver" / "worlds" / "lab.json").read_text(encoding="utf-8"))
    lab["name"], lab["objects"] = "lab-two", lab["objects"][:2]
    path = folder / "lab-two.json"
    path.write_text(json.dumps(lab), encoding="utf-8")
    return path


def test_an_episode_over_zenoh_is_recorded_whole(tmp_path: Path) -> None:
    endpoint = free_endpoint()
    mcap = tmp_path / "zenoh.mcap"
    recording = Recording(load_profile().robot.geometry, mcap=mcap)
    log = EpisodeLog()
    with DriverProcess(["-m", "csl_cli", "driver", "sim", "--robot", "rec", "--listen", endpoint,
                        "--world", str(_two_objects(tmp_path))]) as node:
        node.ready()
        zenoh_driver = ZenohDriver("rec", connect=[endpoint], discover_s=5.0)
        learner = LocalLearner(tmp_path / "library.sqlite", seed_library=read_library_json(EXAMPLE_LIBRARY))
        try:
            assert zenoh_driver.wait_ready(5.0)  # as csl run waits: alive and its first state published
            executive = Executive(recording.attach(zenoh_driver, log), learner, log=log, on_tick=recording.tick)
            try:
                result = executive.run(on_object=lambda record: recording.handled(record, "?"))
            finally:
                executive.shutdown()
        finally:
            zenoh_driver.close()
            learner.close()
            recording.close()
    assert result.status == "SUCCESS" and len(result.objects) == 2
    with mcap.open("rb") as f:
        messages = [(channel.topic, message) for _, channel, message in make_reader(f).iter_messages()]
    on = {t.name: [m for topic, m in messages if topic == t.name] for t in topics.ALL}
    assert [json.loads(m.data) for m in on[topics.EVENTS.name]] == log.events
    assert len(on[topics.PATHS.name]) == sum(e["event"] == "move" for e in log.events)
    assert len(on[topics.SONAR.name]) == sum(e["event"] in ("sense", "discriminate") and "procedure" in e
                                             for e in log.events)
    assert len(on[topics.STATUS.name]) == result.ticks
    times = [m.log_time for m in on[topics.TF.name]]
    assert times == sorted(times) and len(set(times)) == len(times)
