"""``--disturb`` on ``csl demo`` and ``csl run --driver sim``: the simulator's disturbance
preset reaches the in-process simulator, and objects taken away are reported gone, which
is not a failure of the run (docs/executive.md, "Disturbances")."""

from __future__ import annotations

import json
from pathlib import Path

import pytest

from csl_cli.main import main


def test_every_object_taken_away_is_reported_gone_and_the_run_succeeds(tmp_path: Path,
                                                                       capsys: pytest.CaptureFixture[str]) -> None:
    # with the appearance on, four of the seven are handled before any sensing there is to
    # disturb: the story of every object taken away is told with the arm alone
    status = main(["run", "--driver", "sim", "--disturb", "remove:1", "--no-plots", "--out", str(tmp_path / "o"),
                   "--json", "--no-appearance"])
    document = json.loads(capsys.readouterr().out)
    outcomes = [o["outcome"] for o in document["objects"]]
    assert outcomes == ["gone"] * 7  # the lab's seven objects, each removed after its first sensing
    assert status == 0
    events = [json.loads(line) for line in (tmp_path / "o" / "episode.jsonl").read_text().splitlines()]
    assert sum(e["event"] == "gone" for e in events) == 7
    assert not [e for e in events if e["event"] == "learn"]  # nothing learned from a disturbed attempt


def test_a_bad_disturbance_is_one_line_and_exit_2(capsys: pytest.CaptureFixture[str]) -> None:
    assert main(["demo", "--disturb", "nudge:2"]) == 2
    error = capsys.readouterr().err.strip().splitlines()
    assert error == ["csl demo: error: argument --disturb: 'nudge:2': the probability must be a number from 0 to 1 "
                     "(see 'csl demo --help')"]
