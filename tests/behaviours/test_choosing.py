"""Following the run-time tree: BestTest, FollowBranch, ChooseGrasp (behaviours.choosing).

The four-object library (conftest.four_objects) from (60,0): the best test is
Width-Degree-1°(24,0), 1.5 bits for 72 s of moving and 100 s of sensing; a width of
8.5 leaves the cup and the tumbler, 18 the box alone (a Front-Pinch leaf at (6,0),
36 s away from (24,0)), 30 the closed box (a No-Grab leaf).
"""

from __future__ import annotations

import math

import pytest
from py_trees.common import Status

from behaviours.choosing import BestTest, ChooseGrasp, FollowBranch
from behaviours.records import GraspAttempt
from learner.choosing.node import ScoredTest
from learner.runtime import Matched, Unreliable
from planner import MoveCost
from tests.behaviours.conftest import HEIGHT, REGION, ROBOT, WIDTH, P, measure, put, run, start_object


# -- BestTest --------------------------------------------------------------------------------


def test_best_test_chooses_the_highest_scoring_test(services, log) -> None:  # noqa: ANN001
    record, step = start_object(services)
    assert run(BestTest(ROBOT), services) == Status.SUCCESS
    assert step.test is not None and str(step.test.test) == WIDTH and step.test.target == P(24, 0)
    assert step.attempt is None  # a sensing test is no grasp attempt
    assert log.events == [{"event": "choose", "object": 0, "behaviour": "BestTest", "how": "best", "test": WIDTH,
                           "at": [24, 0], "gain": 1.5, "move_s": 72.0, "sense_s": 100.0}]
    assert record.ledger.computing_s == 0.25  # one timed decision on the quarter-second clock
    assert not record.ledger.recoveries


def test_best_test_fails_when_the_session_awaits_reselection(services, log) -> None:  # noqa: ANN001
    record, step = start_object(services)
    record.session.unusable(record.session.decide())  # e.g. no path to its position
    assert record.session.awaiting_reselection
    assert run(BestTest(ROBOT), services) == Status.FAILURE
    assert step.test is None and log.events == []
    assert record.ledger.computing_s == 0.0  # not even asked


def test_best_test_fails_at_a_leaf(services, log) -> None:  # noqa: ANN001
    record, step = start_object(services)
    measure(record, 18.0)  # the box alone: a grasp leaf, no test
    assert run(BestTest(ROBOT), services) == Status.FAILURE
    assert step.test is None and log.events == []


# -- FollowBranch ----------------------------------------------------------------------------


def test_follow_branch_follows_the_matching_branch(services, log) -> None:  # noqa: ANN001
    record, step = start_object(services)
    step.test = record.session.decide()
    step.values = {"Width-Degree-1°": 8.5}
    assert run(FollowBranch(ROBOT), services) == Status.SUCCESS
    assert record.session.candidates == ("cup", "tumbler") and record.session.depth == 1
    assert record.session.position == P(24, 0)
    assert record.session.measurements == {("Width-Degree-1°", P(24, 0)): 8.5}
    assert record.ledger.tests == [f"{WIDTH}=8.5"]
    assert log.events == [{"event": "branch", "object": 0, "behaviour": "FollowBranch", "test": WIDTH,
                           "value": 8.5, "range": [8.0, 9.0]}]


def test_follow_branch_fails_on_a_value_between_the_branches(services, log) -> None:  # noqa: ANN001
    record, step = start_object(services)
    step.test = record.session.decide()
    step.values = {"Width-Degree-1°": 13.5}  # [8,9] widens to [5,12], [18,18] to [15,21]
    assert run(FollowBranch(ROBOT), services) == Status.FAILURE
    assert record.session.depth == 0 and record.session.awaiting_reselection
    assert record.session.unreliable_count == 1 and record.session.can_follow_nearest
    assert record.ledger.tests == [f"{WIDTH}=13.5"]
    assert log.events == [{"event": "unreliable", "object": 0, "behaviour": "FollowBranch", "test": WIDTH,
                           "value": 13.5, "ranges": [[8.0, 9.0], [18.0, 18.0], [30.0, 30.0]]}]


def test_follow_branch_fails_on_a_dropout(services, log) -> None:  # noqa: ANN001
    record, step = start_object(services)
    step.test = record.session.decide()
    step.values = {"Width-Degree-1°": None}
    assert run(FollowBranch(ROBOT), services) == Status.FAILURE
    assert record.session.awaiting_reselection and not record.session.can_follow_nearest
    assert record.ledger.tests == [f"{WIDTH}=-"]
    assert log.events[0]["event"] == "unreliable" and log.events[0]["value"] is None


def test_follow_branch_on_a_successful_grasp_feature_grasps_the_object(services, log) -> None:  # noqa: ANN001
    record, step = start_object(services)
    measure(record, 8.5, 4.8)
    test = record.session.decide()
    step.test, step.attempt = test, GraspAttempt("Front-Wrap", P(6, 0), as_feature=test, success=True)
    assert run(FollowBranch(ROBOT), services) == Status.SUCCESS
    assert (record.outcome, record.grasp, record.grasp_position) == ("grasped", "Front-Wrap", P(6, 0))
    assert record.ledger.tests == ["Front-Wrap(6,*)=1"]
    assert log.events == []


@pytest.mark.parametrize(("success", "tests"), [(False, ["Front-Wrap(6,*)=0"]), (None, [])])
def test_follow_branch_fails_on_a_grasp_feature_that_did_not_hold(services, log,  # noqa: ANN001
                                                                   success, tests) -> None:  # noqa: ANN001
    # A grasp tried as a feature that did not hold is a test applied (value 0, the demo
    # table's `tests` column counts it); one never executed (success None) is not.
    record, step = start_object(services)
    measure(record, 8.5, 4.8)
    test = record.session.decide()
    step.test, step.attempt = test, GraspAttempt("Front-Wrap", P(6, 0), as_feature=test, success=success)
    assert run(FollowBranch(ROBOT), services) == Status.FAILURE
    assert record.outcome is None and record.session.depth == 1 and record.ledger.tests == tests and log.events == []


def test_follow_branch_without_a_test_fails(services) -> None:  # noqa: ANN001
    start_object(services)
    assert run(FollowBranch(ROBOT), services) == Status.FAILURE


def test_a_free_test_is_not_counted_again(services) -> None:  # noqa: ANN001
    """A value measured earlier serves again at no cost: the ledger lists robot tests."""
    record, step = start_object(services)
    record.session.record({"Height": 9.2}, P(6, 0))
    test = record.session.decide()
    assert isinstance(test, ScoredTest) and str(test.test) == HEIGHT and test.cost == 0
    step.test, step.values = test, {}
    assert run(FollowBranch(ROBOT), services) == Status.SUCCESS
    assert record.session.candidates == ("box",) and record.ledger.tests == []


# -- ChooseGrasp -----------------------------------------------------------------------------


def test_choose_grasp_takes_the_leafs_grasp(services, log) -> None:  # noqa: ANN001
    record, step = start_object(services)
    assert measure(record, 18.0) == [Matched(1, (18.0, 18.0), 18.0)]
    assert run(ChooseGrasp(ROBOT), services) == Status.SUCCESS
    assert step.attempt == GraspAttempt("Front-Pinch", P(6, 0)) and step.test is None
    assert log.events == [{"event": "choose_grasp", "object": 0, "behaviour": "ChooseGrasp", "how": "leaf",
                           "grasp": "Front-Pinch", "at": [6, 0], "move_s": 36.0, "candidates": ["box"]}]


def test_choose_grasp_takes_the_other_end_when_only_it_has_a_path(services, log, monkeypatch) -> None:  # noqa: ANN001
    # (6,0) in an obstacle: its half-turn twin (6,180) is as good a grasp (vision knows the
    # reference direction up to a half turn) and 30 in from (24,0): 60 s at 2 s/in
    navigator = services.navigator
    blocked = navigator.pose_for(REGION, 6.0, 0.0)
    priced = navigator.move_cost

    def move_cost(start, goal, *, exact=False):  # noqa: ANN001, ANN202
        if (goal.x_in, goal.y_in) == (blocked.x_in, blocked.y_in):
            return MoveCost(math.inf, math.inf, 0.0, exact, "goal in an obstacle")
        return priced(start, goal, exact=exact)

    monkeypatch.setattr(navigator, "move_cost", move_cost)
    record, step = start_object(services)
    measure(record, 18.0)
    assert run(ChooseGrasp(ROBOT), services) == Status.SUCCESS
    assert step.attempt == GraspAttempt("Front-Pinch", P(6, 180))
    assert log.events[-1]["at"] == [6, 180] and log.events[-1]["move_s"] == 60.0


def test_choose_grasp_fails_where_a_test_is_due(services, log) -> None:  # noqa: ANN001
    start_object(services)
    assert run(ChooseGrasp(ROBOT), services) == Status.FAILURE
    assert log.events == []


def test_choose_grasp_fails_where_a_test_is_reselected(services) -> None:  # noqa: ANN001
    record, step = start_object(services)
    assert measure(record, 13.5) == [Unreliable(13.5)]
    assert run(ChooseGrasp(ROBOT), services) == Status.FAILURE
    assert step.attempt is None


# -- set-up ----------------------------------------------------------------------------------


def test_a_behaviour_ticked_without_setup_raises_a_clear_error(services) -> None:  # noqa: ANN001
    start_object(services)
    with pytest.raises(RuntimeError, match=r"BestTest: ticked before setup\(services=\.\.\.\)"):
        BestTest(ROBOT).tick_once()


def test_setup_without_services_raises_a_clear_error() -> None:
    with pytest.raises(RuntimeError, match=r"ChooseGrasp: setup\(\) needs services=Services"):
        ChooseGrasp(ROBOT).setup()
    with pytest.raises(RuntimeError, match="needs services"):
        ChooseGrasp(ROBOT).setup(services=object())


def test_two_robots_never_share_a_step(services) -> None:  # noqa: ANN001
    ours, ours_step = start_object(services, robot="r1")
    theirs, theirs_step = start_object(services, robot="r2")
    put("pose", None, "r2")
    assert run(BestTest("r2"), services) == Status.SUCCESS
    assert theirs_step.test is not None and ours_step.test is None
