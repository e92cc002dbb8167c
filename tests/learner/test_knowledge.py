"""The learner's knowledge: the HERO profile reaches it as docs/method.md tables it.

Reading and validating the file is robot_profile's (tests/robot_profile); here, what
the profile hands the learner.
"""

from __future__ import annotations

import pytest

from robot_profile import load_knowledge, load_profile
from tests.learner.fixtures import HERO, hero


def test_hero_profile_has_the_papers_procedures() -> None:
    k = hero()
    table2 = {p.name: (p.time_s, p.range_in) for p in k.sensing}
    assert table2 == {
        "H-Sweep-1°": (100, (6, 127)), "H-Sweep-5°": (45, (6, 127)),
        "V-Sweep-1°": (76, (6, 127)), "V-Sweep-5°": (42, (6, 127)),
        "S-Sweep-1°": (70, (6, 6)), "H-Scan-0.3": (105, (6, 6)), "D-Scan-0.3": (84, (6, 6)),
    }
    table4 = {g.name: (g.time_s, g.range_in) for g in k.grasping}
    assert table4 == {
        "Front-Pinch": (45, (6, 6)), "Front-Wrap": (60, (6, 6)), "Top-Pinch": (63, (6, 6)),
        "Top-Vert-Grip": (80, (6, 6)), "Top-Hor-Grip": (80, (6, 6)), "No-Grab": (0, (6, 999)),
    }
    assert [f.name for f in k.procedure_for("Depth").features] == ["Height", "Depth", "Top-Hole?"]
    assert k.feature("Width-Degree-5°").error == 5.0 and k.feature("Width").error == 0.5
    assert k.feature("Front-Hole?").binary and k.feature("Front-Hole?").error == 0.0
    assert not k.grasp("No-Grab").verifiable
    assert k.grasp("Top-Pinch").feature_cost_s == 63 + 40


def test_the_profiles_knowledge_keeps_every_field_and_names_the_file() -> None:
    profile = load_profile(HERO)
    k = profile.knowledge()
    assert k.source == str(HERO)
    assert k.sensing is profile.sensing and k.grasping is profile.grasping and k.move is profile.move  # one type
    assert (k.move.seconds_per_inch, k.move.seconds_per_degree, k.move.overhead_s) == (2.0, 0.0, 0.0)
    sweep = k.feature("Width-Degree-1°")
    assert (sweep.error, sweep.unit, sweep.binary, sweep.span, sweep.angular_of) == (3.0, "deg", False, (0.0, 180.0), "Width")
    assert k.feature("Top-Hole?").span == (0.0, 1.0)
    assert [p.name for p in k.sensing] == [p.name for p in profile.sensing]
    assert k.grasp("Front-Pinch").side_effect_penalty_s == 30 and k.grasp("No-Grab").feature_cost_s == 0
    with pytest.raises(KeyError, match="hero2000.toml: unknown grasping procedure 'Lift'"):
        k.grasp("Lift")


def test_loading_errors_name_the_file(tmp_path) -> None:  # noqa: ANN001
    with pytest.raises(ValueError, match="missing.toml: knowledge file not found"):
        load_knowledge(tmp_path / "missing.toml")


def test_coverage_of_a_features_domain() -> None:
    k = hero()
    hole = k.feature("Top-Hole?")
    assert hole.covered_by([(0, 0), (1, 1)]) and not hole.covered_by([(1, 1)])
    width = k.feature("Width")  # span [0, 127], error 0.5
    assert not width.covered_by([(3, 4)])
    assert width.covered_by([(0.5, 60), (60.9, 126.5)])
    assert not width.covered_by([(0.5, 60), (61.1, 126.5)])  # a 0.1 in gap past the widened ranges
