"""Closing is quick and quiet: a ``csl run`` whose driver or learner
process is frozen (SIGSTOP) ends without a traceback, and closing its zenoh sessions
no longer waits out zenoh's ten-second handshake timeout. Real processes throughout:
the fault is between them.

The bounds below are hang guards chosen well under what the faults cost before the
fix (an 11 s exit after a frozen driver; 10 s in a session's close), not timings.
"""

from __future__ import annotations

import os
import re
import signal
import subprocess
import sys
import time
from collections.abc import Iterator
from pathlib import Path

import pytest

from executive.exit_status import LOST
from hero_driver.zenoh_link.client import ZenohDriver
from tests.hero_driver.test_zenoh_support import REPO, DriverProcess
from tests.zenoh_rpc.support import free_endpoint, wait_until

pytestmark = pytest.mark.zenoh

BEFORE_THE_FIX_S = 10.0  # zenoh's default handshake timeout, which every close waited out


def csl(*argv: str, home: Path) -> subprocess.Popen[str]:
    env = {**os.environ, "CSL_HOME": str(home),
           "PYTHONPATH": os.pathsep.join(filter(None, [str(REPO), os.environ.get("PYTHONPATH")]))}
    return subprocess.Popen([sys.executable, "-m", "csl_cli", *argv], cwd=REPO, env=env,
                            stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)


@pytest.fixture
def frozen() -> Iterator[list[int]]:
    """Pids the test stopped; each is continued afterwards so it can be killed."""
    pids: list[int] = []
    yield pids
    for pid in pids:
        try:
            os.kill(pid, signal.SIGCONT)
        except ProcessLookupError:
            pass


def test_a_client_closes_at_once_after_its_driver_froze(frozen: list[int]) -> None:
    endpoint = free_endpoint()
    with DriverProcess.fake("good", endpoint) as driver:
        driver.ready()
        client = ZenohDriver("r1", connect=[endpoint], discover_s=5.0)
        assert client.wait_ready(5.0)
        os.kill(driver.process.pid, signal.SIGSTOP)
        frozen.append(driver.process.pid)
        assert client.wait_gone(5.0)  # the lease ran out; zenoh now retries the frozen peer
        started = time.monotonic()
        client.close()  # raised zenoh.ZError after 10 s before the handshake was bounded
        assert time.monotonic() - started < BEFORE_THE_FIX_S / 2


def test_csl_run_with_a_frozen_driver_exits_lost_in_one_line(tmp_path: Path, frozen: list[int]) -> None:
    endpoint = free_endpoint()
    out = tmp_path / "out"
    with DriverProcess.fake("sim-hang", endpoint) as driver:  # its first sense never answers
        driver.ready()
        run = csl("run", "--driver", "zenoh", "--connect", endpoint, "--out", str(out), "--no-plots",
                  "--library", str(tmp_path / "library.sqlite"), home=tmp_path)
        try:
            log = out / "episode.jsonl"
            moved = '"event": "move"'
            assert wait_until(lambda: log.exists() and moved in log.read_text() or run.poll() is not None, 60.0,
                              step_s=0.1)
            assert run.poll() is None  # moved; now waiting on the sense that never comes
            os.kill(driver.process.pid, signal.SIGSTOP)
            frozen.append(driver.process.pid)
            _, stderr = run.communicate(timeout=BEFORE_THE_FIX_S)  # was 11 s, ending in a 60-line traceback
        finally:
            run.kill()
    assert run.returncode == LOST
    assert "Traceback" not in stderr
    # the loss is the last line and the only one about it (earlier lines are start-up notes)
    # (frozen during the camera look before the next verb, or during that verb: a sense, or a move or
    # grasp when the camera's appearance left one grasp)
    assert re.match(r"csl: robot error: unavailable: (camera|sense|move|grasp): ", stderr.splitlines()[-1]), stderr
    assert sum("unavailable" in line for line in stderr.splitlines()) == 1, stderr


def test_csl_run_with_a_frozen_learner_finishes_and_closes_quietly(tmp_path: Path, frozen: list[int]) -> None:
    driver_at, learner_at = free_endpoint(), free_endpoint()
    out = tmp_path / "out"
    learner_argv = ["-m", "csl_cli", "learner", "serve", "--name", "t", "--listen", learner_at,
                    "--db", str(tmp_path / "library.sqlite")]
    with DriverProcess.sim(driver_at) as driver, DriverProcess(learner_argv) as learner:
        driver.ready()
        learner.ready()
        run = csl("run", "--driver", "zenoh", "--connect", driver_at, "--learner", "zenoh", "--learner-name", "t",
                  "--learner-connect", learner_at, "--out", str(out), "--no-plots", home=tmp_path)
        try:
            log = out / "episode.jsonl"
            moved = '"event": "move"'
            assert wait_until(lambda: log.exists() and moved in log.read_text() or run.poll() is not None, 60.0,
                              step_s=0.1)
            os.kill(learner.process.pid, signal.SIGSTOP)
            frozen.append(learner.process.pid)
            assert run.stdout is not None
            said = ""
            while not said.startswith("exit status"):  # the report, then the sessions close
                said = run.stdout.readline()
                assert said, "csl run ended without its exit status line"
            reported = time.monotonic()
            _, stderr = run.communicate(timeout=60.0)
            closing_s = time.monotonic() - reported
        finally:
            run.kill()
    assert run.returncode in (0, 1)  # the episode ran to its end; what it learned waits in the outbox
    assert "Traceback" not in stderr, stderr
    assert closing_s < BEFORE_THE_FIX_S / 2
