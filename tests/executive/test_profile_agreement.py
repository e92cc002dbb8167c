"""One robot profile, agreed on both ends, with real ``csl`` processes on
127.0.0.1: ``csl driver sim --profile rover.toml`` serves the Rover and says so in its
``hello``; ``csl run --driver zenoh`` planning for the HERO 2000 is refused in one line
naming both profiles (exit 2: the user's inputs disagree), and planning for the Rover
it runs, at the Rover's procedure times. A driver that does not name its profile is
driven, with one line on stderr saying so."""

from __future__ import annotations

import json
import os
import select
import subprocess
import sys
from collections.abc import Iterator
from pathlib import Path

import pytest

from csl_cli.main import main
from hero_driver.sim_driver import SimulatedHero
from hero_driver.zenoh_link.node import DriverNode
from robot_profile import DEFAULT_PROFILE, load_profile, profile_stamp
from tests.zenoh_rpc.support import free_endpoint
from zenoh_rpc.config import open_session
from zenoh_rpc.options import CONFIG_ENV

pytestmark = pytest.mark.zenoh

REPO = Path(__file__).resolve().parents[2]
ROVER = DEFAULT_PROFILE.parent / "rover.toml"
START_TIMEOUT_S = 30.0  # a cold interpreter importing numpy, pymunk and zenoh on a busy box
RUN_TIMEOUT_S = 120.0


def _env() -> dict[str, str]:
    env = {k: v for k, v in os.environ.items() if k != CONFIG_ENV}
    env["PYTHONPATH"] = os.pathsep.join(filter(None, [str(REPO), os.environ.get("PYTHONPATH")]))
    return env


def _csl(*argv: str) -> subprocess.CompletedProcess[str]:
    return subprocess.run([sys.executable, "-m", "csl_cli", *argv], cwd=REPO, env=_env(),
                          capture_output=True, text=True, timeout=RUN_TIMEOUT_S)


@pytest.fixture
def rover_driver() -> Iterator[str]:
    """``csl driver sim --profile rover.toml`` as a child process; its endpoint."""
    endpoint = free_endpoint()
    process = subprocess.Popen([sys.executable, "-m", "csl_cli", "driver", "sim", "--profile", str(ROVER),
                                "--listen", endpoint], cwd=REPO, env=_env(), stdout=subprocess.PIPE,
                               stderr=subprocess.PIPE, text=True)
    try:
        assert process.stdout is not None and process.stderr is not None
        readable, _, _ = select.select([process.stdout], [], [], START_TIMEOUT_S)
        line = process.stdout.readline() if readable else ""
        if not line.startswith(f"serving hero/r1/rpc/* on {endpoint}"):
            pytest.fail(f"csl driver sim did not start: {line}{process.stderr.read()}")
        yield endpoint
    finally:
        process.kill()
        process.wait(10)
        for stream in (process.stdout, process.stderr):
            if stream:
                stream.close()


def _run(endpoint: str, out: Path, *extra: str) -> subprocess.CompletedProcess[str]:
    return _csl("run", "--driver", "zenoh", "--connect", endpoint, "--out", str(out), "--no-plots", *extra)


def test_a_run_planning_for_another_robot_is_refused_in_one_line(rover_driver: str, tmp_path: Path) -> None:
    hero, rover = profile_stamp(load_profile()), profile_stamp(load_profile(ROVER))
    refused = _run(rover_driver, tmp_path / "hero", "--library", str(tmp_path / "hero.sqlite"))
    assert refused.returncode == 2
    assert refused.stderr.splitlines() == [
        f"csl: error: --knowledge {DEFAULT_PROFILE} is robot profile hero2000 (sha256 {hero.sha256[:12]}) "
        f"but driver r1 serves rover (sha256 {rover.sha256[:12]}): run with the driver's profile or start "
        f"the driver with --profile {DEFAULT_PROFILE}"]
    assert not (tmp_path / "hero" / "episode.jsonl").exists()  # refused before the robot moved


@pytest.mark.slow
def test_a_run_planning_for_the_rover_drives_the_rover(rover_driver: str, tmp_path: Path) -> None:
    library = tmp_path / "rover.sqlite"
    trained = _csl("train", "--sim", "--knowledge", str(ROVER), "--out", str(library))
    assert trained.returncode == 0, trained.stderr
    ran = _run(rover_driver, tmp_path / "rover", "--knowledge", str(ROVER), "--library", str(library))
    assert ran.returncode in (0, 1), ran.stderr  # an episode ran to its end
    assert "does not say which robot profile" not in ran.stderr
    times = {p.name: p.time_s for p in load_profile(ROVER).sensing}
    events = [json.loads(line) for line in (tmp_path / "rover" / "episode.jsonl").read_text().splitlines()]
    sensed = [(e["procedure"], e["seconds"]) for e in events if e["event"] == "sense"]
    # The driver process sensed at the Rover's times (30 s, not the HERO's 45 s).
    assert sensed and all(times[name] == seconds for name, seconds in sensed)
    assert events[-1]["event"] == "episode_end"


@pytest.mark.slow
def test_a_driver_that_does_not_name_its_profile_is_driven_with_one_line(
        tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    endpoint = free_endpoint()
    hero = SimulatedHero("old", world="lab")
    with open_session(listen=[endpoint]) as session, DriverNode(hero, session):  # no profile: an older node
        status = main(["run", "--driver", "zenoh", "--robot", "old", "--connect", endpoint, "--out",
                       str(tmp_path / "out"), "--no-plots", "--library", str(tmp_path / "lib.sqlite")])
    assert status in (0, 1)
    assert capsys.readouterr().err.splitlines()[0] == (
        "csl: driver old does not say which robot profile it serves (a driver from before the 'profile' "
        "feature); assuming hero2000, as --knowledge says")
