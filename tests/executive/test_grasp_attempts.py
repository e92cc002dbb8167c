"""What each grasp attempt cost, read from an episode's events, and which attempts the
learner may count (issue 15 §6)."""

from __future__ import annotations

from executive.grasp_attempts import AttemptCost, attempt_costs, disturbed_objects, recordable_attempts


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
