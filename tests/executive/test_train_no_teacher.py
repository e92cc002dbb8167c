"""``csl train --sim --no-teacher``: training objects' grasps found by trying grasps in
the simulator, next to the catalogue's labels (docs/method.md §4.1)."""

from __future__ import annotations

import pytest

from csl_cli.main import main
from robot_profile import load_knowledge
from executive.sim_training import train_in_simulator
from executive.training_sources import SimulatorGrasps, camera_objects
from learner.costs import ModelMoveCost
from learner.library.format import read_library_json
from learner.position import Position
from learner.training.grasps import find_grasps
from tests.learner.fixtures import HERO

FEW = ("cup-8oz/upright", "tumbler-16oz/upright", "tumbler-16oz/lying", "soda-can-12oz/lying",
       "closed-box-11x9x12/upright")


def test_on_a_few_table_3_objects_the_grasp_found_is_the_taught_one() -> None:
    knowledge = load_knowledge(HERO)
    seen = camera_objects()
    taught = [o for o in seen.objects if o.object_id in FEW]
    search = find_grasps(taught, knowledge, SimulatorGrasps(axis_offsets_deg=seen.axis_offsets_deg),
                         ModelMoveCost(knowledge.move))
    found = {o.object_id: o.grasp for o in search.objects}
    for o in taught:
        if o.object_id == "soda-can-12oz/lying":  # Table 3: either top grip, by the approach
            assert found[o.object_id] in ("Top-Vert-Grip", "Top-Hor-Grip")
        else:
            assert found[o.object_id] == o.grasp, o.object_id
    # the cup is round: tried from anywhere; the closed box held by nothing, from both sides
    assert next(o for o in search.objects if o.object_id == "cup-8oz/upright").grasp_position == Position(6, None)
    assert sum(t.object_id == "closed-box-11x9x12/upright" for t in search.trials) == 10
    assert search.grasping_s == sum(knowledge.grasp(t.grasp).time_s for t in search.trials)


def test_a_found_top_grip_holds_from_where_it_was_found_and_the_other_side_fails() -> None:
    seen = camera_objects()
    grasps = SimulatorGrasps(axis_offsets_deg=seen.axis_offsets_deg)
    side = grasps.try_grasp("soda-can-12oz/lying", "Top-Hor-Grip", Position(6, 90))
    end = grasps.try_grasp("soda-can-12oz/lying", "Top-Hor-Grip", Position(6, 0))
    assert side.success and not end.success and side.seconds == 80.0


@pytest.mark.slow
def test_no_teacher_training_finds_the_same_features_and_counts_the_attempts() -> None:
    knowledge = load_knowledge(HERO)
    taught = train_in_simulator(knowledge)
    found = train_in_simulator(knowledge, teacher=False)
    assert taught.grasp_search is None and taught.robot_s == taught.summary.total_s
    search = found.grasp_search
    assert search is not None
    assert found.robot_s == pytest.approx(found.summary.total_s + search.grasping_s + search.moving_s)
    # what is measured does not depend on which top grip (or approach) a lying can got
    assert [d.observations for d in found.result.descriptions] == [d.observations for d in taught.result.descriptions]
    # and only the lying cans differ: either top grip is right (Table 3), the search found
    # the side one; every grasp that holds from any side was found to (its position (6,*))
    differ = {a.object_id: (b.grasp, b.grasp_position) for a, b in zip(taught.result.descriptions,
                                                                      found.result.descriptions) if a != b}
    assert differ == {"soda-can-12oz/lying": ("Top-Hor-Grip", Position(6, 90)),
                      "tennis-can/lying": ("Top-Hor-Grip", Position(6, 90))}


@pytest.mark.slow
def test_csl_train_no_teacher_prints_the_search_and_needs_sim(tmp_path, capsys) -> None:  # noqa: ANN001
    out = tmp_path / "lib.json"
    assert main(["train", "--sim", "--no-teacher", "--out", str(out)]) == 0
    printed = capsys.readouterr().out
    assert "grasps found by trying them" in printed and "with finding the grasps:" in printed
    assert len(read_library_json(out)) == 14
    assert main(["train", "--no-teacher", "--out", str(out)]) == 2
    assert "--no-teacher tries grasps in the simulator: it goes with --sim" in capsys.readouterr().err
