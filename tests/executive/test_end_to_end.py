"""The executive end to end over real zenoh: the driver and the learner in their own
processes on 127.0.0.1, exactly as a hardware driver or a shared library would be."""

from __future__ import annotations

import json
import os
import subprocess
import sys
from pathlib import Path

import pytest

from hero_driver.zenoh_link.client import ZenohDriver
from learner.library.format import write_library_json
from learner.service.zenoh_client import ZenohLearner
from executive.defaults import EXAMPLE_LIBRARY
from executive.executive import Executive
from learner.library.format import read_library_json
from learner.service.local import LocalLearner
from tests.hero_driver.test_zenoh_support import DriverProcess
from tests.zenoh_rpc.support import free_endpoint, wait_until
from tests.learner.test_service_zenoh import ServiceProcess

REPO = Path(__file__).resolve().parents[2]
pytestmark = pytest.mark.zenoh


@pytest.mark.slow
def test_executive_drives_a_driver_process_over_zenoh(tmp_path: Path) -> None:
    endpoint = free_endpoint()
    with DriverProcess.sim(endpoint, robot="e2e") as node:
        node.ready()
        driver = ZenohDriver("e2e", connect=[endpoint], discover_s=5.0)
        assert driver.alive
        learner = LocalLearner(tmp_path / "library.sqlite", seed_library=read_library_json(EXAMPLE_LIBRARY))
        executive = Executive(driver, learner)
        result = executive.run()
        executive.shutdown()
        driver.close()
    assert result.status == "SUCCESS"
    assert len(result.objects) == 7  # the lab's test objects, found by the camera over zenoh
    assert all(o.outcome in ("grasped", "left", "failed") for o in result.objects)
    assert sum(o.outcome == "grasped" for o in result.objects) >= 4
    # every grasped object is learned from, unless nothing was measured on it and no grasp
    # failed first (the camera's appearance alone got it right: that teaches nothing new),
    # or nothing was measured and the camera gave no appearance (nothing to tell it apart by)
    learns = [e for e in executive.log.events if e["event"] == "learn"]
    assert len(learns) == sum(o.outcome == "grasped" for o in result.objects)
    assert all(e["id"] is not None or e["reason"].startswith("nothing was measured and ") for e in learns)
    stored = learner.library().descriptions
    assert sum(d.object_id.startswith("learned/") for d in stored) == sum(e["id"] is not None for e in learns)


@pytest.mark.slow
def test_csl_run_with_driver_and_learner_as_zenoh_nodes(tmp_path: Path) -> None:
    driver_ep, learner_ep = free_endpoint(), free_endpoint()
    seed = tmp_path / "seed.json"
    write_library_json(seed, read_library_json(EXAMPLE_LIBRARY))
    service = ServiceProcess(tmp_path / "shared.sqlite", learner_ep, seed, name="lab")
    try:
        service.ready()
        with DriverProcess.sim(driver_ep, robot="r7") as node:
            node.ready()
            env = {**os.environ, "PYTHONPATH": str(REPO)}
            proc = subprocess.run(
                [sys.executable, "-m", "csl_cli", "run", "--driver", "zenoh", "--robot", "r7",
                 "--connect", driver_ep, "--learner", "zenoh", "--learner-name", "lab",
                 "--learner-connect", learner_ep, "--out", str(tmp_path / "out"), "--no-plots"],
                cwd=REPO, env=env, capture_output=True, text=True, timeout=300)
        assert proc.returncode == 0, proc.stderr
        assert "7 objects:" in proc.stdout and "no truth to judge by" in proc.stdout
        events = [json.loads(line) for line in (tmp_path / "out" / "episode.jsonl").read_text().splitlines()]
        learned = [e for e in events if e["event"] == "learn"]
        assert learned
        other_robot = ZenohLearner("lab", connect=[learner_ep])
        ids = {d.object_id for d in other_robot.library().descriptions}
        # what r7 learned, every robot now sees (a learn with nothing measured stores nothing: id None)
        assert {e["id"] for e in learned if e["id"]} <= ids
        other_robot.close()
    finally:
        service.close()


@pytest.mark.slow
def test_a_driver_vanishing_mid_episode_stops_the_run_with_one_line(tmp_path: Path) -> None:
    endpoint = free_endpoint()
    env = {**os.environ, "PYTHONPATH": str(REPO), "CSL_HOME": str(tmp_path)}
    log = tmp_path / "out" / "episode.jsonl"
    with DriverProcess.sim(endpoint, robot="gone") as node:
        node.ready()
        run = subprocess.Popen(
            [sys.executable, "-m", "csl_cli", "run", "--driver", "zenoh", "--robot", "gone",
             "--connect", endpoint, "--out", str(tmp_path / "out"), "--no-plots"],
            cwd=REPO, env=env, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
        # Killed as soon as work on the first object starts: seven objects' worth of
        # verbs (dozens of round trips) are still ahead, so the episode cannot end first.
        assert wait_until(lambda: log.exists() and '"event": "object"' in log.read_text(), 60.0)
        node.kill()
        out, err = run.communicate(timeout=60)
    events = [json.loads(line) for line in log.read_text().splitlines()]
    assert events[-1]["event"] != "episode_end" and not any(e["event"] == "learn" for e in events[1:])
    assert run.returncode == 3, err  # robot lost (executive/exit_status.py)
    messages = [x for x in err.strip().splitlines() if x.startswith("csl:")]
    assert messages == [messages[-1]] and messages[-1].startswith("csl: robot error: unavailable")
    assert "Traceback" not in err
