"""A grasp the camera's appearance chose, failing, is remembered (docs/method.md §5.8).

In the simulator, a lying 16 oz tumbler (it looks round from above: 16.0 in^2) and a
two-description library: ``look-alike`` (Top-Pinch, recorded with the tumbler's own
appearance, Height-Degree-5°(15,*) = 25) and ``other`` (Front-Pinch, recorded as a long
40 in^2 footprint, so the camera rules it out). With the appearance on, ``look-alike``
is the one candidate: the robot drives to (6,270) and tries Top-Pinch without sensing
anything; the grasp fails cleanly. Nothing was sensed, so ``Discriminate`` drives to
(15,270) for the look-alike's V-Sweep: the tumbler reads 10° there (the shipped library's
tumbler-16oz/lying has Height-Degree-5°(15,*) = 10), outside 25 ± 5, told apart. The
Front-Pinch then succeeds and the object is learned with that one value and its
appearance. On the next encounter the two candidates differ there, and the tree no
longer starts with the grasp that failed.
"""

from __future__ import annotations

import json
from pathlib import Path

from behaviours.services import Params
from executive.executive import Executive
from experiments.conditions import noise_config
from experiments.floor import play
from hero_driver.sim_driver import SimulatedHero
from learner.appearance import Appearance
from learner.choosing.criteria import DEFAULT_CRITERION, criterion
from learner.description import ObjectDescription, Observation
from learner.position import Position
from learner.service.local import LocalLearner
from robot_profile.reader import load_profile

ANY = None
TUMBLER_LOOK = Appearance(True, 16.0, 1.0)  # 4.51 in across, as the camera sees the lying tumbler end on
LOOK_ALIKE = ObjectDescription("look-alike", "Top-Pinch", Position(6, ANY),
                               (Observation("Height-Degree-5°", Position(15, ANY), 25.0),), TUMBLER_LOOK)
OTHER = ObjectDescription("other", "Front-Pinch", Position(6, ANY),
                          (Observation("Height-Degree-5°", Position(6, ANY), 40.0),), Appearance(False, 40.0, 3.0))
FLOOR = {"name": "one tumbler", "room": {"width_in": 120, "depth_in": 120}, "furniture": [],
         "robot": {"x_in": 60.0, "y_in": 30.0, "heading_deg": 90.0},
         "objects": [{"id": "tumbler-16oz/lying", "x_in": 60.0, "y_in": 60.0, "yaw_deg": 0.0}]}
KEPT = ("choose", "choose_grasp", "move", "grasp", "drop_grasp", "discriminate", "learn")


def _encounter(tmp_path: Path, learner: LocalLearner, episode: int) -> list[tuple[str, object]]:
    world = tmp_path / f"floor-{episode}.json"
    world.write_text(json.dumps(FLOOR), encoding="utf-8")
    profile = load_profile()
    hero = SimulatedHero("appearance", world=world, seed=episode, profile=profile, noise=noise_config("off"))
    executive = Executive(hero, learner, profile=profile, params=Params(use_appearance=True),
                          criterion=criterion(DEFAULT_CRITERION))
    play(hero, executive)
    return [(e["event"], e.get("grasp") or e.get("procedure") or e.get("to") or e.get("test"))
            for e in executive.log.events if e["event"] in KEPT]


def test_a_failed_grasp_chosen_by_appearance_alone_is_learned_and_not_repeated(tmp_path: Path) -> None:
    learner = LocalLearner(tmp_path / "library.sqlite", seed_library=[LOOK_ALIKE, OTHER])
    try:
        first = _encounter(tmp_path, learner, 0)
        assert first == [("choose_grasp", "Top-Pinch"), ("move", [6, 270]), ("grasp", "Top-Pinch"),
                         ("drop_grasp", "Top-Pinch"), ("move", [15, 270]), ("discriminate", "V-Sweep-5°"),
                         ("choose_grasp", "Front-Pinch"), ("move", [6, 270]), ("grasp", "Front-Pinch"),
                         ("learn", "Front-Pinch")]
        learned = [d for d in learner.library().descriptions if d.object_id.startswith("learned/")]
        assert len(learned) == 1
        (description,) = learned
        assert description.grasp == "Front-Pinch" and description.appearance == TUMBLER_LOOK
        assert description.observations == (Observation("Height-Degree-5°", Position(15, ANY), 10.0),)
        second = _encounter(tmp_path, learner, 1)
        grasps = [what for event, what in second if event == "grasp"]
        assert grasps == ["Front-Pinch"]  # right the first time: Top-Pinch is not tried again
    finally:
        learner.close()
