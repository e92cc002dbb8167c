"""``csl demo`` twice: the second run reuses the first one's training, and neither run
has a plan that fails."""

from __future__ import annotations

import json
from pathlib import Path

import pytest

from csl_cli.main import main


def _events(out: Path) -> list[dict[str, object]]:
    return [json.loads(line) for line in (out / "episode.jsonl").read_text(encoding="utf-8").splitlines()]


@pytest.mark.slow
def test_a_second_demo_reuses_the_training_and_no_plan_fails(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    for run in ("first", "second"):
        assert main(["demo", "--out", str(tmp_path / run), "--no-plots"]) == 0
    said = capsys.readouterr().err
    trained = [line for line in said.splitlines() if line.startswith(("training on", "reusing trained library"))]
    assert len(trained) == 2 and trained[0].startswith("training on") and trained[1].startswith("reusing")
    key = trained[0].split("(library ")[1][:12]
    assert trained[1].startswith(f"reusing trained library {key}")
    for run in ("first", "second"):
        events = _events(tmp_path / run)
        assert not [e for e in events if e["event"] == "no_path"]
        moves = [e for e in events if e["event"] == "move"]
        assert moves and all(not e["collided"] for e in moves)
