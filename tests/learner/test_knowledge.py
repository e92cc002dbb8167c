"""The knowledge file: the HERO profile loads as method.md tables it; bad files are named."""

from __future__ import annotations

import tomllib

import pytest

from learner.knowledge import knowledge_from_dict, load_knowledge
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


def _data() -> dict:
    with HERO.open("rb") as fh:
        return tomllib.load(fh)


@pytest.mark.parametrize(
    ("mutate", "message"),
    [
        (lambda d: d["sensing"][0].pop("time_s"), "sensing[0] (H-Sweep-1°): missing field 'time_s'"),
        (lambda d: d["sensing"][1].update(colour="red"), "sensing[1] (H-Sweep-5°): unknown key 'colour'"),
        (lambda d: d["grasping"][2].update(time_s=-1), "grasping[2] (Top-Pinch): 'time_s' must not be negative"),
        (lambda d: d["sensing"][4].update(range_in=[9, 6]), "sensing[4] (S-Sweep-1°): 'range_in' is empty"),
        (lambda d: d["move"].pop("overhead_s"), "[move]: missing field 'overhead_s'"),
        (lambda d: d.update(extra={}), "unknown key 'extra'"),
        (lambda d: d["sensing"][1]["features"].append({"name": "Width", "error": 0.7, "unit": "in", "span": [0, 127]}),
         "feature 'Width' is yielded by 'H-Sweep-5°' and 'H-Scan-0.3' with different errors"),
        (lambda d: d["sensing"][0]["features"][0].update(angular_of="Colour"), "'angular_of' names 'Colour'"),
    ],
)
def test_bad_knowledge_is_rejected_naming_file_entry_and_problem(mutate, message) -> None:  # noqa: ANN001
    data = _data()
    mutate(data)
    with pytest.raises(ValueError) as err:
        knowledge_from_dict(data, "k.toml")
    assert str(err.value).startswith("k.toml: ")
    assert message in str(err.value)


def test_unreadable_files_are_one_line_errors(tmp_path) -> None:  # noqa: ANN001
    with pytest.raises(ValueError, match="knowledge file not found"):
        load_knowledge(tmp_path / "missing.toml")
    bad = tmp_path / "bad.toml"
    bad.write_text("[move\n")
    with pytest.raises(ValueError, match="not valid TOML"):
        load_knowledge(bad)


def test_coverage_of_a_features_domain() -> None:
    k = hero()
    hole = k.feature("Top-Hole?")
    assert hole.covered_by([(0, 0), (1, 1)]) and not hole.covered_by([(1, 1)])
    width = k.feature("Width")  # span [0, 127], error 0.5
    assert not width.covered_by([(3, 4)])
    assert width.covered_by([(0.5, 60), (60.9, 126.5)])
    assert not width.covered_by([(0.5, 60), (61.1, 126.5)])  # a 0.1 in gap past the widened ranges
