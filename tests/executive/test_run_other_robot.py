"""``csl run --knowledge OTHER.toml`` from a fresh install: the shipped example library
serves only the HERO 2000, so a new library for another robot starts from one trained
for it in the simulator, kept under the demo's hash (csl_cli/demo_library.py)."""

from __future__ import annotations

import json
from pathlib import Path

import pytest

from csl_cli.main import main
from executive.defaults import EXAMPLE_LIBRARY
from csl_cli.demo_library import trained_folder
from learner.library.checks import check_library
from learner.library.format import read_library_json
from robot_profile import load_profile
from tests.hero_driver.test_zenoh_conformance import ROVER


@pytest.mark.slow
def test_run_with_the_rover_profile_trains_its_library_once(tmp_path: Path,
                                                            capsys: pytest.CaptureFixture[str]) -> None:
    rover = load_profile(ROVER)
    with pytest.raises(ValueError):  # the reason: the example is the HERO's
        check_library(read_library_json(EXAMPLE_LIBRARY), rover.knowledge(), "the example")
    first = tmp_path / "first"
    assert main(["run", "--knowledge", str(ROVER), "--no-plots", "--out", str(first)]) == 0
    captured = capsys.readouterr()
    assert "training on the Table 3 objects in the simulator (library " in captured.err
    assert "(new, seeded with a library trained for rover in the simulator (" in captured.out
    assert "exit status 0: all 7 objects were handled" in captured.out
    (kept,) = trained_folder().glob("*.json")  # one trained library, reused by the next fresh store
    events = [json.loads(line) for line in (first / "episode.jsonl").read_text().splitlines()]
    times = {p.name: p.time_s for p in rover.sensing}
    sensed = [(e["procedure"], e["seconds"]) for e in events if e["event"] == "sense"]
    assert sensed and all(times[name] == seconds for name, seconds in sensed)  # the rover's own times

    assert main(["run", "--knowledge", str(ROVER), "--no-plots", "--library", str(tmp_path / "other.sqlite"),
                 "--out", str(tmp_path / "second")]) == 0
    captured = capsys.readouterr()
    assert f"reusing trained library {kept.stem[:12]} ({kept})" in captured.err
    assert "training on" not in captured.err
