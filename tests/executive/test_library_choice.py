"""One library: after ``csl demo``, ``csl library show`` (and the other commands that
read a library, and ``csl tree``) read the demo's library while the robot's,
``$CSL_HOME/library.sqlite``, does not exist; once it does, they read the robot's
(csl_cli/library_choice.py). Every test runs in a temporary CSL_HOME and folder."""

from __future__ import annotations

import json
from pathlib import Path

import pytest

import executive.sim_training
from csl_cli.main import main
from executive import defaults
from learner.library.format import read_library_json
from learner.library.store import LibraryStore
from reporting.history import append_run, default_history, episode_run
from tests.executive.floors import sim_training

EXAMPLE = read_library_json(defaults.EXAMPLE_LIBRARY)


def _shown(capsys: pytest.CaptureFixture[str], *argv: str) -> tuple[list[str], str]:
    """The ids ``csl library show --json`` prints, and what it said on stderr."""
    assert main(["library", "show", "--json", *argv]) == 0
    out, err = capsys.readouterr()
    return [d["id"] for d in json.loads(out)["descriptions"]], err


def _a_demo_ran(library: Path, count: int = 3) -> list[str]:
    """A demo's library of ``count`` descriptions at ``library``, and its history row."""
    with LibraryStore(library) as store:
        store.add(EXAMPLE[:count])
    append_run(default_history(), episode_run(command="demo", robot="r1", world="lab", seed=0, criterion="c",
                                              outcomes=[], robot_s=0.0, events=[], library_size=count,
                                              library=library))
    return [d.object_id for d in EXAMPLE[:count]]


@pytest.mark.slow
def test_demo_then_library_show_shows_the_demos_descriptions(tmp_path: Path, capsys,  # noqa: ANN001
                                                             monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.setattr(executive.sim_training, "train_in_simulator", lambda *args, **kwargs: sim_training())
    here = tmp_path / "work"
    here.mkdir()
    monkeypatch.chdir(here)
    assert main(["demo", "--no-plots"]) == 0
    out = capsys.readouterr().out
    robot = defaults.library_db()
    assert (f"library: csl-out/library.sqlite (this demo's own; 'csl library show' and 'csl tree' read the last "
            f"demo's until 'csl run' starts your robot's, {robot})") in out.splitlines()
    demo = here / "csl-out" / "library.sqlite"
    with LibraryStore(demo) as store:
        learned = [d.object_id for d in store.descriptions()]
    assert any(i.startswith("learned/") for i in learned)  # what the demo learned, not only what it trained

    elsewhere = tmp_path / "elsewhere"
    elsewhere.mkdir()
    monkeypatch.chdir(elsewhere)  # the last demo's library is found from any folder
    ids, err = _shown(capsys)
    assert ids == learned and not robot.exists()
    assert err.startswith(f"csl library show: reading the last demo's library, {demo} (no robot library at {robot}")
    assert main(["library", "stats"]) == 0 and f"{len(learned)} descriptions," in capsys.readouterr().out
    assert main(["tree", "--json"]) == 0
    assert capsys.readouterr().err.startswith(f"csl tree: reading the last demo's library, {demo}")


def test_the_robots_library_once_it_exists(tmp_path: Path, capsys) -> None:  # noqa: ANN001
    demo_ids = _a_demo_ran(tmp_path / "demo.sqlite", 3)
    assert _shown(capsys)[0] == demo_ids
    assert main(["library", "import", str(defaults.EXAMPLE_LIBRARY)]) == 0  # import writes the robot's library
    assert f"into {defaults.library_db()} (a new library)" in capsys.readouterr().out
    ids, err = _shown(capsys)
    assert ids == [d.object_id for d in EXAMPLE] and err == ""
    assert _shown(capsys, "--db", str(tmp_path / "demo.sqlite"))[0] == demo_ids  # --db reads any


def test_the_last_demo_is_the_one_read(tmp_path: Path, capsys) -> None:  # noqa: ANN001
    _a_demo_ran(tmp_path / "first.sqlite", 2)
    last = _a_demo_ran(tmp_path / "second.sqlite", 4)
    assert _shown(capsys)[0] == last


@pytest.mark.parametrize(
    ("history", "why"),
    [
        (None, "and no demo has run ('csl demo' keeps its own in its --out folder); pass --db to choose one"),
        ("gone", "and the last demo's, {gone}, is gone; pass --db to choose one"),
        ("damaged", "and the last demo's could not be looked up ({history}:1: not a JSON row: "),
    ],
)
def test_no_library_to_read_is_one_line(tmp_path: Path, capsys, history: str | None, why: str) -> None:  # noqa: ANN001
    gone = tmp_path / "gone.sqlite"
    if history == "gone":
        _a_demo_ran(gone)
        gone.unlink()
    elif history == "damaged":
        default_history().parent.mkdir(parents=True, exist_ok=True)
        default_history().write_text("{not json\n", encoding="utf-8")
    for action in ("show", "stats", "export", "check", "backup"):
        argv = ["library", action] + ([str(tmp_path / "out.json")] if action in ("export", "backup") else [])
        assert main(argv) == 2
        err = capsys.readouterr().err.splitlines()
        assert len(err) == 1 and err[0].startswith(
            f"csl: error: {defaults.library_db()}: no library database there ('csl run' or 'csl library import' "
            "starts it), ")
        assert why.format(gone=gone, history=default_history()) in err[0]


def test_tree_falls_back_to_the_example_library(capsys) -> None:  # noqa: ANN001
    assert main(["tree"]) == 0
    out, err = capsys.readouterr()
    assert out.startswith("move-to-(") and err == ""


def test_a_demo_never_starts_the_robots_library_anew(capsys) -> None:  # noqa: ANN001
    home = defaults.library_db().parent
    home.mkdir(parents=True, exist_ok=True)
    assert main(["demo", "--out", str(home)]) == 2
    err = capsys.readouterr().err.splitlines()
    assert err == [f"csl: error: --out: {home} is where your robot's library is kept ($CSL_HOME), and a demo makes "
                   "its own library anew in --out: choose another folder"]
