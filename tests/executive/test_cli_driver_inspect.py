"""``csl driver state`` and ``csl driver call`` (looking at a running robot by hand, as
``ros2 topic echo`` and ``ros2 service call`` do) and ``csl driver check --json``, as
real processes against ``csl -v driver sim`` on 127.0.0.1."""

from __future__ import annotations

import json
import os
import select
import signal
import subprocess
import sys
from collections.abc import Iterator
from dataclasses import dataclass
from pathlib import Path

import pytest

from csl_cli.main import main
from hero_driver.zenoh_link.codec import decode_state
from hero_driver.zenoh_link.verbs import NAMES
from robot_profile import DEFAULT_PROFILE, load_profile, profile_stamp
from tests.zenoh_rpc.support import free_endpoint
from zenoh_rpc.options import CONFIG_ENV

pytestmark = pytest.mark.zenoh

REPO = Path(__file__).resolve().parents[2]
START_TIMEOUT_S = 30.0  # a cold interpreter importing numpy, pymunk and zenoh on a busy box
RUN_TIMEOUT_S = 120.0
ROBOT = "inspect1"


def _env() -> dict[str, str]:
    env = {k: v for k, v in os.environ.items() if k != CONFIG_ENV}
    env["PYTHONPATH"] = os.pathsep.join(filter(None, [str(REPO), os.environ.get("PYTHONPATH")]))
    return env


def _csl(*argv: str) -> subprocess.CompletedProcess[str]:
    return subprocess.run([sys.executable, "-m", "csl_cli", *argv], cwd=REPO, env=_env(),
                          capture_output=True, text=True, timeout=RUN_TIMEOUT_S)


@dataclass
class Sim:
    endpoint: str
    process: subprocess.Popen[str]

    def stop(self) -> str:
        """Stop the driver (SIGINT, as Ctrl-C) and return what it logged."""
        self.process.send_signal(signal.SIGINT)
        _, err = self.process.communicate(timeout=RUN_TIMEOUT_S)
        return err


@pytest.fixture
def sim() -> Iterator[Sim]:
    """``csl -v driver sim --noise clean`` as a child process."""
    endpoint = free_endpoint()
    process = subprocess.Popen([sys.executable, "-m", "csl_cli", "-v", "driver", "sim", "--robot", ROBOT,
                                "--noise", "clean", "--listen", endpoint], cwd=REPO, env=_env(),
                               stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
    try:
        assert process.stdout is not None
        readable, _, _ = select.select([process.stdout], [], [], START_TIMEOUT_S)
        line = process.stdout.readline() if readable else ""
        if not line.startswith(f"serving hero/{ROBOT}/rpc/*"):
            process.kill()
            pytest.fail(f"csl driver sim did not start: {line}{process.communicate()[1]}")
        yield Sim(endpoint, process)
    finally:
        if process.poll() is None:
            process.kill()
            process.communicate()


@pytest.mark.slow
def test_call_and_state_against_a_running_driver(sim: Sim) -> None:
    at = ("--connect", sim.endpoint)
    noop = _csl("driver", "call", ROBOT, "noop", *at)
    assert (noop.returncode, noop.stdout) == (0, '{"v": 1}\n')

    hello = json.loads(_csl("driver", "call", ROBOT, "hello", *at).stdout)
    assert hello["profile"] == {"name": "hero2000", "sha256": profile_stamp(load_profile(DEFAULT_PROFILE)).sha256}

    # clean noise: the robot ends exactly on the waypoint, and its clock is the move's duration
    goal = {"x_in": 40.0, "y_in": 30.0, "heading_deg": 90.0}
    moved = _csl("driver", "call", ROBOT, "move", json.dumps({"waypoints": [goal]}), *at)
    assert moved.returncode == 0, moved.stderr
    reply = json.loads(moved.stdout)
    assert reply["pose"] == goal and reply["collided"] is False and reply["duration_s"] > 0

    echoed = _csl("driver", "state", ROBOT, "--count", "3", *at)
    assert echoed.returncode == 0, echoed.stderr
    lines = echoed.stdout.splitlines()
    assert len(lines) == 3  # one message a line, exactly --count of them
    for line in lines:
        state = decode_state(line.encode())  # each a valid state message, as sent
        assert (state.pose.x_in, state.pose.y_in, state.pose.heading_deg) == (40.0, 30.0, 90.0)
        assert state.clock_s == reply["duration_s"] and 0 < state.battery < 1

    refused = _csl("driver", "call", ROBOT, "sense", '{"procedure": "No-Such-Scan"}', *at)
    assert refused.returncode == 1  # the driver's error reply, printed as it was sent
    assert json.loads(refused.stdout)["code"] == "unknown_procedure"

    log = sim.stop()  # -v: the driver logged one info line per request
    assert f"INFO zenoh_rpc.server: hero/{ROBOT}/rpc/move: ok" in log


@pytest.mark.slow
def test_driver_check_json(sim: Sim) -> None:
    checked = _csl("driver", "check", "--robot", ROBOT, "--connect", sim.endpoint, "--json")
    doc = json.loads(checked.stdout)  # all of stdout: one document, no table
    assert doc["robot"] == ROBOT and len(doc["checks"]) >= 10
    assert doc["failed"] == sum(not c["passed"] for c in doc["checks"])
    assert doc["passed"] + doc["failed"] == len(doc["checks"])
    assert {"liveliness", "noop", "hello"} <= {c["name"] for c in doc["checks"]}
    assert checked.returncode == (0 if doc["failed"] == 0 else 1) and doc["failed"] == 0


@pytest.mark.slow
def test_nobody_serving_is_exit_3_and_says_how_to_start_one() -> None:
    endpoint = free_endpoint()
    for argv in (["driver", "state", "ghost", "--timeout", "0.5"],
                 ["driver", "call", "ghost", "noop", "--timeout", "1"]):
        result = _csl(*argv, "--connect", endpoint)
        err = result.stderr.strip().splitlines()
        assert result.returncode == 3 and len(err) == 1, result.stderr
        assert err[0].startswith("csl: robot error: unavailable: ") and "'csl driver sim --robot ghost'" in err[0]


@pytest.mark.parametrize(
    ("argv", "message"),
    [
        (["noop", "{not json"], "REQUEST: not JSON: Expecting property name enclosed in double quotes at column 2"),
        (["noop", "[1, 2]"], "REQUEST: expected a JSON object"),
        (["sense", "{}"], "REQUEST: procedure: missing field"),
        (["move", '{"waypoints": [{"x_in": 1, "y_in": NaN, "heading_deg": 0}]}'], "REQUEST: waypoints[0].y_in"),
        (["fly"], f"VERB: unknown verb 'fly' (verbs: {', '.join(NAMES)})"),
    ],
)
def test_bad_requests_are_one_line_exit_2_before_anything_is_sent(argv: list[str], message: str,
                                                                 capsys) -> None:  # noqa: ANN001
    # no driver and no endpoint needed: the request is checked as the driver would check it first
    assert main(["driver", "call", "r1", *argv, "--connect", "tcp/127.0.0.1:9"]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and err[0].startswith(f"csl: error: {message}")
