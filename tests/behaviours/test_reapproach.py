"""A procedure refused as out of range is re-approached (behaviours.reapproach): the
branch ``ApplyTest or re-approach`` (or ``Grasp ...``) ticked alone on the fake driver.

The FakeNavigator's geometry (conftest) puts position (d, o) of the object at
(100, 50) at the world point (100 + d cos o, 50 + d sin o), facing the object: (24,0)
is (124, 50, 180), (6,0) is (106, 50, 180).
"""

from __future__ import annotations

import dataclasses

import pytest
from py_trees.common import Status

from behaviours.actions import ApplyTest, Grasp
from behaviours.reapproach import RefusedForRange, reapproached
from behaviours.records import GraspAttempt, Refusal
from behaviours.services import Params
from hero_driver.interface import NO_TARGET, OUT_OF_RANGE
from hero_driver.interface import Pose as DriverPose  # noqa: I001 (the planner has a Pose too)
from tests.behaviours.conftest import HEIGHT, ROBOT, P, put, refused, run, start_object
from tests.behaviours.test_actions import _at_grasp, _grasp_feature


def test_a_refusal_for_range_is_recorded_on_the_step_and_nothing_counted(services, driver, log) -> None:  # noqa: ANN001
    record, step = start_object(services)
    chosen = step.test = record.session.decide()
    driver.script("sense", refused(OUT_OF_RANGE, "H-Sweep-1°: object at 21.9 in, range is 24-24 in"))
    assert run(ApplyTest(ROBOT), services) == Status.FAILURE  # the action alone: the branch judges
    said = "H-Sweep-1°: object at 21.9 in, range is 24-24 in"
    assert step.refusal == Refusal("H-Sweep-1°", False, said, "ApplyTest")
    assert not record.session.awaiting_reselection and record.session.decide() == chosen
    assert not record.off_position and log.kinds() == ["driver_error"]


def test_any_other_refusal_is_not_one_for_range(services, driver, log) -> None:  # noqa: ANN001
    record, step = start_object(services)
    step.test = record.session.decide()
    driver.script("sense", refused(NO_TARGET, "no object in front of the sonar"))
    assert run(reapproached(ROBOT, ApplyTest(ROBOT)), services) == Status.FAILURE
    assert step.refusal is None and record.session.awaiting_reselection and not record.reapproaches


def test_the_condition_alone_fails_without_a_refusal(services) -> None:  # noqa: ANN001
    start_object(services)
    condition = RefusedForRange(ROBOT)
    assert run(condition, services) == Status.FAILURE and condition.feedback_message == "not refused for range"


def test_apply_test_refused_out_of_range_is_tried_again_after_a_re_approach(services, driver, log) -> None:  # noqa: ANN001
    record, step = start_object(services)
    chosen = step.test = record.session.decide()
    driver.script("sense", refused(OUT_OF_RANGE, "H-Sweep-1°: object at 21.9 in, range is 24-24 in"))
    assert run(reapproached(ROBOT, ApplyTest(ROBOT)), services) == Status.FAILURE
    # nothing was measured and nothing tried: the same test comes back, from a move
    assert not record.session.awaiting_reselection and record.session.decide() == chosen
    assert record.off_position and record.reapproaches == {"H-Sweep-1°": 1}
    assert record.ledger.recoveries["re-approach"] == 1 and record.ledger.sensing_s == 0.0
    assert log.events[1] == {"event": "reapproach", "object": 0, "behaviour": "ApplyTest", "procedure": "H-Sweep-1°",
                             "tries": 1, "message": "H-Sweep-1°: object at 21.9 in, range is 24-24 in"}


@pytest.mark.parametrize(("tries", "before"), [(2, 2), (0, 0)])
def test_apply_test_refused_out_of_range_past_its_tries_is_unusable(services, driver, log, tries, before) -> None:  # noqa: ANN001
    services = dataclasses.replace(services, params=Params(reapproach_tries=tries))
    record, step = start_object(services)
    step.test = record.session.decide()
    record.reapproaches["H-Sweep-1°"] = before
    driver.script("sense", refused(OUT_OF_RANGE, "object at 21.9 in"))
    assert run(reapproached(ROBOT, ApplyTest(ROBOT)), services) == Status.FAILURE
    assert record.session.awaiting_reselection and str(record.session.decide().test) == HEIGHT
    assert not record.off_position and log.kinds() == ["driver_error"]


def test_apply_test_of_a_grasp_feature_refused_out_of_range_is_not_a_failed_grasp(services, driver) -> None:  # noqa: ANN001
    record, step = _grasp_feature(services)
    driver.script("grasp", refused(OUT_OF_RANGE, "Front-Wrap: object at 4.3 in, range is 6-6 in"))
    # the step ends; the recovery sees no failed grasp
    assert run(reapproached(ROBOT, ApplyTest(ROBOT)), services) == Status.FAILURE
    assert step.attempt.success is None and record.session.wrong_predictions == []
    assert record.session.decide() == step.test and record.off_position


def test_grasp_refused_out_of_range_is_tried_again_after_a_re_approach(services, driver, log) -> None:  # noqa: ANN001
    record, step = _at_grasp(services, "Top-Vert-Grip")
    for tries in (1, 2):  # refused twice: re-approached twice, the grasp never counted as failed
        driver.script("grasp", refused(OUT_OF_RANGE, "Top-Vert-Grip: object at 4.5 in, range is 6-6 in"))
        assert run(reapproached(ROBOT, Grasp(ROBOT)), services) == Status.FAILURE
        assert step.attempt == GraspAttempt("Top-Vert-Grip", P(6, 0)) and record.off_position
        assert record.reapproaches["Top-Vert-Grip"] == tries
    driver.script("grasp", refused(OUT_OF_RANGE, "Top-Vert-Grip: object at 4.5 in, range is 6-6 in"))
    assert run(reapproached(ROBOT, Grasp(ROBOT)), services) == Status.FAILURE
    assert step.attempt.failed  # the third refusal of the same grasp counts, as every refusal did before
    assert log.kinds() == ["driver_error", "reapproach"] * 2 + ["driver_error"]


@pytest.mark.parametrize(("seen", "again"), [(DriverPose(105.5, 50.0, 180.0), True),  # the camera moved it
                                              (DriverPose(106.0, 50.0, 180.0), False)])  # nothing moved it
def test_a_grasp_refused_out_of_range_is_re_approached_only_after_a_correction(services, driver, seen,  # noqa: ANN001
                                                                                again) -> None:
    record, step = _at_grasp(services, "Top-Vert-Grip")
    record.arrived = DriverPose(106.0, 50.0, 180.0)  # where the move to (6,0) ended, by dead reckoning
    put("pose", seen)  # where the look before the grasp placed the robot
    driver.script("grasp", refused(OUT_OF_RANGE, "Top-Vert-Grip: object at 4.5 in, range is 6-6 in"))
    assert run(reapproached(ROBOT, Grasp(ROBOT)), services) == Status.FAILURE
    # planned from an uncorrected pose, the same move would end where the robot stands
    assert record.off_position is again and step.attempt.failed is not again


