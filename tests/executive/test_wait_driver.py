"""``csl run --wait-driver SECONDS``: a driver process killed mid-episode (SIGKILL: its
liveliness token goes with it) and started again under the same robot name lets the run
finish every object; one that does not come back ends the run with one line and exit
status 3. Real processes on 127.0.0.1: the fault is between them.

The bounds on how long a run may take are hang guards, not timings.
"""

from __future__ import annotations

import json
import os
import subprocess
import sys
import time
from pathlib import Path

import pytest

from csl_cli.main import build_parser
from executive.exit_status import ALL_HANDLED, BAD_INPUT, LOST
from tests.hero_driver.test_zenoh_support import REPO, DriverProcess
from tests.zenoh_rpc.support import free_endpoint, wait_until

HANG_GUARD_S = 90.0  # a whole episode on the simulator takes seconds; this only catches a hang


def csl_run(endpoint: str, wait_s: float, out: Path) -> subprocess.Popen[str]:
    env = {**os.environ, "PYTHONPATH": os.pathsep.join(filter(None, [str(REPO), os.environ.get("PYTHONPATH")]))}
    return subprocess.Popen([sys.executable, "-m", "csl_cli", "run", "--driver", "zenoh", "--connect", endpoint,
                             "--wait-driver", f"{wait_s:g}", "--out", str(out), "--no-plots",
                             "--library", str(out.parent / "library.sqlite")],
                            cwd=REPO, env=env, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)


def events(out: Path) -> list[dict[str, object]]:
    log = out / "episode.jsonl"
    if not log.exists():
        return []
    return [json.loads(line) for line in log.read_text(encoding="utf-8").splitlines() if line.endswith("}")]


def working_on(out: Path, index: int) -> bool:
    """The executive has started on object ``index`` (its ``object`` event is logged)."""
    return any(e["event"] == "object" and e["object"] == index for e in events(out))


@pytest.mark.slow
@pytest.mark.zenoh
def test_a_driver_killed_and_restarted_under_the_same_name_lets_the_run_finish(tmp_path: Path) -> None:
    endpoint, out = free_endpoint(), tmp_path / "out"
    with DriverProcess.sim(endpoint) as first:
        first.ready()
        run = csl_run(endpoint, 20.0, out)
        try:
            assert wait_until(lambda: working_on(out, 1), HANG_GUARD_S), run.stderr.read() if run.stderr else ""
            first.kill()  # SIGKILL mid-episode: object 0 handled, object 1 in hand
            time.sleep(2.0)
            with DriverProcess.sim(endpoint) as second:  # the same robot name, 2 s later
                second.ready()
                said, err = run.communicate(timeout=HANG_GUARD_S)
        finally:
            run.kill()
    assert run.returncode == ALL_HANDLED, said + err
    assert "exit status 0: all 7 objects were handled" in said
    log = events(out)
    lost = [e for e in log if e["event"] == "driver_error"]
    assert lost and {e["code"] for e in lost} == {"unavailable"}
    [in_hand] = {e["object"] for e in lost}
    assert isinstance(in_hand, int) and in_hand >= 1  # the kill came once object 1 was started
    first_look, again = [e for e in log if e["event"] == "located"]
    assert again["again"].startswith("driver for r1 came back after ")
    seen = {tuple(r["centroid"]) for r in first_look["regions"]}
    # The restarted simulator put the world back: the objects handled before the kill are on the
    # floor again but stay handled, the one in hand is resumed, the others are queued again
    # (objects are started in the order they were first located).
    dealt_with = {tuple(r["centroid"]) for r in first_look["regions"][:in_hand + 1]}
    assert {tuple(r["centroid"]) for r in again["regions"]} == seen - dealt_with
    started = [tuple(e["centroid"]) for e in log if e["event"] == "object"]
    assert len(started) == 7 and set(started) == seen  # every object worked on exactly once


@pytest.mark.slow
@pytest.mark.zenoh
def test_a_driver_that_does_not_come_back_ends_the_run_in_one_line(tmp_path: Path) -> None:
    endpoint, out = free_endpoint(), tmp_path / "out"
    wait_s = 3.0
    with DriverProcess.sim(endpoint) as driver:
        driver.ready()
        run = csl_run(endpoint, wait_s, out)
        try:
            assert wait_until(lambda: working_on(out, 1), HANG_GUARD_S)
            driver.kill()
            killed = time.monotonic()
            said, err = run.communicate(timeout=HANG_GUARD_S)
            took = time.monotonic() - killed
        finally:
            run.kill()
    assert run.returncode == LOST
    [line] = [line for line in err.splitlines() if line.startswith("csl: ")][-1:]
    assert line == "csl: robot error: unavailable: no driver for robot r1 came back within 3 s"
    assert "Traceback" not in err
    print(f"exit {run.returncode} {took:.1f} s after the kill (wait {wait_s:g} s)")  # measured, reported in the docs


def run_args(*argv: str) -> object:
    return build_parser().parse_args(["run", *argv])


def test_the_flag_goes_with_a_driver_that_can_be_lost(tmp_path: Path) -> None:
    args = run_args("--wait-driver", "5", "--out", str(tmp_path / "out"))
    with pytest.raises(ValueError, match=r"^--wait-driver goes with --driver zenoh"):
        args.handler(args)  # type: ignore[attr-defined]


@pytest.mark.parametrize("text", ["-1", "nan", "inf", "soon"])
def test_bad_seconds_are_refused_in_one_line(text: str, capsys: pytest.CaptureFixture[str]) -> None:
    with pytest.raises(SystemExit) as exited:
        run_args("--driver", "zenoh", "--wait-driver", text)
    assert exited.value.code == BAD_INPUT
    [line] = [line for line in capsys.readouterr().err.splitlines() if "--wait-driver" in line and "error" in line]
    assert line.startswith("csl run: error: argument --wait-driver: ")


def test_the_default_is_to_stop_at_once() -> None:
    assert run_args().wait_driver == 0.0  # type: ignore[attr-defined]
