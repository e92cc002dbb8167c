"""Paths the user names are taken as named: a missing folder for ``--db``/``--library``
is a one-line error, never created behind their back; a new library is announced; a
server checks its database before it binds a port; errors say how to fix them."""

from __future__ import annotations

import os
import select
import signal
import socket
import subprocess
import sys
from pathlib import Path

import pytest

from executive import defaults
from csl_cli.main import main
from tests.zenoh_rpc.support import free_endpoint


def _one_error_line(capsys) -> str:  # noqa: ANN001
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1, err
    return err[0]


@pytest.mark.parametrize(
    "argv",
    [
        ["run", "--no-plots", "--library", "{missing}/lib.sqlite", "--out", "{tmp}/out"],
        ["library", "--db", "{missing}/lib.sqlite", "import", str(defaults.EXAMPLE_LIBRARY)],
        ["learner", "serve", "--db", "{missing}/lib.sqlite", "--listen", "tcp/127.0.0.1:9"],
    ],
)
def test_a_missing_folder_is_an_error_not_created(argv: list[str], tmp_path: Path, capsys) -> None:  # noqa: ANN001
    missing = tmp_path / "no" / "such"
    argv = [a.format(missing=missing, tmp=tmp_path) for a in argv]
    assert main(argv) == 2
    option = "--library" if "--library" in argv else "--db"
    assert _one_error_line(capsys) == (f"csl: error: {option}: folder {missing} does not exist "
                                       "(create it first, or choose another path)")
    assert not (tmp_path / "no").exists()


@pytest.mark.slow
def test_a_new_library_is_announced_once(tmp_path: Path, capsys) -> None:  # noqa: ANN001
    db = tmp_path / "lib.sqlite"
    assert main(["library", "--db", str(db), "import", str(defaults.EXAMPLE_LIBRARY)]) == 0
    assert capsys.readouterr().out == f"imported 14 descriptions into {db} (a new library)\n"
    assert main(["library", "--db", str(db), "import", "--replace", str(defaults.EXAMPLE_LIBRARY)]) == 0
    assert capsys.readouterr().out == f"imported 14 descriptions into {db}\n"  # it exists now
    # a command says so in its report, never on stderr: a run that fails still says one line
    run = tmp_path / "run.sqlite"
    argv = ["run", "--max-steps", "1", "--no-plots", "--out", str(tmp_path / "out"), "--library", str(run)]
    assert main(argv) == 1  # one step per object is too few: every object fails, quickly
    assert f"\nlibrary: {run} (new, seeded with hero2000-library.json)\n" in capsys.readouterr().out
    assert main(argv) == 1
    assert f"\nlibrary: {run}\n" in capsys.readouterr().out


def test_learner_serve_checks_its_database_before_the_port(tmp_path: Path, capsys) -> None:  # noqa: ANN001
    not_a_database = tmp_path / "notes.sqlite"
    not_a_database.write_text("shopping list\n")
    with socket.socket() as taken:  # the port is busy too: the database is what gets reported
        taken.bind(("127.0.0.1", 0))
        taken.listen()
        port = taken.getsockname()[1]
        assert main(["learner", "serve", "--db", str(not_a_database), "--listen", f"tcp/127.0.0.1:{port}"]) == 2
    line = _one_error_line(capsys)
    assert line.startswith(f"csl: error: {not_a_database}: not a csl library database")
    assert not_a_database.read_text() == "shopping list\n"


def test_an_unknown_world_lists_the_shipped_ones(tmp_path: Path, capsys) -> None:  # noqa: ANN001
    for argv in (["demo", "--world", "moon"], ["run", "--world", "moon"], ["driver", "sim", "--world", "moon"]):
        assert main([*argv, *(["--out", str(tmp_path)] if argv[0] != "driver" else [])]) == 2
        line = _one_error_line(capsys)
        assert "argument --world: 'moon' is neither a world file nor a shipped world (shipped: apartment, apartment-2, clutter, crossing, lab, reference, training, two-rooms)" in line
    world = tmp_path / "moon.json"
    world.write_text("{}")  # a file is taken as a file, and read (and refused) by the simulator
    assert main(["demo", "--world", str(world), "--out", str(tmp_path)]) == 2
    assert "shipped" not in _one_error_line(capsys)


@pytest.mark.slow
@pytest.mark.zenoh
def test_an_unreachable_learner_suggests_serving_one(tmp_path: Path, capsys) -> None:  # noqa: ANN001
    argv = ["run", "--learner", "zenoh", "--learner-connect", "tcp/127.0.0.1:9", "--out", str(tmp_path)]
    assert main(argv) == 3
    line = _one_error_line(capsys)
    assert line.startswith("csl: learner error: ") and line.endswith("start it with 'csl learner serve')")


@pytest.mark.zenoh
def test_learner_serve_says_when_its_library_is_new(tmp_path: Path) -> None:
    repo = Path(__file__).resolve().parents[2]
    db = tmp_path / "shared.sqlite"
    env = {**os.environ, "PYTHONPATH": str(repo)}
    for new in (True, False):
        serve = subprocess.Popen([sys.executable, "-m", "csl_cli", "learner", "serve", "--db", str(db),
                                  "--listen", free_endpoint()], cwd=repo, env=env, stdout=subprocess.PIPE,
                                 stderr=subprocess.PIPE, text=True)
        try:
            assert serve.stdout is not None
            readable, _, _ = select.select([serve.stdout], [], [], 30.0)
            ready = serve.stdout.readline() if readable else ""
        finally:
            serve.send_signal(signal.SIGINT)
            serve.communicate(timeout=30)
        assert f"14 descriptions, version 1, from {db}" in ready
        assert (f"(a new library, seeded from {defaults.EXAMPLE_LIBRARY})" in ready) is new
