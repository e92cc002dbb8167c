"""``csl driver check``: passes against the simulated HERO, and against broken driver
processes fails exactly the checks that name what they break."""

from __future__ import annotations

import re

import pytest

from executive.cli import main
from hero_driver.zenoh_link.conformance import Procedures
from tests.hero_driver.test_zenoh_support import DriverProcess
from tests.zenoh_rpc.support import free_endpoint
from zenoh_rpc.config import open_session

pytestmark = pytest.mark.zenoh

ALL_CHECKS = {
    "liveliness", "state-published", "noop", "hello", "reset", "camera", "camera-mapping", "move",
    "state-after-move", "busy", "sense", "grasp", "release", "out-of-range-target", "unknown-verb",
    "unknown-procedure", "malformed-json", "not-utf8", "not-an-object", "wildcard-silence", "wrong-types",
    "missing-field", "unknown-field", "non-finite-number", "wrong-version", "keeps-serving",
}


def run_check(endpoint: str, robot: str, capsys: pytest.CaptureFixture[str],
              timeout_s: float = 10.0) -> tuple[int, dict[str, str]]:
    """Exit status and each named check's PASS/FAIL from the printed table."""
    status = main(["driver", "check", "--robot", robot, "--connect", endpoint,
                   "--timeout", str(timeout_s)])
    table = capsys.readouterr().out
    verdicts = dict(re.findall(r"^(\S+)\s+(PASS|FAIL)\s", table, re.MULTILINE))
    return status, verdicts


def failed(verdicts: dict[str, str]) -> set[str]:
    return {name for name, verdict in verdicts.items() if verdict == "FAIL"}


def test_the_simulated_hero_passes_every_check(capsys: pytest.CaptureFixture[str]) -> None:
    endpoint = free_endpoint()
    with DriverProcess.sim(endpoint, robot="conf") as process:
        process.ready()
        status, verdicts = run_check(endpoint, "conf", capsys)
    assert set(verdicts) == ALL_CHECKS
    assert failed(verdicts) == set()
    assert status == 0


def test_a_broken_driver_fails_the_checks_it_breaks(capsys: pytest.CaptureFixture[str]) -> None:
    endpoint = free_endpoint()
    with DriverProcess.fake("broken", endpoint, robot="broken") as process:
        process.ready()
        status, verdicts = run_check(endpoint, "broken", capsys)
    # Text feature values (from a sonar that never refuses, so nothing is out of
    # range either), a crash on an unknown procedure, a clock that survives reset,
    # and (as every FakeHero) an image without the robot in it.
    assert failed(verdicts) == {"sense", "out-of-range-target", "unknown-procedure", "reset", "camera-mapping"}
    assert status == 1


def test_a_driver_without_token_or_state_fails_those_checks(capsys: pytest.CaptureFixture[str]) -> None:
    endpoint = free_endpoint()
    with DriverProcess.fake("tokenless", endpoint, robot="bare") as process:
        process.ready()
        status, verdicts = run_check(endpoint, "bare", capsys, timeout_s=2.0)
    assert {"liveliness", "state-published", "reset", "unknown-verb"} <= failed(verdicts)
    assert verdicts["noop"] == "PASS"
    assert status == 1


def test_procedures_come_from_the_knowledge_profile() -> None:
    chosen = Procedures.from_profile()
    assert chosen.sense == "V-Sweep-5°"  # the cheapest of the long-range sweeps
    assert chosen.near in {"S-Sweep-1°", "H-Scan-0.3", "D-Scan-0.3"}
    assert chosen.grasp == "Front-Pinch"


@pytest.mark.parametrize("argv", [
    ["driver", "check", "--timeout", "0"],
    ["driver", "check", "--robot", "r/1"],
    ["driver", "check", "--connect", "localhost"],
    ["driver", "sim", "--robot", "r*"],
    ["driver", "sim", "--listen", "nowhere"],
    ["driver", "sim", "--listen", "udpx/127.0.0.1:1"],
    ["driver", "sim", "--world", "no-such-world", "--listen", "udpx/127.0.0.1:1"],
])
def test_bad_arguments_exit_2_with_one_line(argv: list[str], capsys: pytest.CaptureFixture[str]) -> None:
    assert main(argv) == 2
    err = capsys.readouterr().err
    assert err.startswith("csl: error: ") and err.count("\n") == 1


def test_a_taken_port_exits_2(capsys: pytest.CaptureFixture[str]) -> None:
    endpoint = free_endpoint()
    with open_session(listen=[endpoint]):
        assert main(["driver", "sim", "--listen", endpoint]) == 2
    assert "Address already in use" in capsys.readouterr().err
