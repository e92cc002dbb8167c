"""Dead reckoning corrected by the overhead camera, a whole episode in the simulator
(docs/executive.md, "Where the robot is"): on a floor of the experiment's noisy
execution episodes where the `paper` preset's drift grows past the 6 in procedures'
range tolerance, the driver refuses procedures for range when the executive trusts its
dead reckoning, and none when the camera corrects it: all eight objects are then
handled right, one fewer without. Without the camera a refused procedure is not
re-approached (the same plan from the same believed pose would end where the robot
stands): the refusal counts as the verb failing."""

from __future__ import annotations

from pathlib import Path

import pytest

from behaviours.services import Params
from experiments.conditions import EXECUTION_NOISE, noise_config
from tests.executive.floors import play_floor, refused_for_range

FLOOR_SEED = 24_000  # the experiment's floor of seed 24: drift past 1.5 in, one object lost trusting it
# The floor's story was measured before GraspVerified?: its image after each grasp draws from
# the simulator's one random stream, so these runs keep it off to stay that story
# (docs/executive.md, "Verifying the robot").


def episode(tmp_path: Path, localise: bool) -> tuple[list[dict[str, object]], list[bool]]:
    """The floor's events and, per record, whether its object was handled right."""
    return play_floor(tmp_path / ("on" if localise else "off"), FLOOR_SEED, noise_config(EXECUTION_NOISE),
                      Params(localise=localise, verify_grasps=False))


@pytest.mark.slow
def test_the_camera_keeps_the_robot_within_the_procedures_range(tmp_path: Path) -> None:
    trusting, before = episode(tmp_path, localise=False)
    corrected, after = episode(tmp_path, localise=True)
    # measured 9 (the robot more than 1.5 in off the 6 in it meant to stand at); the count
    # moves with the recoveries, which try more or fewer grasps there
    assert len(refused_for_range(trusting)) >= 5
    assert refused_for_range(corrected) == []
    assert any(e["event"] == "localised" for e in corrected)
    assert sum(after) == len(after) == 8 and sum(before) < 8  # measured: 7 of 8 handled right trusting it
    assert not any(e["event"] == "reapproach" for e in trusting)  # nothing corrected the pose it would plan from

