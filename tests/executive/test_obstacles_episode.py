"""A person crossing the robot's way, whole episodes in the simulator: with the driver's
safety stop and the blocked-move branch the robot stops short, waits or goes around,
and grasps the bottle without ever touching anyone; without them (a driver that
ignores movers, the branch off) the same floor ends in contacts.

The floor: the disturbance episodes' soda bottle (Front-Wrap) and closed box (No-Grab),
with a person pacing the line x = 40 in between the robot's start and the bottle, who
walks into the robot's way after the first image.
"""

from __future__ import annotations

import json
from pathlib import Path

from behaviours.services import Params
from executive import defaults
from executive.episode_log import EpisodeLog
from executive.executive import EpisodeResult, Executive
from hero_driver.sim_driver import SimulatedHero
from learner.library.format import read_library_json
from learner.service.local import LocalLearner

BOTTLE = {"id": "soda-bottle-16oz/upright", "x_in": 70, "y_in": 30}
BOX = {"id": "closed-box-10x10x10/upright", "x_in": 85, "y_in": 70, "yaw_deg": 15}
# starting at the far end (40, 92), out of the first camera image's way: the camera draws
# movers, so one standing in the way at the start is planned around, stop or no stop
PERSON = {"shape": "disc", "path": [[40, 8], [40, 92]], "speed_in_s": 12, "start_in": 84}


def floor(tmp_path: Path) -> Path:
    data = {"name": "crossing", "room": {"width_in": 120, "depth_in": 100},
            "robot": {"x_in": 20, "y_in": 20, "heading_deg": 0}, "objects": [BOTTLE, BOX], "movers": [PERSON]}
    path = tmp_path / "crossing.json"
    path.write_text(json.dumps(data), encoding="utf-8")
    return path


def episode(tmp_path: Path, *, on: bool) -> tuple[EpisodeResult, EpisodeLog, SimulatedHero]:
    driver = SimulatedHero("r1", world=floor(tmp_path), seed=0, stop_for_movers=on)
    learner = LocalLearner(tmp_path / f"library-{on}.sqlite", seed_library=read_library_json(defaults.EXAMPLE_LIBRARY))
    log = EpisodeLog()
    executive = Executive(driver, learner, log=log, params=Params(blocked_tries=3 if on else 0))
    try:
        return executive.run(), log, driver
    finally:
        executive.shutdown()
        learner.close()


def test_the_robot_stops_short_waits_or_goes_around_and_grasps_without_contact(tmp_path: Path) -> None:
    result, log, driver = episode(tmp_path, on=True)
    moves = [e for e in log.events if e["event"] == "move"]
    assert any("blocked" in e for e in moves)  # the person did get in the way
    assert any(e["behaviour"] in ("MoveTo test around it", "MoveTo test again", "WaitForMover") for e in moves)
    assert [r.outcome for r in result.objects] == ["grasped", "left"]
    assert result.objects[0].grasp == "Front-Wrap" and driver.truth()[0].binned
    assert driver.contacts == 0


def test_without_the_stop_and_the_branch_the_same_floor_ends_in_contacts(tmp_path: Path) -> None:
    result, log, driver = episode(tmp_path, on=False)
    assert driver.contacts > 0
    assert not any("blocked" in e for e in log.events)
