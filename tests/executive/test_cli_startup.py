"""``csl --help`` and the argument parsing of every command stay light: the planner
stack, the simulator, the transport and matplotlib are imported only by the command
that runs them (a user's shell completion or ``--help`` should not pay ~1 s for them);
``csl --help`` imports no command's module at all, so not numpy either."""

from __future__ import annotations

import argparse
import json
import subprocess
import sys
from pathlib import Path

import pytest

from csl_cli.commands import COMMANDS
from csl_cli.main import ALL, build_parser, named_command

REPO = Path(__file__).resolve().parents[2]
HEAVY = ("matplotlib", "ompl", "pymunk", "cv2", "zenoh", "py_trees", "scipy")


def test_building_the_parser_imports_no_heavy_stack() -> None:
    code = ("import json, sys\nfrom csl_cli.main import build_parser\nbuild_parser()\n"
            f"print(json.dumps(sorted(m for m in {HEAVY!r} if m in sys.modules)))")
    out = subprocess.run([sys.executable, "-c", code], cwd=REPO, capture_output=True, text=True, check=True)
    assert json.loads(out.stdout) == []


def _imported_by(argv: list[str], prefixes: tuple[str, ...]) -> list[str]:
    """The modules under ``prefixes`` that ``csl ARGV`` has imported when it exits,
    in a fresh interpreter."""
    code = ("import contextlib, io, json, sys\nfrom csl_cli.main import main\n"
            f"with contextlib.redirect_stdout(io.StringIO()):\n    main({argv!r})\n"
            f"print(json.dumps(sorted(m for m in sys.modules if m.split('.')[0] in {prefixes!r})))")
    out = subprocess.run([sys.executable, "-c", code], cwd=REPO, capture_output=True, text=True, check=True)
    return json.loads(out.stdout)


def test_csl_help_imports_no_command_and_no_numpy() -> None:
    assert _imported_by(["--help"], ("numpy", "csl_cli", "rich")) == ["csl_cli", "csl_cli.commands", "csl_cli.interrupt",
                                                                      "csl_cli.main"]


@pytest.mark.parametrize("argv", [["run", "--help"], ["demo", "--help"], ["bt", "--help"], ["tree", "--help"],
                                  ["train", "--help"], ["learner", "serve", "--help"],
                                  ["experiment", "paper", "--help"], ["log", "--help"], ["driver", "--help"],
                                  ["driver", "sim", "--help"], ["camera", "--help"], ["library", "--help"],
                                  ["library", "show", "--help"], ["library", "history", "--help"]])
def test_a_commands_help_imports_no_numpy(argv: list[str]) -> None:
    """Each of these commands keeps its stack in its handlers. ``csl driver call
    --help`` is the exception by design: it lists the verbs from the verb table."""
    assert _imported_by(argv, ("numpy",)) == []


def test_printing_the_behaviour_tree_imports_no_drawing_no_simulator_and_no_transport() -> None:
    """``csl bt`` builds the tree and prints it: matplotlib only for ``--render``."""
    imported = _imported_by(["bt"], ("matplotlib", "pymunk", "zenoh", "csl_cli"))
    assert "csl_cli.commands.bt" in imported and "csl_cli.commands.episode" not in imported
    assert [m for m in imported if not m.startswith("csl_cli")] == []


def test_the_table_lists_every_command_its_module_registers_with_the_same_help() -> None:
    """``csl --help`` reads the table; the modules register the commands: in the same
    order, with the same help line."""
    parser = build_parser(ALL)
    (commands,) = [a for a in parser._actions if isinstance(a, argparse._SubParsersAction)]  # noqa: SLF001
    registered = [(choice.dest, choice.help) for choice in commands._choices_actions]  # noqa: SLF001
    assert registered == [(c.name, c.help) for c in COMMANDS]
    for command in COMMANDS:  # each command's own parser comes from its module
        own = build_parser(command.name)
        (sub,) = [a for a in own._actions if isinstance(a, argparse._SubParsersAction)]  # noqa: SLF001
        assert sub.choices[command.name].format_help() == commands.choices[command.name].format_help()


@pytest.mark.parametrize(("argv", "named"), [
    (["--help"], None), (["-vv", "run", "--help"], "run"), (["--log-level", "debug", "log", "run"], "log"),
    (["experiment", "paper", "--out", "run"], "experiment"), (["frobnicate"], None)])
def test_the_command_is_the_first_word_that_names_one(argv: list[str], named: str | None) -> None:
    assert named_command(argv) == named
