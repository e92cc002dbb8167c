"""A refusal for range is not a failed grasp, a whole episode in the simulator
(docs/executive.md, "A refusal for range is not a failed verb"): on a floor of the
unseen test objects at 3x the `paper` noise, the drift of single moves leaves the robot
more than the range tolerance off a grasp position although the camera corrects it
before every verb. Counting those refusals as failed grasps (``reapproach_tries`` 0,
the old way) drops a right grasp and leaves an object wrong; re-approaching handles all
eight."""

from __future__ import annotations

from pathlib import Path

import pytest

from behaviours.services import Params
from experiments.conditions import noise_config
from tests.executive.floors import play_floor, refused_for_range

FLOOR_SEED = 13_000  # the floor of the experiment's seed 13; measured: 9 refusals the old way, 1 re-approaching


@pytest.mark.slow
def test_a_grasp_refused_for_range_is_re_approached_not_dropped(tmp_path: Path) -> None:
    noise = noise_config("paper", 3.0)
    # measured before GraspVerified?, whose image after each grasp draws from the simulator's
    # one random stream: off, to stay this floor's story (docs/executive.md, "Verifying the robot")
    old_events, old = play_floor(tmp_path / "old", FLOOR_SEED, noise, Params(reapproach_tries=0, verify_grasps=False))
    new_events, new = play_floor(tmp_path / "new", FLOOR_SEED, noise, Params(verify_grasps=False))
    # the old way: the refused grasps dropped one by one (measured: 9 refusals, 7 of 8 right)
    assert len(refused_for_range(old_events)) >= 5 and sum(old) < len(old)
    assert not any(e["event"] == "reapproach" for e in old_events)
    # re-approaching: each refusal is followed by its re-approach, and the object is handled
    assert 1 <= len(refused_for_range(new_events)) < len(refused_for_range(old_events))
    for i in refused_for_range(new_events):
        assert new_events[i + 1]["event"] == "reapproach"
        assert new_events[i + 1]["object"] == new_events[i]["object"]
    assert sum(new) == len(new) == 8
