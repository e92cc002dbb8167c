"""``csl demo --knowledge FILE``: the planner and the simulator both work from FILE.

Before, the planner and the simulator were handed the shipped profile whatever the flag
said. Here the profile's vision time is raised from 5 s to 60 s: the simulator charges
it at the start of every move, and the planner adds it to the price of every move that
goes anywhere, so with the shipped profile some moves and prices stay well under 60 s
(a short reposition costs about 25 s).
"""

from __future__ import annotations

import json
import math
from pathlib import Path

import pytest

from csl_cli.main import main
from robot_profile import DEFAULT_PROFILE

VISION_S = 60.0


@pytest.mark.slow
def test_demo_plans_and_simulates_with_the_given_profile(tmp_path: Path, capsys) -> None:  # noqa: ANN001
    text = DEFAULT_PROFILE.read_text(encoding="utf-8")
    assert "vision_s = 5.0" in text
    profile = tmp_path / "slow-vision.toml"
    profile.write_text(text.replace("vision_s = 5.0", f"vision_s = {VISION_S}"), encoding="utf-8")
    out = tmp_path / "out"
    assert main(["demo", "--knowledge", str(profile), "--out", str(out), "--no-plots"]) in (0, 1)
    capsys.readouterr()
    events = [json.loads(line) for line in (out / "episode.jsonl").read_text().splitlines()]
    timed = [e["seconds"] for e in events if e["event"] == "move"]
    priced = [e["move_s"] for e in events if e["event"] == "choose" and e.get("move_s")]
    assert timed and priced
    assert min(timed) >= VISION_S  # the simulator's clock
    assert min(s for s in priced if math.isfinite(s)) >= VISION_S  # the planner's price
