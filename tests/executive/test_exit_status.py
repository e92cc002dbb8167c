"""The exit status a script reads after ``csl run`` (executive/exit_status.py)."""

from __future__ import annotations

from executive.exit_status import ALL_HANDLED, LOST, SOME_FAILED, episode_status, run_status


def test_all_grasped_or_left_is_success() -> None:
    assert episode_status(["grasped", "left", "grasped"]) == (ALL_HANDLED, "all 3 objects were handled")


def test_one_failed_or_unfinished_object_fails_the_run() -> None:
    assert episode_status(["grasped", "failed", None]) == (SOME_FAILED, "2 of 3 objects were not handled")


def test_no_object_located_is_a_failure_not_a_success() -> None:
    status, why = episode_status([])
    assert status == SOME_FAILED and "no object was located" in why


def test_no_object_grasped_is_nothing_really_done() -> None:
    assert episode_status(["left", "left", "failed"]) == (
        SOME_FAILED, "nothing really done: no object of 3 was grasped (2 left as No-Grab, 1 not handled)")
    assert episode_status(["left", "grasped"]) == (ALL_HANDLED, "all 2 objects were handled")
    assert episode_status(["gone", "left"])[0] == ALL_HANDLED  # taken away: not the robot's doing


FAULTS = [{"event": "driver_fault", "object": i % 3, "verb": verb, "message": "x"}
          for i, verb in enumerate(["grasp"] * 7 + ["sense"] * 2)]


def test_driver_faults_end_the_run_3_with_a_count_per_verb() -> None:
    status, why, lines = run_status(["left", "grasped", "left"], FAULTS, "r1")
    line = "9 driver faults (grasp: 7, sense: 2): driver r1 failed verbs (`internal` or malformed replies); " \
           "look at the robot"
    assert (status, lines) == (LOST, [line])
    assert why == f"{line}; all 3 objects were handled"


def test_an_unverified_grasp_names_the_driver_suspect() -> None:
    events = [{"event": "grasp_unverified", "object": 2, "driver": "hero7"}]
    status, why, lines = run_status(["grasped", "grasped", "failed"], events, "hero7")
    assert status == LOST
    assert lines == ["driver hero7 suspect: 1 grasps reported held while the look after (the camera's, or a rescan) "
                     "still saw the object on the floor (objects 2); check its finger sensor"]


def test_implausible_values_are_counted_and_fail_the_run_only_when_an_object_failed() -> None:
    events = [{"event": "implausible", "feature": f} for f in ("Width", "Height", "Width")]
    line = "3 implausible values (Width: 2, Height: 1): those tests were reselected; check the sensors' units"
    assert run_status(["grasped", "left"], events) == (ALL_HANDLED, "all 2 objects were handled", [line])
    assert run_status(["grasped", "failed"], events) == (SOME_FAILED, "1 of 2 objects were not handled", [line])


def test_a_feature_whose_values_were_mostly_implausible_makes_the_driver_suspect() -> None:
    """Width sensed 5 times, 4 of them implausible: a sensor in another unit (the run
    ends 3 whatever its objects' outcomes). Height sensed 10 times, 2 implausible: a
    sonar's outliers, said and no more. Three implausible of three is enough; two of
    two is not (:data:`WRONG_UNIT_MIN`)."""
    def sensed(feature: str, n: int) -> list[dict[str, object]]:
        return [{"event": "sense", "procedure": "p", "values": {feature: 1.0}}] * n

    def bad(feature: str, n: int) -> list[dict[str, object]]:
        return [{"event": "implausible", "feature": feature}] * n

    events = sensed("Width", 5) + bad("Width", 4) + sensed("Height", 10) + bad("Height", 2)
    status, why, lines = run_status(["grasped", "left"], events, "r1")
    assert status == LOST
    assert lines == ["driver r1 suspect: most values of Width were implausible (Width: 4 of 5); check that "
                     "sensor's unit against the profile"]
    assert why == f"{lines[0]}; all 2 objects were handled"
    noise = sensed("Height", 10) + bad("Height", 2)
    assert run_status(["grasped"], noise)[0] == ALL_HANDLED
    assert run_status(["grasped"], sensed("Width", 3) + bad("Width", 3))[0] == LOST
    assert run_status(["grasped"], sensed("Width", 2) + bad("Width", 2))[0] == ALL_HANDLED


def test_refusals_for_range_are_said_only_when_the_run_did_not_succeed() -> None:
    events = [{"event": "driver_error", "object": 0, "code": "out_of_range", "message": "m"}] * 4
    assert run_status(["grasped"], events) == (ALL_HANDLED, "all 1 objects were handled", [])
    status, why, lines = run_status(["left", "left"], events)
    assert (status, why) == (SOME_FAILED, "nothing really done: no object of 2 was grasped (2 left as No-Grab, "
                                          "0 not handled)")
    assert lines == ["4 procedures refused for range: check the sonar's unit and the robot's range check "
                     "against the profile"]


def test_durations_left_out_of_the_grasp_costs_make_the_driver_suspect() -> None:
    events = [{"event": "grasp_cost_ignored", "object": 0, "grasp": "Front-Wrap"}] * 2
    status, _, lines = run_status(["grasped"], events, "r1")
    assert status == LOST and lines[0].startswith("driver r1 suspect: 2 grasp durations implausible")


def test_state_publications_the_link_refused_end_the_run_3_and_say_so() -> None:
    status, why, lines = run_status(["grasped", "left"], [], "r1", refused_states=4)
    assert status == LOST
    assert lines == ["4 state publications for r1 refused: nothing asked of the robot explained them (a second "
                     "client driving it, a driver that restarted with a fresh world, or a forged state; "
                     "docs/security.md)"]
    assert why.startswith(lines[0]) and why.endswith("all 2 objects were handled")
    assert run_status(["grasped", "left"], [], "r1")[0] == ALL_HANDLED  # none refused: nothing said
