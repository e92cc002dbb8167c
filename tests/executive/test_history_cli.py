"""``csl run`` appends its row to the history; ``csl library history`` lists the runs,
draws the learning curve, and says in one line (exit 2) what is wrong with a file."""

from __future__ import annotations

import dataclasses
import json
from pathlib import Path

import matplotlib.image
import numpy as np
import pytest

from csl_cli.main import main
from executive.episode_log import read_log
from reporting.history import Run, append_run, default_history, read_history, wrong_grasps
from learner.library.store import LibraryStore


def _run(**changes: object) -> Run:
    base = Run(date="2026-01-02T03:04:05+00:00", command="run", robot="r1", world="lab", seed=3,
               criterion="cs-id3", objects=4, handled=3, failed=1, errors=2, robot_min_per_object=10.0,
               library_size=20, library="/somewhere/library.sqlite")
    return dataclasses.replace(base, **changes)  # type: ignore[arg-type]


def test_a_run_appends_its_row(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    library = tmp_path / "lib.sqlite"
    # one recognition step reaches a grasp only where the camera's appearance leaves one:
    # two of the seven are handled, five fail (test_cli_json)
    assert main(["run", "--json", "--max-steps", "1", "--no-plots", "--out", str(tmp_path / "out"),
                 "--library", str(library)]) == 1
    doc = json.loads(capsys.readouterr().out)
    (row,) = read_history(default_history())
    with LibraryStore(library) as store:
        size = len(store.descriptions())
    assert dataclasses.replace(row, date="", robot_min_per_object=None) == Run(
        date="", command="run", robot="r1", world="lab", seed=0, criterion="cs-id3-failure", objects=7, handled=2,
        failed=5, errors=wrong_grasps(read_log(tmp_path / "out" / "episode.jsonl")), robot_min_per_object=None,
        library_size=size, library=str(library.resolve()))
    assert row.robot_min_per_object == pytest.approx(sum(o["robot_s"] for o in doc["objects"]) / 60 / 7)

    assert main(["library", "history"]) == 0
    lines = capsys.readouterr().out.splitlines()
    assert lines[0] == f"1 run in {default_history()}"
    assert lines[1].split() == ["#", "date", "cmd", "world", "seed", "criterion", "obj", "done", "fail", "err", "min",
                                "lib"]
    day, time = row.date[:10], row.date[11:16]
    assert lines[2].split() == ["1", day, time, "run", "lab", "0", "cs-id3-failure", "7", "2", "5", str(row.errors),
                                f"{row.robot_min_per_object:.1f}", str(size)]


def test_history_json_lists_every_run(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    path = tmp_path / "history.jsonl"
    runs = [_run(), _run(seed=None, world=None, library=None)]
    for run in runs:
        append_run(path, run)
    assert main(["library", "history", "--history", str(path), "--json"]) == 0
    doc = json.loads(capsys.readouterr().out)
    assert doc == {"history": str(path), "runs": [dataclasses.asdict(r) for r in runs], "plot": None}


def test_db_keeps_the_runs_of_one_library(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    mine, theirs = tmp_path / "mine.sqlite", tmp_path / "theirs.sqlite"
    path = tmp_path / "history.jsonl"
    for seed, library in ((1, mine), (2, theirs), (3, mine)):
        append_run(path, _run(seed=seed, library=str(library.resolve())))
    assert main(["library", "--db", str(mine), "history", "--history", str(path), "--json"]) == 0
    assert [r["seed"] for r in json.loads(capsys.readouterr().out)["runs"]] == [1, 3]
    assert main(["library", "history", "--db", str(tmp_path / "other.sqlite"), "--history", str(path)]) == 2
    assert capsys.readouterr().err == f"csl: error: {path}: no runs recorded on {tmp_path / 'other.sqlite'} yet\n"


def _curve(tmp_path: Path, name: str, runs: list[Run]) -> np.ndarray:
    path = tmp_path / f"{name}.jsonl"
    for run in runs:
        append_run(path, run)
    png = tmp_path / f"{name}.png"
    assert main(["library", "history", "--history", str(path), "--out", str(png)]) == 0
    return matplotlib.image.imread(png)


def test_the_learning_curve_is_drawn(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    falling = [_run(robot_min_per_object=m, errors=e) for m, e in ((12.0, 3), (9.0, 1), (7.0, 0))]
    drawn = _curve(tmp_path, "falling", falling)
    assert capsys.readouterr().out.splitlines()[-1] == f"learning curve: {tmp_path / 'falling.png'}"
    assert drawn.shape[0] >= 500 and drawn.shape[1] >= 500
    flat = _curve(tmp_path, "flat", [_run(robot_min_per_object=m, errors=0) for m in (12.0, 9.0, 7.0)])
    assert flat.shape == drawn.shape and not np.array_equal(flat, drawn)  # the errors line is drawn from the data


@pytest.mark.parametrize(("argv", "says"), [
    (["--history", "{tmp}/none.jsonl"], "{tmp}/none.jsonl: no history file there"),
    (["--history", "{tmp}/bad.jsonl"], "{tmp}/bad.jsonl:1: not a JSON row: "),
    (["--history", "{tmp}/empty.jsonl"], "{tmp}/empty.jsonl: no runs recorded yet"),
    (["--history", "{tmp}/empty.jsonl", "--out", "{tmp}/curve.pdf"], "--out: {tmp}/curve.pdf is not a .png file"),
    (["--history", "{tmp}/empty.jsonl", "--out", "{tmp}/no/curve.png"], "--out: folder {tmp}/no does not exist"),
])
def test_bad_input_is_one_line_and_exit_2(tmp_path: Path, capsys: pytest.CaptureFixture[str], argv: list[str],
                                          says: str) -> None:
    (tmp_path / "bad.jsonl").write_text("{oops\n", encoding="utf-8")
    (tmp_path / "empty.jsonl").write_text("", encoding="utf-8")
    assert main(["library", "history", *(a.format(tmp=tmp_path) for a in argv)]) == 2
    err = capsys.readouterr().err
    assert err.startswith(f"csl: error: {says.format(tmp=tmp_path)}") and err.count("\n") == 1


def test_help_names_every_option(capsys: pytest.CaptureFixture[str]) -> None:
    assert main(["library", "history", "--help"]) == 0
    text = capsys.readouterr().out
    assert all(option in text for option in ("--history FILE", "--out PNG", "--json", "--db"))
    assert main(["library", "--help"]) == 0
    assert "history" in capsys.readouterr().out
