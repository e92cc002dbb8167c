"""zenoh's own user/password authentication, turned on with ``--zenoh-config`` /
``CSL_ZENOH_CONFIG``, with real ``csl`` processes on 127.0.0.1: a driver node (and a
learner service) started with a password dictionary serves only a session that
presents matching credentials (docs/security.md)."""

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
from learner.service.interface import LearnerUnavailable
from tests.zenoh_rpc.support import free_endpoint
from zenoh_rpc.config import UserConfig
from zenoh_rpc.options import CONFIG_ENV

REPO = Path(__file__).resolve().parents[2]
START_TIMEOUT_S = 30.0  # a cold interpreter importing numpy, pymunk and zenoh on a busy box
RUN_TIMEOUT_S = 120.0


@pytest.fixture
def configs(tmp_path: Path) -> dict[str, Path]:
    """The node's file (its own credentials and the dictionary it checks), a client's
    with the matching password, and one with a wrong password."""
    users = tmp_path / "users.txt"
    users.write_text("executive:correct-horse\n")
    files = {
        "node": {"user": "executive", "password": "correct-horse", "dictionary_file": str(users)},
        "right": {"user": "executive", "password": "correct-horse"},
        "wrong": {"user": "executive", "password": "battery-staple"},
    }
    paths = {}
    for name, usrpwd in files.items():
        paths[name] = tmp_path / f"{name}.json5"
        paths[name].write_text(json.dumps({"transport": {"auth": {"usrpwd": usrpwd}}}))
    return paths


def _env(config: Path | None) -> dict[str, str]:
    env = {k: v for k, v in os.environ.items() if k != CONFIG_ENV}
    env["PYTHONPATH"] = os.pathsep.join(filter(None, [str(REPO), os.environ.get("PYTHONPATH")]))
    if config is not None:
        env[CONFIG_ENV] = str(config)
    return env


class Node:
    """A ``csl`` serving command as a child process; :meth:`close` always ends it."""

    def __init__(self, argv: list[str], config: Path) -> None:
        self.process = subprocess.Popen([sys.executable, "-m", "csl_cli", *argv, "--zenoh-config", str(config)],
                                        cwd=REPO, env=_env(None), stdout=subprocess.PIPE, stderr=subprocess.PIPE,
                                        text=True)
        assert self.process.stdout is not None
        readable, _, _ = select.select([self.process.stdout], [], [], START_TIMEOUT_S)
        self.line = self.process.stdout.readline() if readable else ""
        if not self.line.startswith("serving"):
            self.close()
            pytest.fail(f"{argv[0]} did not start: {self.line}{self.process.stderr.read()}")  # type: ignore[union-attr]

    def close(self) -> None:
        if self.process.poll() is None:
            self.process.kill()
        self.process.wait(10)
        for stream in (self.process.stdout, self.process.stderr):
            if stream:
                stream.close()


@pytest.fixture
def driver(configs: dict[str, Path]) -> Iterator[str]:
    """``csl driver sim`` (the lab, seed 0) requiring a password; its endpoint."""
    endpoint = free_endpoint()
    node = Node(["driver", "sim", "--listen", endpoint], configs["node"])
    try:
        assert node.line.startswith(f"serving hero/r1/rpc/* on {endpoint}")
        yield endpoint
    finally:
        node.close()


def _run(endpoint: str, out: Path, config: Path | None) -> subprocess.CompletedProcess[str]:
    argv = [sys.executable, "-m", "csl_cli", "run", "--driver", "zenoh", "--connect", endpoint,
            "--out", str(out), "--no-plots", "--library", str(out / "lib.sqlite")]
    return subprocess.run(argv, cwd=REPO, env=_env(config), capture_output=True, text=True, timeout=RUN_TIMEOUT_S)


@pytest.mark.slow
@pytest.mark.zenoh
def test_only_the_matching_password_drives_the_robot(driver: str, configs: dict[str, Path],
                                                     tmp_path: Path) -> None:
    refused = _run(driver, tmp_path / "stranger", None)
    assert refused.returncode == 3
    assert refused.stderr.strip().splitlines() == [
        f"csl: robot error: unavailable: no driver is serving robot 'r1' at {driver} (or it requires "
        "credentials: --zenoh-config, docs/security.md); start one with 'csl driver sim --robot r1'"]
    assert not (tmp_path / "stranger" / "episode.jsonl").exists()  # nothing ran: the robot never moved

    admitted = _run(driver, tmp_path / "executive", configs["right"])  # through CSL_ZENOH_CONFIG
    assert admitted.returncode in (0, 1), admitted.stderr  # an episode ran to its end: not lost, not refused
    assert "exit status " in admitted.stdout
    events = [json.loads(line) for line in (tmp_path / "executive" / "episode.jsonl").read_text().splitlines()]
    assert events[-1]["event"] == "episode_end"


@pytest.mark.slow
@pytest.mark.zenoh
def test_the_conformance_suite_reaches_a_driver_only_with_the_password(driver: str, configs: dict[str, Path]) -> None:
    argv = [sys.executable, "-m", "csl_cli", "driver", "check", "--connect", driver, "--timeout", "5"]
    refused = subprocess.run(argv, cwd=REPO, env=_env(None), capture_output=True, text=True, timeout=RUN_TIMEOUT_S)
    assert refused.returncode == 1 and "nothing serves robot r1" in refused.stdout
    admitted = subprocess.run(argv, cwd=REPO, env=_env(configs["right"]), capture_output=True, text=True,
                              timeout=RUN_TIMEOUT_S)
    assert admitted.returncode == 0, admitted.stdout + admitted.stderr


@pytest.mark.slow
@pytest.mark.zenoh
def test_the_learner_service_admits_only_the_matching_password(configs: dict[str, Path], tmp_path: Path) -> None:
    from learner.service.zenoh_client import ZenohLearner

    endpoint = free_endpoint()
    node = Node(["learner", "serve", "--name", "auth", "--db", str(tmp_path / "lib.sqlite"), "--listen", endpoint],
                configs["node"])
    try:
        for stranger in (None, UserConfig(configs["wrong"])):
            with pytest.raises(LearnerUnavailable, match=f"^learner 'auth': cannot reach a service: .*{endpoint}"):
                ZenohLearner("auth", connect=[endpoint], timeout_s=1.0, zenoh_config=stranger)
        learner = ZenohLearner("auth", connect=[endpoint], timeout_s=5.0, zenoh_config=UserConfig(configs["right"]))
        try:
            assert learner.library().descriptions  # the seeded example library, read through the password
        finally:
            learner.close()
    finally:
        node.close()


@pytest.mark.parametrize("argv", [
    ["run", "--driver", "zenoh"],
    ["run", "--learner", "zenoh"],
    ["driver", "sim"],
    ["learner", "serve"],
])
def test_a_bad_config_file_is_one_line_naming_it_and_exit_2(tmp_path: Path, capsys: pytest.CaptureFixture[str],
                                                             argv: list[str]) -> None:
    bad = tmp_path / "zenoh.json5"
    bad.write_text('{ transport: { auth: { usrpwd: { user: "x", pasword: "y" } } } }')
    out = ["--out", str(tmp_path / "out")] if argv[0] == "run" else ["--db", str(tmp_path / "l.sqlite")] \
        if argv[0] == "learner" else []
    assert main([*argv, *out, "--zenoh-config", str(bad)]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert err == [f"csl: error: --zenoh-config {bad}: line 1, column 45: unknown field `pasword`, "
                   "expected one of `user`, `password`, `dictionary_file`"]


def test_a_bad_file_named_by_the_environment_says_so(tmp_path: Path, capsys: pytest.CaptureFixture[str],
                                                     monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.setenv(CONFIG_ENV, str(tmp_path / "missing.json5"))
    assert main(["run", "--driver", "zenoh", "--out", str(tmp_path / "out")]) == 2
    assert capsys.readouterr().err.strip() == (f"csl: error: {CONFIG_ENV} {tmp_path}/missing.json5: "
                                               "No such file or directory (os error 2)")


def test_a_config_file_without_zenoh_in_the_run_is_a_mistake(tmp_path: Path, capsys: pytest.CaptureFixture[str],
                                                             configs: dict[str, Path]) -> None:
    assert main(["run", "--zenoh-config", str(configs["right"]), "--out", str(tmp_path / "out")]) == 2
    assert capsys.readouterr().err.strip().startswith(
        "csl: error: --zenoh-config goes with --driver or --learner zenoh")


def test_an_endpoint_flag_the_file_overrides_is_refused(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    routed = tmp_path / "routed.json5"
    routed.write_text(json.dumps({"connect": {"endpoints": ["tcp/127.0.0.1:7400"]}}))
    argv = ["run", "--driver", "zenoh", "--connect", "tcp/127.0.0.1:7447", "--zenoh-config", str(routed),
            "--out", str(tmp_path / "out")]
    assert main(argv) == 2
    assert capsys.readouterr().err.strip() == (
        f"csl: error: --connect tcp/127.0.0.1:7447: --zenoh-config {routed} sets connect/endpoints, which wins "
        "over --connect; give the endpoint in one place only")
