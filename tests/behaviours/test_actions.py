"""Acting on the robot: LocateObjects, MoveTo, ApplyTest, Grasp, Learn (behaviours.actions).

The FakeNavigator's geometry (conftest) puts position (d, o) of the object at
(100, 50) at the world point (100 + d cos o, 50 + d sin o), facing the object: (60,0)
is (160, 50, 180), (24,0) is (124, 50, 180), (6,0) is (106, 50, 180).
"""

from __future__ import annotations

import dataclasses

import pytest
from py_trees.common import Status

from behaviours.actions import ApplyTest, Grasp, Learn, LocateObjects, MoveTo
from behaviours.records import GraspAttempt
from hero_driver.interface import (BUSY, NO_TARGET, UNAVAILABLE, Driver, DriverError, GraspResult,
                                   Pose as DriverPose, RobotState, SenseResult)
from learner.appearance import Appearance
from learner.choosing.node import ScoredTest
from learner.description import ObjectDescription, Observation
from planner import Region
from tests.behaviours.conftest import (HEIGHT, PENDING, REGION, ROBOT, FakeDriver, P, fresh_board, get, image, measure,
                                       moved, pose_at, put, refused, region, run, setup, start_object, tick)


def test_the_fake_driver_is_a_driver(driver) -> None:  # noqa: ANN001
    assert isinstance(driver, Driver)


# -- LocateObjects ---------------------------------------------------------------------------


def test_locate_objects_queues_every_region_nearest_first(services, driver, nav, log) -> None:  # noqa: ANN001
    far, north, south = region(100, 50), region(30, 40, pixels=90), region(30, -40, pixels=60, orientation=None)
    nav.see(far, north, south)
    driver.script("camera", image())
    fresh_board()
    assert run(LocateObjects(ROBOT), services) == Status.SUCCESS
    # the robot stands at (0, 0) (driver.state()): north and south are both 50 in away,
    # ties broken by centroid, so south (y = -40) first; far is 111.8 in away
    assert get("objects") == [south, north, far]
    assert driver.verbs() == ["camera"] and nav.observed == 1
    assert log.events == [{"event": "located", "behaviour": "LocateObjects", "regions": [
        {"centroid": [30.0, -40.0], "pixels": 60, "orientation": None},
        {"centroid": [30.0, 40.0], "pixels": 90, "orientation": 0.0},
        {"centroid": [100.0, 50.0], "pixels": 200, "orientation": 0.0}]}]


def test_locate_objects_measures_from_the_end_of_the_last_move(services, driver, nav) -> None:  # noqa: ANN001
    far, near = region(100, 50), region(30, 40)
    nav.see(near, far)
    driver.script("camera", image())
    fresh_board()
    put("pose", DriverPose(110.0, 50.0, 0.0))  # the last move ended beside `far`
    assert run(LocateObjects(ROBOT), services) == Status.SUCCESS
    assert get("objects") == [far, near]


def test_locate_objects_runs_while_the_camera_is_busy(services, driver, nav) -> None:  # noqa: ANN001
    nav.see(REGION)
    driver.script("camera", PENDING)
    fresh_board()
    behaviour = setup(LocateObjects(ROBOT), services)
    assert tick(behaviour, max_ticks=3) == Status.RUNNING
    assert behaviour.feedback_message == "waiting for the robot" and nav.observed == 0
    driver.pending[0].set_result(image())
    assert tick(behaviour) == Status.SUCCESS and get("objects") == [REGION]
    assert driver.verbs() == ["camera"]  # started once, watched three times


def test_locate_objects_fails_when_the_camera_is_refused(services, driver, log) -> None:  # noqa: ANN001
    driver.script("camera", refused(BUSY, "another verb is executing"))
    fresh_board()
    assert run(LocateObjects(ROBOT), services) == Status.FAILURE
    assert log.of("driver_error")[0]["code"] == BUSY


def test_locate_objects_raises_when_the_driver_is_gone(services, driver) -> None:  # noqa: ANN001
    driver.script("camera", refused(UNAVAILABLE, "driver closed"))
    fresh_board()
    with pytest.raises(DriverError, match="unavailable"):
        run(LocateObjects(ROBOT), services)


# -- MoveTo test -----------------------------------------------------------------------------


def _at_sixty(services, nav):  # noqa: ANN001, ANN202
    """The session at (60,0) with the width test chosen, the robot standing there."""
    record, step = start_object(services)
    step.test = record.session.decide()
    put("pose", pose_at(nav, P(60, 0)))
    return record, step


def test_move_to_test_plans_and_drives_to_the_tests_position(services, driver, nav, log) -> None:  # noqa: ANN001
    record, step = _at_sixty(services, nav)
    there = DriverPose(124.0, 50.0, 180.0)
    driver.script("move", moved(there, 72.0))
    assert run(MoveTo(ROBOT, "test"), services) == Status.SUCCESS
    start, goal = nav.plans[0]
    assert (start.x_in, start.y_in, goal.x_in, goal.y_in, goal.heading_deg) == (160.0, 50.0, 124.0, 50.0, 180.0)
    assert driver.calls == [("move", (there,), (100.0, 50.0))]  # the path's waypoints, facing the object
    assert get("pose") == there and record.session.position == P(24, 0)
    assert record.ledger.moving_s == 72.0 and record.ledger.computing_s == 0.25  # one timed plan
    assert log.events == [{"event": "move", "object": 0, "behaviour": "MoveTo test", "to": [24, 0],
                           "seconds": 72.0, "collided": False, "pose": [124.0, 50.0, 180.0],
                           "path": [[124.0, 50.0, 180.0]]}]


def test_move_to_test_already_there_needs_no_move(services, driver, nav, log) -> None:  # noqa: ANN001
    record, step = _at_sixty(services, nav)
    record.session.position = P(24, 0)
    assert run(MoveTo(ROBOT, "test"), services) == Status.SUCCESS
    assert nav.plans == [] and driver.calls == [] and log.events == []


def test_move_to_test_with_no_path_marks_the_test_tried_without_a_value(services, driver, nav, log) -> None:  # noqa: ANN001
    record, step = _at_sixty(services, nav)
    nav.block(REGION, P(24, 0), "goal in collision")
    assert run(MoveTo(ROBOT, "test"), services) == Status.FAILURE
    assert driver.calls == []
    assert log.events == [{"event": "no_path", "object": 0, "behaviour": "MoveTo test", "to": [24, 0],
                           "reason": "goal in collision"}]
    session = record.session
    assert session.awaiting_reselection
    assert session.measurements == {} and session.unreliable_count == 0 and not session.can_follow_nearest
    assert session.position == P(60, 0) and get("pose") == pose_at(nav, P(60, 0))
    nxt = session.decide()  # the width counts as tried: the height is reselected
    assert isinstance(nxt, ScoredTest) and str(nxt.test) == HEIGHT


def test_move_to_test_that_collided_is_unusable(services, driver, nav, log) -> None:  # noqa: ANN001
    record, step = _at_sixty(services, nav)
    stopped = DriverPose(140.0, 50.0, 180.0)
    driver.script("move", moved(stopped, 40.0, collided=True))
    assert run(MoveTo(ROBOT, "test"), services) == Status.FAILURE
    assert get("pose") == stopped and record.ledger.moving_s == 40.0  # paid, and where it stopped
    assert record.session.position == P(60, 0) and record.session.awaiting_reselection
    assert log.events[0]["collided"] is True


def test_move_to_test_refused_by_the_driver_is_unusable(services, driver, nav, log) -> None:  # noqa: ANN001
    record, step = _at_sixty(services, nav)
    driver.script("move", refused(BUSY, "still sensing"))
    assert run(MoveTo(ROBOT, "test"), services) == Status.FAILURE
    assert record.session.awaiting_reselection and record.ledger.moving_s == 0.0
    assert log.events == [{"event": "driver_error", "object": 0, "behaviour": "MoveTo test", "code": BUSY,
                           "message": "still sensing"}]


def test_move_to_test_raises_when_the_driver_is_gone(services, driver, nav, log) -> None:  # noqa: ANN001
    record, step = _at_sixty(services, nav)
    driver.script("move", refused(UNAVAILABLE, "driver closed"))
    with pytest.raises(DriverError) as raised:
        run(MoveTo(ROBOT, "test"), services)
    assert raised.value.code == UNAVAILABLE
    assert log.kinds() == ["driver_error"] and not record.session.awaiting_reselection


def test_move_to_reports_running_and_cancels_when_preempted(services, driver, nav) -> None:  # noqa: ANN001
    record, step = _at_sixty(services, nav)
    driver.script("move", PENDING)
    behaviour = setup(MoveTo(ROBOT, "test"), services)
    assert tick(behaviour, max_ticks=2) == Status.RUNNING
    future = driver.pending[0]
    behaviour.stop(Status.INVALID)  # pre-empted by a higher-priority branch
    assert future.cancelled() and record.session.position == P(60, 0)


def test_move_to_test_without_a_test_fails(services, driver, nav) -> None:  # noqa: ANN001
    start_object(services)
    assert run(MoveTo(ROBOT, "test"), services) == Status.FAILURE
    assert nav.plans == [] and driver.calls == []


def test_move_to_refuses_an_unknown_target() -> None:
    with pytest.raises(ValueError, match="'test' or 'grasp'"):
        MoveTo(ROBOT, "leaf")


def test_move_to_without_setup_raises_a_clear_error(services) -> None:  # noqa: ANN001
    record, step = start_object(services)
    step.test = record.session.decide()
    with pytest.raises(RuntimeError, match="MoveTo test: ticked before setup"):
        MoveTo(ROBOT, "test").tick_once()


# -- MoveTo grasp ----------------------------------------------------------------------------


def _leaf_attempt(services, nav, grasp: str = "Front-Pinch", at=P(6, 0)):  # noqa: ANN001, ANN202
    record, step = start_object(services)
    measure(record, 18.0)  # the box: robot at (24,0)
    step.attempt = GraspAttempt(grasp, at)
    put("pose", pose_at(nav, P(24, 0)))
    return record, step


def test_move_to_grasp_drives_to_the_grasp_position(services, driver, nav, log) -> None:  # noqa: ANN001
    record, step = _leaf_attempt(services, nav)
    driver.script("move", moved(DriverPose(106.0, 50.0, 180.0), 36.0))
    assert run(MoveTo(ROBOT, "grasp"), services) == Status.SUCCESS
    assert record.session.position == P(6, 0) and record.ledger.moving_s == 36.0
    assert step.attempt == GraspAttempt("Front-Pinch", P(6, 0))  # not yet tried
    assert log.events[0]["to"] == [6, 0] and log.events[0]["behaviour"] == "MoveTo grasp"


def test_move_to_grasp_with_no_path_fails_without_failing_the_grasp(services, driver, nav, log) -> None:  # noqa: ANN001
    record, step = _leaf_attempt(services, nav)
    nav.block(REGION, P(6, 0), "goal outside the free space")
    assert run(MoveTo(ROBOT, "grasp"), services) == Status.FAILURE
    assert step.attempt == GraspAttempt("Front-Pinch", P(6, 0)) and not step.attempt.failed  # OtherEnd's turn
    assert driver.calls == [] and not record.session.awaiting_reselection
    assert log.events == [{"event": "no_path", "object": 0, "behaviour": "MoveTo grasp", "to": [6, 0],
                           "reason": "goal outside the free space"}]


def test_move_to_grasp_that_collided_is_a_failed_grasp(services, driver, nav) -> None:  # noqa: ANN001
    record, step = _leaf_attempt(services, nav)
    driver.script("move", moved(DriverPose(115.0, 50.0, 180.0), 20.0, collided=True))
    assert run(MoveTo(ROBOT, "grasp"), services) == Status.FAILURE
    assert step.attempt is not None and step.attempt.failed and record.session.position == P(24, 0)


def test_move_to_grasp_of_a_failed_attempt_fails_at_once(services, driver, nav) -> None:  # noqa: ANN001
    record, step = _leaf_attempt(services, nav)
    step.attempt = GraspAttempt("Front-Pinch", P(6, 0), success=False)
    assert run(MoveTo(ROBOT, "grasp"), services) == Status.FAILURE
    assert nav.plans == [] and driver.calls == []


# -- ApplyTest -------------------------------------------------------------------------------


def test_apply_test_senses_and_keeps_every_value(services, driver, log) -> None:  # noqa: ANN001
    record, step = start_object(services)
    step.test = record.session.decide()
    driver.script("sense", SenseResult("H-Sweep-1°", {"Width-Degree-1°": 8.5004}, 100.0, 24.0))
    assert run(ApplyTest(ROBOT), services) == Status.SUCCESS
    assert driver.calls == [("sense", "H-Sweep-1°")]
    assert step.values == {"Width-Degree-1°": 8.5004} and record.ledger.sensing_s == 100.0
    assert record.session.measurements == {}  # following the branch is FollowBranch's
    assert log.events == [{"event": "sense", "object": 0, "behaviour": "ApplyTest", "procedure": "H-Sweep-1°",
                           "values": {"Width-Degree-1°": 8.5}, "seconds": 100.0}]


def test_apply_test_runs_until_the_sonar_answers(services, driver) -> None:  # noqa: ANN001
    record, step = start_object(services)
    step.test = record.session.decide()
    driver.script("sense", PENDING)
    behaviour = setup(ApplyTest(ROBOT), services)
    assert tick(behaviour, max_ticks=2) == Status.RUNNING and step.values is None
    driver.pending[0].set_result(SenseResult("H-Sweep-1°", {"Width-Degree-1°": 18.0}, 100.0, 24.0))
    assert tick(behaviour) == Status.SUCCESS and step.values == {"Width-Degree-1°": 18.0}


def test_apply_test_of_a_value_measured_earlier_is_free(services, driver, log) -> None:  # noqa: ANN001
    record, step = start_object(services)
    record.session.record({"Height": 9.2}, P(6, 0))
    step.test = record.session.decide()
    assert str(step.test.test) == HEIGHT and step.test.cost == 0
    assert run(ApplyTest(ROBOT), services) == Status.SUCCESS
    assert step.values == {} and driver.calls == [] and log.events == []


def test_apply_test_refused_by_the_driver_makes_the_test_unusable(services, driver, log) -> None:  # noqa: ANN001
    record, step = start_object(services)
    step.test = record.session.decide()
    driver.script("sense", refused(NO_TARGET, "no object in front of the sonar"))
    assert run(ApplyTest(ROBOT), services) == Status.FAILURE
    assert record.session.awaiting_reselection and record.session.measurements == {}
    assert step.values is None and record.ledger.sensing_s == 0.0
    assert log.events == [{"event": "driver_error", "object": 0, "behaviour": "ApplyTest", "code": NO_TARGET,
                           "message": "no object in front of the sonar"}]
    assert str(record.session.decide().test) == HEIGHT  # reselected
    assert not record.off_position


def test_apply_test_raises_when_the_driver_is_gone(services, driver) -> None:  # noqa: ANN001
    record, step = start_object(services)
    step.test = record.session.decide()
    driver.script("sense", refused(UNAVAILABLE, "no reply"))
    with pytest.raises(DriverError, match="unavailable: no reply"):
        run(ApplyTest(ROBOT), services)
    assert not record.session.awaiting_reselection


def _grasp_feature(services):  # noqa: ANN001, ANN202
    """Width 8.5, Height 4.8 (unreliable): Front-Wrap tried as a feature from (6,0)."""
    record, step = start_object(services)
    measure(record, 8.5, 4.8)
    test = record.session.decide()
    assert str(test.test) == "Front-Wrap(6,*)"
    step.test, step.attempt = test, GraspAttempt("Front-Wrap", P(6, 0), as_feature=test)
    return record, step


def test_apply_test_of_a_grasp_feature_grasps(services, driver, log) -> None:  # noqa: ANN001
    record, step = _grasp_feature(services)
    driver.script("grasp", GraspResult("Front-Wrap", False, 60.0))
    assert run(ApplyTest(ROBOT), services) == Status.SUCCESS
    assert driver.calls == [("grasp", "Front-Wrap")]
    assert step.attempt.success is False and record.ledger.grasping_s == 60.0 and record.ledger.sensing_s == 0
    assert log.events == [{"event": "grasp", "object": 0, "behaviour": "ApplyTest", "grasp": "Front-Wrap",
                           "as_feature": True, "success": False, "seconds": 60.0}]


def test_apply_test_of_a_refused_grasp_feature_is_a_failed_grasp(services, driver) -> None:  # noqa: ANN001
    record, step = _grasp_feature(services)
    driver.script("grasp", refused(NO_TARGET, "nothing in front of the hand"))
    assert run(ApplyTest(ROBOT), services) == Status.SUCCESS  # FollowBranch fails on it
    assert step.attempt.failed and record.session.decide() == step.test  # not made unusable


# -- Grasp -----------------------------------------------------------------------------------


def _at_grasp(services, grasp: str = "Front-Pinch", at=P(6, 0), success=None):  # noqa: ANN001, ANN202
    record, step = start_object(services)
    measure(record, 18.0)
    record.session.position = at
    step.attempt = GraspAttempt(grasp, at, success=success)
    return record, step


def test_grasp_that_holds_grasps_the_object(services, driver, log) -> None:  # noqa: ANN001
    record, step = _at_grasp(services)
    driver.script("grasp", GraspResult("Front-Pinch", True, 45.0))
    assert run(Grasp(ROBOT), services) == Status.SUCCESS
    assert (record.outcome, record.grasp, record.grasp_position) == ("grasped", "Front-Pinch", P(6, 0))
    assert step.attempt == GraspAttempt("Front-Pinch", P(6, 0), success=True)
    assert record.ledger.grasping_s == 45.0
    assert log.events == [{"event": "grasp", "object": 0, "behaviour": "Grasp", "grasp": "Front-Pinch",
                           "as_feature": False, "success": True, "seconds": 45.0}]


def test_grasp_that_slips_fails(services, driver) -> None:  # noqa: ANN001
    record, step = _at_grasp(services)
    driver.script("grasp", GraspResult("Front-Pinch", False, 45.0))
    assert run(Grasp(ROBOT), services) == Status.FAILURE
    assert step.attempt.failed and record.outcome is None and record.ledger.grasping_s == 45.0


def test_grasp_the_finger_sensor_cannot_confirm_leaves_the_object(services, driver, log) -> None:  # noqa: ANN001
    record, step = start_object(services)
    measure(record, 30.0)  # the closed box: No-Grab, from where the robot stands
    leaf = record.session.decide()
    assert (leaf.grasp, leaf.position) == ("No-Grab", P(24, 0))
    step.attempt = GraspAttempt("No-Grab", P(24, 0))
    assert run(Grasp(ROBOT), services) == Status.SUCCESS
    assert driver.calls == []
    assert (record.outcome, record.grasp, record.grasp_position) == ("left", "No-Grab", P(24, 0))
    assert step.attempt.success is True and record.ledger.grasping_s == 0.0
    assert log.events == [{"event": "leave", "object": 0, "behaviour": "Grasp", "grasp": "No-Grab"}]


@pytest.mark.parametrize("attempt", [None, GraspAttempt("Front-Pinch", P(6, 0), success=False)])
def test_grasp_without_a_live_attempt_fails(services, driver, attempt) -> None:  # noqa: ANN001
    record, step = _at_grasp(services)
    step.attempt = attempt
    assert run(Grasp(ROBOT), services) == Status.FAILURE
    assert driver.calls == [] and record.outcome is None


def test_grasp_refused_by_the_driver_is_a_failed_grasp(services, driver, log) -> None:  # noqa: ANN001
    record, step = _at_grasp(services)
    driver.script("grasp", refused(NO_TARGET, "nothing in front of the hand"))
    assert run(Grasp(ROBOT), services) == Status.FAILURE
    assert step.attempt.failed and log.of("driver_error")[0]["code"] == NO_TARGET


def test_move_to_a_position_the_robot_was_refused_at_drives_there_again(services, driver, nav, log) -> None:  # noqa: ANN001
    record, step = _at_sixty(services, nav)
    record.session.position, record.off_position = P(24, 0), True  # believed there; a refusal said otherwise
    put("pose", DriverPose(126.5, 50.0, 180.0))  # where the camera placed it since: 26.5 in from the object
    there = DriverPose(124.0, 50.0, 180.0)
    driver.script("move", moved(there, 7.5))
    assert run(MoveTo(ROBOT, "test"), services) == Status.SUCCESS
    start, goal = nav.plans[0]
    assert (start.x_in, goal.x_in) == (126.5, 124.0) and driver.verbs() == ["move"]
    assert not record.off_position and record.session.position == P(24, 0) and record.ledger.moving_s == 7.5
    assert record.arrived == there  # a later refusal re-approaches only if a look corrects this


# -- Learn -----------------------------------------------------------------------------------


def _wrapped_after_four_features(services, driver, where: Region = REGION):  # noqa: ANN001, ANN202
    """Width 8.5 at (24,0), Height 3.4, Depth 3.0 and a top hole at (6,0), then Front-Wrap held."""
    record, _ = start_object(services, where=where)
    measure(record, 8.5)
    record.session.record({"Height": 3.4, "Depth": 3.0, "Top-Hole?": 1.0}, P(6, 0))
    record.finish("grasped", "Front-Wrap", P(6, 0))
    driver.script("release", RobotState(DriverPose(106.0, 50.0, 180.0), 500.0, 0.9))
    return record


def test_learn_saves_what_was_measured_and_puts_the_object_away(services, driver, log) -> None:  # noqa: ANN001
    record = _wrapped_after_four_features(services, driver)
    assert run(Learn(ROBOT), services) == Status.SUCCESS
    assert services.learner.learned == [ObjectDescription("learned/Front-Wrap", "Front-Wrap", P(6, 0), (
        Observation("Depth", P(6, 0), 3.0), Observation("Height", P(6, 0), 3.4),
        Observation("Top-Hole?", P(6, 0), 1.0), Observation("Width-Degree-1°", P(24, 0), 8.5)))]
    assert record.learned_id == "learned/Front-Wrap#1" and driver.verbs() == ["release"]
    assert log.events == [{"event": "learn", "object": 0, "behaviour": "Learn", "id": "learned/Front-Wrap#1",
                           "grasp": "Front-Wrap", "features": 4, "wrong": []}]


def test_learn_skips_an_object_left_where_it_is(services, driver, log) -> None:  # noqa: ANN001
    record, step = start_object(services)
    measure(record, 30.0)
    record.finish("left", "No-Grab", P(24, 0))
    assert run(Learn(ROBOT), services) == Status.SUCCESS
    assert services.learner.learned == [] and driver.calls == [] and log.events == []
    assert record.learned_id is None


@pytest.mark.parametrize("outcome", [None, "failed"])
def test_learn_fails_for_an_object_not_grasped(services, driver, outcome) -> None:  # noqa: ANN001
    record, step = start_object(services)
    if outcome:
        record.finish(outcome)
    assert run(Learn(ROBOT), services) == Status.FAILURE
    assert services.learner.learned == [] and driver.calls == []


def test_learn_saves_nothing_from_a_cluster_but_puts_the_object_away(services, driver, log) -> None:  # noqa: ANN001
    # the same measurements as the first test above, on touching objects: none is the held one's alone
    record = _wrapped_after_four_features(services, driver, dataclasses.replace(REGION, cluster=True))
    assert run(Learn(ROBOT), services) == Status.SUCCESS
    assert services.learner.learned == [] and driver.verbs() == ["release"] and record.learned_id is None
    assert log.events == [{"event": "learn", "object": 0, "behaviour": "Learn", "id": None, "grasp": "Front-Wrap",
                           "features": 0, "reason": "a cluster of touching objects"}]


@pytest.mark.parametrize("appearance", [None, Appearance(True, 8.96, 1.0)])
def test_learn_saves_nothing_when_nothing_was_measured_and_nothing_was_wrong(services, driver, log,  # noqa: ANN001
                                                                               appearance) -> None:
    record, step = start_object(services)
    record.session.appearance = appearance  # the camera's appearance alone picked the grasp, and it held
    record.finish("grasped", "Front-Pinch", P(6, 0))
    driver.script("release", RobotState(DriverPose(106.0, 50.0, 180.0), 0.0, 1.0))
    assert run(Learn(ROBOT), services) == Status.SUCCESS
    assert services.learner.learned == [] and driver.verbs() == ["release"] and record.learned_id is None
    assert log.events == [{"event": "learn", "object": 0, "behaviour": "Learn", "id": None, "grasp": "Front-Pinch",
                           "features": 0, "reason": "nothing was measured and no grasp failed: nothing to learn"}]


def test_learn_saves_a_lesson_with_nothing_sensed_by_its_appearance(services, driver, log) -> None:  # noqa: ANN001
    # three grasps tried as features failed cleanly, then Top-Vert-Grip held: nothing was
    # sensed, but the library was wrong three times, and the camera's footprint says
    # which objects the lesson is about
    record, step = start_object(services)
    record.session.appearance = Appearance(True, 8.96, 1.239)
    record.session.wrong_predictions.extend(["Front-Wrap", "Top-Pinch", "Front-Pinch"])
    record.finish("grasped", "Top-Vert-Grip", P(6, 0))
    driver.script("release", RobotState(DriverPose(106.0, 50.0, 180.0), 0.0, 1.0))
    assert run(Learn(ROBOT), services) == Status.SUCCESS
    assert services.learner.learned == [ObjectDescription("learned/Top-Vert-Grip", "Top-Vert-Grip", P(6, 0), (),
                                                          Appearance(True, 8.96, 1.239))]
    assert record.learned_id == "learned/Top-Vert-Grip#1"
    assert log.events == [{"event": "learn", "object": 0, "behaviour": "Learn", "id": "learned/Top-Vert-Grip#1",
                           "grasp": "Top-Vert-Grip", "features": 0, "by": "appearance",
                           "wrong": ["Front-Wrap", "Top-Pinch", "Front-Pinch"]}]


def test_learn_saves_nothing_without_an_appearance_even_after_a_wrong_grasp(services, driver, log) -> None:  # noqa: ANN001
    record, step = start_object(services)  # no camera appearance: a description of nothing would match anything
    record.session.wrong_predictions.append("Front-Wrap")
    record.finish("grasped", "Front-Pinch", P(6, 0))
    driver.script("release", RobotState(DriverPose(106.0, 50.0, 180.0), 0.0, 1.0))
    assert run(Learn(ROBOT), services) == Status.SUCCESS
    assert services.learner.learned == [] and driver.verbs() == ["release"] and record.learned_id is None
    assert log.events == [{"event": "learn", "object": 0, "behaviour": "Learn", "id": None, "grasp": "Front-Pinch",
                           "features": 0, "reason": "nothing was measured and the camera gave no appearance: "
                                                    "it would match every object"}]


def test_fake_driver_refuses_unscripted_calls() -> None:
    with pytest.raises(AssertionError, match="unexpected driver call"):
        FakeDriver().camera()


def test_learn_keeps_the_appearance_the_camera_saw(services, driver) -> None:  # noqa: ANN001
    record, step = start_object(services)
    record.session.appearance = Appearance(False, 13.44, 2.333)
    measure(record, 8.5)
    record.finish("grasped", "Front-Wrap", P(6, 0))
    driver.script("release", RobotState(DriverPose(106.0, 50.0, 180.0), 500.0, 0.9))
    assert run(Learn(ROBOT), services) == Status.SUCCESS
    (learned,) = services.learner.learned
    assert learned.appearance == Appearance(False, 13.44, 2.333)
    assert learned.observations == (Observation("Width-Degree-1°", P(24, 0), 8.5),)
