"""Closing is quiet: a ``csl run`` whose driver or learner process is frozen (SIGSTOP)
ends without a traceback, and closing a zenoh session to a frozen peer raises nothing
(before the handshake was bounded it waited out zenoh's ten seconds and then raised
zenoh.ZError). Real processes throughout: the fault is between them.

How long closing takes is measured, not asserted: ``bench/bench_zenoh_failures.py``;
the bounded handshake itself is checked in tests/zenoh_rpc/test_settings.py.
"""

from __future__ import annotations

import os
import re
import signal
import subprocess
import sys
from collections.abc import Iterator
from pathlib import Path

import pytest

from executive.exit_status import LOST
from hero_driver.zenoh_link.client import ZenohDriver
from tests.hero_driver.test_zenoh_support import REPO, DriverProcess
from tests.zenoh_rpc.support import free_endpoint, wait_until

pytestmark = pytest.mark.zenoh

HANG_GUARD_S = 60.0  # only so that a hang fails the test instead of stopping the suite


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


def test_a_client_closes_without_error_after_its_driver_froze(frozen: list[int]) -> None:
    endpoint = free_endpoint()
    with DriverProcess.fake("good", endpoint) as driver:
        driver.ready()
        client = ZenohDriver("r1", connect=[endpoint], discover_s=5.0)
        assert client.wait_ready(5.0)
        os.kill(driver.process.pid, signal.SIGSTOP)
        frozen.append(driver.process.pid)
        assert client.wait_gone(5.0)  # the lease ran out; zenoh now retries the frozen peer
        client.close()  # raised zenoh.ZError after 10 s before the handshake was bounded


@pytest.mark.slow
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
            _, stderr = run.communicate(timeout=HANG_GUARD_S)  # ended in a 60-line traceback before the fix
        finally:
            run.kill()
    assert run.returncode == LOST
    assert "Traceback" not in stderr
    # the loss is the last line and the only one about it (earlier lines are start-up notes)
    # (frozen during the camera look before the next verb, or during that verb: a sense, or a move or
    # grasp when the camera's appearance left one grasp)
    assert re.match(r"csl: robot error: unavailable: (camera|sense|move|grasp): ", stderr.splitlines()[-1]), stderr
    assert sum("unavailable" in line for line in stderr.splitlines()) == 1, stderr


@pytest.mark.slow
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
            _, stderr = run.communicate(timeout=HANG_GUARD_S)
        finally:
            run.kill()
    assert run.returncode in (0, 1)  # the episode ran to its end; what it learned waits in the outbox
    assert "Traceback" not in stderr, stderr
