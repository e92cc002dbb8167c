"""``-v``/``--log-level`` on ``csl`` and on every command, through ``logging``; the
default stays quiet (warnings only); ``-v`` tells the executive's story, other
libraries' debug output waits for ``-vvv``."""

from __future__ import annotations

import argparse
import json
import logging
import re
import subprocess
import sys
import tomllib
from pathlib import Path

import pytest

import executive.sim_training
from behaviours.events import RECOVERIES
from csl_cli.main import OUR_PACKAGES, build_parser, log_level, main, others_level
from tests.executive.floors import sim_training

ROOT = Path(__file__).resolve().parents[2]
LINE = re.compile(r"^\S+ \S+ (DEBUG|INFO|WARNING|ERROR|CRITICAL) (\S+): (.*)$")  # date, time, level, logger


@pytest.mark.parametrize(
    ("options", "level"),
    [
        ([], logging.WARNING),
        (["-v"], logging.INFO),
        (["-vv"], logging.DEBUG),
        (["-v", "-v", "-v"], logging.DEBUG),  # there is nothing below debug
        (["--log-level", "error"], logging.ERROR),
        (["--log-level", "ERROR", "-vv"], logging.ERROR),  # the named level wins over -v
        (["--verbose"], logging.INFO),
    ],
)
def test_the_level_the_options_name(options: list[str], level: int) -> None:
    parser = build_parser()
    assert log_level(parser.parse_args([*options, "bt"])) == level  # before the command
    assert log_level(parser.parse_args(["bt", *options])) == level  # or after it
    assert log_level(parser.parse_args(["library", *options, "show"])) == level  # or after a group


def _commands(parser: argparse.ArgumentParser) -> list[argparse.ArgumentParser]:
    found = []
    for action in parser._actions:
        if isinstance(action, argparse._SubParsersAction):
            for child in action.choices.values():
                found += [child, *_commands(child)]
    return found


def test_every_command_takes_the_options() -> None:
    commands = _commands(build_parser())
    names = {p.prog for p in commands}
    assert {"csl demo", "csl run", "csl library show", "csl driver sim", "csl driver state",
            "csl learner serve"} <= names
    for command in commands:
        assert {"-v", "--verbose", "--log-level"} <= set(command._option_string_actions), command.prog


def test_quiet_by_default_and_info_with_v(capsys) -> None:  # noqa: ANN001
    probe = logging.getLogger("executive.test-probe")
    assert main(["bt"]) == 0
    probe.info("an info line")
    probe.warning("a warning line")
    err = capsys.readouterr().err
    assert "an info line" not in err and "WARNING executive.test-probe: a warning line" in err
    assert main(["bt", "-v"]) == 0
    probe.info("an info line")
    probe.debug("a debug line")
    err = capsys.readouterr().err
    assert "INFO executive.test-probe: an info line" in err and "a debug line" not in err
    assert main(["--log-level", "debug", "bt"]) == 0
    probe.debug("a debug line")
    assert capsys.readouterr().err.count("a debug line") == 1  # one handler, however often main runs
    main(["bt"])  # leave the process as quiet as it was


@pytest.mark.parametrize(
    ("options", "level"),
    [
        ([], logging.WARNING),
        (["-v"], logging.WARNING),
        (["-vv"], logging.WARNING),
        (["-vvv"], logging.DEBUG),
        (["--log-level", "info"], logging.INFO),  # one level for all
    ],
)
def test_the_level_other_libraries_get(options: list[str], level: int) -> None:
    assert others_level(build_parser().parse_args(["bt", *options])) == level


@pytest.mark.parametrize(("options", "shown"), [(["-vv"], False), (["-vvv"], True), (["--log-level", "debug"], True)])
def test_other_libraries_debug_lines_wait_for_vvv(options: list[str], shown: bool, capsys) -> None:  # noqa: ANN001
    assert main(["bt", *options]) == 0
    capsys.readouterr()
    logging.getLogger("matplotlib.test-probe").debug("a library's debug line")
    logging.getLogger("pydot").info("a library's info line")
    logging.getLogger("planner.test-probe").debug("our debug line")
    logging.getLogger("PIL.test-probe").warning("a library's warning")
    err = capsys.readouterr().err
    assert "our debug line" in err and "a library's warning" in err
    assert ("a library's debug line" in err) == shown and ("a library's info line" in err) == shown
    main(["bt"])  # leave the process as quiet as it was


def test_our_packages_are_those_pyproject_installs() -> None:
    found = tomllib.loads((ROOT / "pyproject.toml").read_text(encoding="utf-8"))["tool"]["setuptools"]["packages"]
    assert OUR_PACKAGES == {name.rstrip("*") for name in found["find"]["include"]}


@pytest.mark.slow
def test_v_tells_the_demo_and_nothing_of_other_libraries(tmp_path: Path, capsys,  # noqa: ANN001
                                                        monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.setattr(executive.sim_training, "train_in_simulator", lambda *args, **kwargs: sim_training())
    out = tmp_path / "out"
    assert main(["demo", "-v", "--no-plots", "--out", str(out)]) == 0
    err = capsys.readouterr().err.splitlines()
    main(["bt"])  # leave the process as quiet as it was
    logged = [m for m in map(LINE.match, err) if m]
    assert logged and {m[2].partition(".")[0] for m in logged} <= OUR_PACKAGES  # no pydot, matplotlib, PIL...
    assert "DEBUG" not in {m[1] for m in logged}
    told = [m[3] for m in logged if m[2] == "executive.narration"]
    verbs = [m[3] for m in logged if m[2] == "executive.verb_log"]
    events = [json.loads(line) for line in (out / "episode.jsonl").read_text(encoding="utf-8").splitlines()]
    chosen = next(e for e in events if e["event"] == "choose")  # the first test chosen, with its cost
    assert any(line.startswith(f"tick {chosen['tick']}, object {chosen['object']}: choose {chosen['test']} "
                               f"({chosen['how']}), cost {chosen['move_s'] + chosen['sense_s']:.1f} s (move ")
               for line in told)
    sensed = next(e for e in events if e["event"] == "sense")
    assert any(line.startswith(f"r1: sense (procedure {sensed['procedure']}) answered in ") for line in verbs)
    assert any(line.startswith("r1: move (waypoints ") for line in verbs)
    recoveries = [e for e in events if e["event"] in RECOVERIES]
    assert recoveries and len([line for line in told if ": recovery " in line]) == len(recoveries)
    assert [line.split(":")[0] for line in told if ": outcome " in line] == [f"object {i}" for i in range(7)]


@pytest.mark.slow
def test_vv_keeps_other_libraries_quiet_and_vvv_lets_them_speak(tmp_path: Path) -> None:
    """In a process of its own, so that pydot and matplotlib log as they are first
    imported (``csl bt --render`` imports both), as they did at ``-vv``."""
    def run(verbosity: str) -> set[str]:
        done = subprocess.run([sys.executable, "-m", "csl_cli", "bt", "--render", str(tmp_path / "bt.png"),
                               verbosity], capture_output=True, text=True, timeout=300, cwd=tmp_path)
        assert done.returncode == 0, done.stderr
        return {m[2].partition(".")[0] for m in map(LINE.match, done.stderr.splitlines()) if m}

    assert not run("-vv") - OUR_PACKAGES
    assert {"pydot", "matplotlib"} <= run("-vvv")


def test_a_bad_level_is_one_line(capsys) -> None:  # noqa: ANN001
    assert main(["bt", "--log-level", "loud"]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and "--log-level: invalid choice: 'loud'" in err[0]
