"""Shell completion through argcomplete: commands, options, the shipped worlds on
``--world`` and the shipped robot profiles on ``--knowledge``/``--profile``; asked the way
the shell hook asks (``_ARGCOMPLETE``, ``COMP_LINE``, ``COMP_POINT``)."""

from __future__ import annotations

import io
import os
import subprocess
import sys
from pathlib import Path

import argcomplete
import pytest
from argcomplete import io as argcomplete_io

from executive import defaults
from csl_cli.main import build_parser
from hero_driver.zenoh_link.verbs import NAMES

REPO = Path(__file__).resolve().parents[2]


class _Done(Exception):
    """argcomplete's exit, caught instead of leaving the test process."""


class _Finder(argcomplete.CompletionFinder):
    """argcomplete's finder, its debug output kept off file descriptor 9 (which it
    would open and close under pytest, whose fault handler owns it)."""

    def _init_debug_stream(self) -> None:
        argcomplete_io.debug_stream = io.StringIO()


def _complete(line: str, monkeypatch: pytest.MonkeyPatch, cwd: Path) -> list[str]:
    """What argcomplete offers for ``line`` with the cursor at its end."""
    monkeypatch.chdir(cwd)
    for name, value in {"_ARGCOMPLETE": "1", "COMP_LINE": line, "COMP_POINT": str(len(line)),
                        "_ARGCOMPLETE_IFS": "\n", "_ARGCOMPLETE_SUPPRESS_SPACE": "1"}.items():
        monkeypatch.setenv(name, value)
    monkeypatch.delenv("_ARGCOMPLETE_STDOUT_FILENAME", raising=False)
    out = io.StringIO()

    def done(code: int = 0) -> None:
        raise _Done(code)

    with pytest.raises(_Done):
        _Finder()(build_parser(), exit_method=done, output_stream=out)
    return [c.strip() for c in out.getvalue().split("\n") if c]


def test_commands_and_actions(monkeypatch: pytest.MonkeyPatch, tmp_path: Path) -> None:
    assert _complete("csl de", monkeypatch, tmp_path) == ["demo"]
    assert set(_complete("csl ", monkeypatch, tmp_path)) >= {"demo", "run", "bt", "library", "driver", "learner"}
    actions = [c for c in _complete("csl driver ", monkeypatch, tmp_path) if not c.startswith("-")]
    assert actions == ["sim", "check", "state", "call"]
    assert _complete("csl library sh", monkeypatch, tmp_path) == ["show"]
    assert "--log-level" in _complete("csl demo --lo", monkeypatch, tmp_path)
    verbs = [c for c in _complete("csl driver call r1 ", monkeypatch, tmp_path) if not c.startswith("-")]
    assert verbs == list(NAMES)  # the verb table's, in its order
    assert _complete("csl driver call r1 re", monkeypatch, tmp_path) == ["release", "reset"]


def test_worlds_then_world_files(monkeypatch: pytest.MonkeyPatch, tmp_path: Path) -> None:
    (tmp_path / "mars.json").write_text("{}")
    (tmp_path / "notes.txt").write_text("")
    (tmp_path / "worlds").mkdir()
    offered = _complete("csl demo --world ", monkeypatch, tmp_path)
    assert offered[:8] == ["apartment", "apartment-2", "clutter", "crossing", "lab", "reference", "training", "two-rooms"] and sorted(offered[8:]) == ["mars.json", "worlds/"]  # not notes.txt
    assert _complete("csl run --world t", monkeypatch, tmp_path) == ["training", "two-rooms"]
    assert _complete("csl driver sim --world la", monkeypatch, tmp_path) == ["lab"]


def test_robot_profiles(monkeypatch: pytest.MonkeyPatch, tmp_path: Path) -> None:
    folder = f"{defaults.PROFILES}/"
    shipped = [f"{folder}hero2000.toml", f"{folder}rover.toml"]
    assert [c for c in _complete(f"csl run --knowledge {folder}", monkeypatch, tmp_path) if c.endswith(".toml")] \
        == shipped
    assert _complete(f"csl driver sim --profile {folder}r", monkeypatch, tmp_path) == [f"{folder}rover.toml"]
    (tmp_path / "arm.toml").write_text("")
    assert _complete("csl demo --knowledge ", monkeypatch, tmp_path)[-1] == "arm.toml"


def test_robot_names_and_library_ids(monkeypatch: pytest.MonkeyPatch, tmp_path: Path) -> None:
    import csl_cli.completion
    from learner.library.format import read_library_json
    from learner.library.store import LibraryStore

    asked = []
    monkeypatch.setattr(csl_cli.completion, "live_robots", lambda endpoint, timeout_s: asked.append(endpoint) or [])
    assert _complete("csl run --driver zenoh --robot ", monkeypatch, tmp_path) == ["r1"]  # none alive: the default
    assert [c for c in _complete("csl driver call ", monkeypatch, tmp_path) if not c.startswith("-")] == ["r1"]
    assert asked == ["tcp/127.0.0.1:7447", "tcp/127.0.0.1:7447"]  # the default driver endpoint
    monkeypatch.setattr(csl_cli.completion, "live_robots", lambda endpoint, timeout_s: ["r2", "r3"])
    assert _complete("csl driver state r", monkeypatch, tmp_path) == ["r2", "r3"]
    example = read_library_json(defaults.EXAMPLE_LIBRARY)
    with LibraryStore(tmp_path / "lib.sqlite") as store:
        store.add(example[:2])
    offered = _complete("csl library show --db lib.sqlite ", monkeypatch, tmp_path)
    assert [c for c in offered if not c.startswith("-")] == [d.object_id for d in example[:2]]


def test_the_installed_command_completes(tmp_path: Path) -> None:
    """The real entry point: main hands the shell's request to argcomplete, which
    answers and exits before any command runs; and argcomplete's global completion
    finds the PYTHON_ARGCOMPLETE_OK mark in the module the ``csl`` script imports."""
    out = tmp_path / "completions"
    env = {**os.environ, "_ARGCOMPLETE": "1", "COMP_LINE": "csl dr", "COMP_POINT": "6", "_ARGCOMPLETE_IFS": "\n",
           "_ARGCOMPLETE_STDOUT_FILENAME": str(out), "PYTHONPATH": str(REPO)}
    done = subprocess.run([sys.executable, "-m", "csl_cli"], cwd=tmp_path, env=env, capture_output=True,
                          text=True, timeout=60)
    assert done.returncode == 0 and done.stdout == "" and out.read_text().strip() == "driver"
    script = Path(sys.executable).with_name("csl")
    assert script.is_file(), "the project is installed in this environment (pip install -e .)"
    check = subprocess.run([sys.executable, "-W", "ignore", "-m", "argcomplete._check_console_script", str(script)],
                           capture_output=True, text=True, timeout=60)
    assert check.returncode == 0, check.stderr
