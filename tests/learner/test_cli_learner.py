"""``csl tree``, ``csl train`` and ``csl library`` as a user runs them."""

from __future__ import annotations

import json
import subprocess
import sys

import pytest

from csl_cli.main import main
from learner.library.format import write_library_json
from tests.learner.fixtures import four_objects


@pytest.fixture
def lib(tmp_path):  # noqa: ANN001, ANN201
    path = tmp_path / "lib.json"
    write_library_json(path, four_objects())
    return path


def test_tree_prints_the_papers_style(lib, capsys) -> None:  # noqa: ANN001
    assert main(["tree", "--library", str(lib), "--pose", "60,0"]) == 0
    out = capsys.readouterr().out.splitlines()
    assert out[:2] == ["move-to-(24,0) (72s)", "Width-Degree-1°(24,0) (100s)"]


def test_tree_text_rounds_a_bearing_the_json_keeps_it(capsys) -> None:  # noqa: ANN001
    """Standing at a bearing no grid holds, id3 (whose * slots need not be where the
    robot is) sends the robot to it: the text says 339.2, the JSON the exact bearing."""
    bearing = "339.16071978233924"
    assert main(["tree", "--criterion", "id3", "--pose", f"60,{bearing}"]) == 0
    text = capsys.readouterr().out
    assert "    move-to-(6,339.2) (5s)\n" in text and bearing not in text
    assert main(["tree", "--criterion", "id3", "--pose", f"60,{bearing}", "--json"]) == 0
    assert f"[6, {bearing}]" in json.dumps(json.loads(capsys.readouterr().out))


def test_tree_json_and_criterion(lib, capsys) -> None:  # noqa: ANN001
    assert main(["tree", "--library", str(lib), "--pose", "60,0", "--json", "--criterion", "id3"]) == 0
    tree = json.loads(capsys.readouterr().out)
    assert tree["kind"] == "test" and tree["feature"] == "Width-Degree-1°"  # 1.5 bits: the most informative


@pytest.mark.parametrize(
    ("argv", "message"),
    [
        (["tree", "--pose", "sixty,0"], "--pose distance: expected a number"),
        (["tree", "--pose", "60"], "--pose: expected DISTANCE,ORIENTATION"),
        (["tree", "--library", "/nonexistent/lib.json"], "library file not found"),
        (["tree", "--knowledge", "/nonexistent/k.toml"], "knowledge file not found"),
    ],
)
def test_bad_arguments_are_one_line_and_exit_2(lib, capsys, argv, message) -> None:  # noqa: ANN001
    if "--library" not in argv:
        argv = [*argv, "--library", str(lib)]
    assert main(argv) == 2
    err = capsys.readouterr().err
    assert err.startswith("csl: error: ") and message in err and err.count("\n") == 1


def test_library_commands_and_a_failed_import_keeps_the_library(tmp_path, lib, capsys) -> None:  # noqa: ANN001
    db = tmp_path / "store.sqlite"
    assert main(["library", "--db", str(db), "import", str(lib)]) == 0
    assert main(["library", "--db", str(db), "import", str(lib)]) == 2  # ids clash: nothing written
    assert "already in the library" in capsys.readouterr().err
    bad = tmp_path / "bad.json"
    bad.write_text('{"format": "csl-library", "version": 1, "descriptions": [{"id": 3}]}')
    assert main(["library", "--db", str(db), "import", str(bad)]) == 2
    assert main(["library", "--db", str(db), "stats"]) == 0
    assert "4 descriptions" in capsys.readouterr().out
    out = tmp_path / "out.json"
    assert main(["library", "--db", str(db), "export", str(out)]) == 0
    assert json.loads(out.read_text())["descriptions"][0]["id"] == "cup"
    assert main(["library", "--db", str(db), "show", "cup"]) == 0
    assert "Front-Wrap(6,*)" in capsys.readouterr().out


def test_the_console_script_never_shows_a_traceback(tmp_path) -> None:  # noqa: ANN001
    bad = tmp_path / "k.toml"
    bad.write_text("[move]\nseconds_per_inch = -2\n")
    proc = subprocess.run([sys.executable, "-m", "csl_cli", "tree", "--knowledge", str(bad)],
                          capture_output=True, text=True)
    assert proc.returncode == 2
    assert "Traceback" not in proc.stderr and "'seconds_per_inch' must not be negative" in proc.stderr
