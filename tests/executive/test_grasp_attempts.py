"""What each grasp attempt cost, read from an episode's events, and which attempts the
learner may count (docs/method.md §5.7)."""

from __future__ import annotations

from pathlib import Path
from types import SimpleNamespace
from typing import cast

from behaviours.records import ObjectRecord
from behaviours.services import LibraryMatrix
from executive.grasp_attempts import (DURATION_FACTOR, AttemptCost, LearnedGraspCosts, attempt_costs,
                                      disturbed_objects, plausible_duration, recordable_attempts)
from learner.costs import GraspCostRecord
from learner.service.local import LocalLearner
from robot_profile import load_profile
from tests.behaviours.conftest import RecordingLog


def test_a_failure_that_changed_the_object_also_costs_the_sensing_it_voided() -> None:
    events = [
        {"event": "sense", "object": 0, "seconds": 42.0},
        {"event": "sense", "object": 0, "seconds": 100.0},
        {"event": "grasp", "object": 0, "grasp": "Front-Wrap", "as_feature": True, "success": False, "seconds": 60.0},
        {"event": "side_effect", "object": 0, "effect": "changed"},
        {"event": "start_over", "object": 0, "changed": True},
        {"event": "sense", "object": 0, "seconds": 45.0},
        {"event": "discriminate", "object": 0, "seconds": 5.0},
        {"event": "grasp", "object": 0, "grasp": "Top-Pinch", "as_feature": False, "success": False, "seconds": 63.0},
        {"event": "start_over", "object": 0, "changed": False},  # pushed: voids nothing
        {"event": "grasp", "object": 0, "grasp": "Top-Vert-Grip", "as_feature": False, "success": True,
         "seconds": 80.0},
        {"event": "sense", "object": 1, "seconds": 70.0},
        {"event": "grasp", "object": 1, "grasp": "Front-Wrap", "as_feature": False, "success": True, "seconds": 60.0},
        {"event": "episode_end", "status": "SUCCESS"},
    ]
    # the wrap voided 42 + 100 s of sensing: 60 + 142 = 202 s; the push costs its 63 s
    assert attempt_costs(events) == [
        AttemptCost(0, "Front-Wrap", False, 202.0), AttemptCost(0, "Top-Pinch", False, 63.0),
        AttemptCost(0, "Top-Vert-Grip", True, 80.0), AttemptCost(1, "Front-Wrap", True, 60.0)]
    assert attempt_costs(events)[0].as_record() == ("Front-Wrap", 202.0, False)


def test_a_disturbed_object_is_not_counted_and_each_object_is_counted_alone() -> None:
    events = [
        {"event": "grasp", "object": 0, "grasp": "Front-Wrap", "as_feature": True, "success": False, "seconds": 60.0},
        {"event": "disturbance", "object": 0, "before": "grasp", "found": "moved"},
        {"event": "grasp", "object": 0, "grasp": "Top-Pinch", "as_feature": False, "success": True, "seconds": 63.0},
        {"event": "sense", "object": 1, "seconds": 70.0},
        {"event": "grasp", "object": 1, "grasp": "Front-Wrap", "as_feature": False, "success": False, "seconds": 60.0},
        {"event": "start_over", "object": 1, "changed": True},
        {"event": "disturbance", "before": "grasp", "found": "gone"},  # no object: names none
        {"event": "grasp", "object": 2, "grasp": "Top-Pinch", "as_feature": False, "success": True, "seconds": 63.0},
    ]
    assert disturbed_objects(events) == {0}
    # object 0 was moved by someone: neither of its grasps is counted, the one before
    # the disturbance included; object 1's failure carries the 70 s it voided
    assert recordable_attempts(events, [0, 1]) == [AttemptCost(1, "Front-Wrap", False, 130.0)]
    assert recordable_attempts(events, [0]) == []
    assert recordable_attempts(events, [2]) == [AttemptCost(2, "Top-Pinch", True, 63.0)]


def test_a_duration_beyond_ten_times_its_procedure_time_either_way_is_implausible() -> None:
    knowledge = load_profile().knowledge()  # Front-Wrap takes 60 s; No-Grab 0 s (never executed)
    assert DURATION_FACTOR == 10.0
    assert plausible_duration("Front-Wrap", 60.0, knowledge)
    assert plausible_duration("Front-Wrap", 6.0, knowledge) and plausible_duration("Front-Wrap", 600.0, knowledge)
    assert not plausible_duration("Front-Wrap", 60_000.0, knowledge)  # milliseconds
    assert not plausible_duration("Front-Wrap", 1.0, knowledge)  # minutes
    assert not plausible_duration("Front-Wrap", 600.5, knowledge)
    assert not plausible_duration("Front-Wrap", 5.9, knowledge)
    assert plausible_duration("No-Grab", 12_345.0, knowledge)  # nothing to compare with


def test_learned_grasp_costs_leave_an_implausible_duration_out_and_say_so(tmp_path: Path) -> None:
    knowledge = load_profile().knowledge()
    learner = LocalLearner(tmp_path / "library.sqlite", knowledge=knowledge)
    log = RecordingLog()
    log.events.extend([
        {"event": "grasp", "object": 0, "grasp": "Front-Pinch", "success": False, "seconds": 45_000.0},
        {"event": "grasp", "object": 0, "grasp": "Front-Wrap", "success": True, "seconds": 60.0},
    ])
    costs = LearnedGraspCosts(learner, knowledge, LibraryMatrix(learner, knowledge), log.events, log)
    recorded = costs.finished(cast(ObjectRecord, SimpleNamespace(index=0)))
    assert [a.as_record() for a in recorded] == [("Front-Wrap", 60.0, True)]
    assert learner.grasp_costs() == [GraspCostRecord("Front-Wrap", 1, 60.0, 0, 0.0)]
    assert log.of("grasp_cost_ignored") == [
        {"event": "grasp_cost_ignored", "object": 0, "behaviour": "LearnedGraspCosts", "grasp": "Front-Pinch",
         "seconds": 45_000.0, "expected": 45.0, "factor": 10.0}]
    learner.close()
