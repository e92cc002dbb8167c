"""No grasp is lost, with real processes: ``csl learner serve`` is killed (SIGKILL) and
restarted again and again while ``csl run --learner zenoh`` episodes grasp and learn;
at the end every grasped object's description is in the library exactly once."""

from __future__ import annotations

import json
import os
import select
import signal
import sqlite3
import subprocess
import sys
import time
from collections import Counter
from contextlib import closing
from pathlib import Path

import pytest

from executive.defaults import EXAMPLE_LIBRARY
from learner.library.format import write_library_json
from learner.service.outbox import QUEUED_PREFIX
from learner.service.zenoh_client import ZenohLearner
from tests.learner.fixtures import P, desc, four_objects
from tests.learner.test_service_zenoh import REPO, ServiceProcess
from tests.zenoh_rpc.support import free_endpoint

pytestmark = [pytest.mark.zenoh, pytest.mark.slow]

# Each disturbed episode kills the service once the robot has handled each of these
# objects (restarting it at once), so six kills cost two episodes' start-up, not six.
KILLED_AFTER = ("object 0:", "object 2:", "object 4:")
DISTURBED = 2  # episodes with kills; one more runs undisturbed and delivers what waits
RUN_TIMEOUT_S = 60.0
MUG = desc("mug", "Front-Wrap", ("Width-Degree-1°", P(24, 0), 10), ("Front-Hole?", P(6, None), 1))


def start_run(out: Path, endpoint: str, outbox: Path, seed: int) -> subprocess.Popen[str]:
    env = {**os.environ, "PYTHONPATH": os.pathsep.join(filter(None, [str(REPO), os.environ.get("PYTHONPATH")]))}
    return subprocess.Popen(
        [sys.executable, "-m", "csl_cli", "run", "--learner", "zenoh", "--learner-name", "test",
         "--learner-connect", endpoint, "--outbox", str(outbox), "--seed", str(seed), "--no-plots",
         "--out", str(out),
         # sensing first, so that most objects send a description: the kills need learns to interrupt
         "--no-appearance"],
        cwd=REPO, env=env, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)


def wait_for_line(stream: object, text: str, timeout_s: float) -> bool:
    """Read ``stream`` until a line containing ``text`` (True) or EOF/timeout (False)."""
    deadline = time.monotonic() + timeout_s
    while time.monotonic() < deadline:
        readable, _, _ = select.select([stream], [], [], max(0.0, deadline - time.monotonic()))
        if not readable:
            return False
        line = stream.readline()  # type: ignore[attr-defined]
        if not line:
            return False
        if text in line:
            return True
    return False


def learned(log: Path) -> list[dict[str, object]]:
    """The episode log's learn events that sent a description (features measured, or a
    lesson saved by its appearance: an id either way)."""
    events = [json.loads(line) for line in log.read_text(encoding="utf-8").splitlines()]
    return [e for e in events if e.get("event") == "learn" and e.get("id") is not None]


def test_killing_the_service_during_episodes_loses_and_duplicates_nothing(tmp_path: Path) -> None:
    seed = EXAMPLE_LIBRARY  # the robot's own library: it recognises and grasps the lab's objects
    db, outbox, endpoint = tmp_path / "lib.sqlite", tmp_path / "outbox.sqlite", free_endpoint()
    service = ServiceProcess(db, endpoint, seed)
    service.ready()
    logs: list[Path] = []
    queued = 0
    try:
        for episode in range(DISTURBED + 1):
            out = tmp_path / f"episode-{episode}"
            run = start_run(out, endpoint, outbox, seed=episode)
            try:
                for line in KILLED_AFTER if episode < DISTURBED else ():
                    # killed mid-episode, then back and serving (its queued learns arriving) until the next
                    assert wait_for_line(run.stderr, line, RUN_TIMEOUT_S), f"the episode never reached {line!r}"
                    service.process.send_signal(signal.SIGKILL)
                    service.close()
                    service = ServiceProcess(db, endpoint, seed)
                    service.ready()
                stdout, stderr = run.communicate(timeout=RUN_TIMEOUT_S)
            finally:
                if run.poll() is None:
                    run.kill()
                    run.wait()
            assert run.returncode in (0, 1), stderr  # objects may fail; the learner's loss must not stop it
            logs.append(out / "episode.jsonl")
            queued += sum(str(e["id"]).startswith(QUEUED_PREFIX) for e in learned(out / "episode.jsonl"))
    finally:
        service.close()

    events = [e for log in logs for e in learned(log)]
    assert len(events) >= 2 * (DISTURBED + 1)  # the episodes grasped and learned, twice an episode or more
    assert queued >= 1  # the kills did land while the robot was learning
    with closing(sqlite3.connect(db)) as library, closing(sqlite3.connect(outbox)) as box:
        rows = library.execute("SELECT d.grasp, count(o.feature), d.learn_key FROM descriptions d "
                               "LEFT JOIN observations o ON o.description_seq = d.seq "
                               "WHERE d.learn_key IS NOT NULL GROUP BY d.seq").fetchall()
        waiting = box.execute("SELECT count(*) FROM outbox").fetchone()[0]
    assert waiting == 0
    assert len(rows) == len(events)  # each grasp exactly once: none lost, none stored twice
    assert len({key for _, _, key in rows}) == len(rows)
    assert Counter((g, n) for g, n, _ in rows) == Counter((e["grasp"], e["features"]) for e in events)


def test_a_learn_resent_over_zenoh_with_its_key_is_stored_once(tmp_path: Path) -> None:
    seed = tmp_path / "seed.json"
    write_library_json(seed, four_objects())
    service = ServiceProcess(tmp_path / "lib.sqlite", free_endpoint(), seed)
    try:
        service.ready()
        with ZenohLearner(service.name, connect=[service.endpoint], timeout_s=3.0) as robot:
            assert robot.learn(MUG, "k1") == "mug"
            assert robot.learn(MUG, "k1") == "mug"
            assert robot.learn(MUG) == "mug#2"
            assert [d.object_id for d in robot.library().descriptions][-2:] == ["mug", "mug#2"]
    finally:
        service.close()
