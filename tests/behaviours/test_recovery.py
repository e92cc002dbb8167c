"""Every recovery and its gate (behaviours.recovery), ticked alone.

Scenarios on the four-object library (conftest.four_objects), from (60,0):

- width 13.5 at the root is unreliable ([8,9] widens to [5,12], [18,18] to [15,21]);
  the next-best is Height(6,*) from (24,0): 36 s of moving + 84 s;
- width 14 is unreliable too, and nearest the box's [18,18] (4 away, vs 5 from 9);
- width 8.5 leaves cup and tumbler; a height of 4.8 there is unreliable ([3.5] and [6]
  widen to [3,4] and [5.5,6.5]); the next-best is Front-Wrap tried as a feature from
  (6,0): 0 s + 60 s + 30 s of side-effect penalty;
- width 18 leaves the box: a Front-Pinch leaf at (6,0).
"""

from __future__ import annotations

import pytest
from py_trees.common import Status
from py_trees.composites import Selector, Sequence

from behaviours.actions import MoveTo
from behaviours.records import GraspAttempt
from behaviours.recovery import (AmbiguousGrasp, Backtrack, CheckSideEffects, Discriminate, DropFailedGrasp,
                                 GraspFailed, NearestNeighbour, OtherEnd, Reselect, StartOver, ValueUnreliable)
from behaviours.services import Params
from hero_driver.interface import (INTERNAL, NO_TARGET, UNAVAILABLE, DriverError, Pose as DriverPose,
                                   SenseResult)
from learner.choosing.matrix import DescriptionMatrix
from learner.runtime import Exhausted, Unreliable
from tests.behaviours.conftest import (HEIGHT, PENDING, REGION, ROBOT, P, desc, hero, image, make_services,
                                       measure, moved, pose_at, put, refused, region, run, setup, start_object, tick)


# -- Unreliable? -----------------------------------------------------------------------------


def test_unreliable_fails_at_a_fresh_node(services) -> None:  # noqa: ANN001
    start_object(services)
    assert run(ValueUnreliable(ROBOT), services) == Status.FAILURE


def test_unreliable_succeeds_after_an_untrusted_value(services) -> None:  # noqa: ANN001
    record, _ = start_object(services)
    assert measure(record, 13.5) == [Unreliable(13.5)]
    assert run(ValueUnreliable(ROBOT), services) == Status.SUCCESS


def test_unreliable_succeeds_after_an_unusable_test(services) -> None:  # noqa: ANN001
    record, _ = start_object(services)
    record.session.unusable(record.session.decide())
    assert run(ValueUnreliable(ROBOT), services) == Status.SUCCESS


def test_unreliable_fails_when_nearest_neighbour_is_due() -> None:
    services = make_services(params=Params(nearest_after=1))
    record, _ = start_object(services)
    measure(record, 13.5)
    assert run(ValueUnreliable(ROBOT), services) == Status.FAILURE


def test_unreliable_still_reselects_after_a_dropout_when_nearest_is_due() -> None:
    """A dropout leaves no value to be near to: nearest neighbour cannot act, so it is not due."""
    services = make_services(params=Params(nearest_after=1))
    record, _ = start_object(services)
    assert measure(record, None) == [Unreliable(None)]
    assert run(ValueUnreliable(ROBOT), services) == Status.SUCCESS


@pytest.mark.parametrize(("params", "expected"), [(Params(), Status.SUCCESS),
                                                  (Params(nearest_after=1), Status.FAILURE)])
def test_unreliable_gates_reselect(params, expected) -> None:  # noqa: ANN001
    services = make_services(params=params)
    record, step = start_object(services)
    measure(record, 13.5)
    gate, reselect = ValueUnreliable(ROBOT), Reselect(ROBOT)
    assert run(Sequence("reselect", memory=True, children=[gate, reselect]), services) == expected
    if expected == Status.SUCCESS:
        assert str(step.test.test) == HEIGHT and record.ledger.recoveries == {"reselect": 1}
    else:
        assert reselect.status == Status.INVALID  # never ticked
        assert step.test is None and not record.ledger.recoveries and services.log.events == []


# -- Reselect --------------------------------------------------------------------------------


def test_reselect_chooses_the_next_best_test(services, log) -> None:  # noqa: ANN001
    record, step = start_object(services)
    measure(record, 13.5)
    assert run(Reselect(ROBOT), services) == Status.SUCCESS
    assert str(step.test.test) == HEIGHT and step.test.target == P(6, 0)
    assert record.ledger.recoveries == {"reselect": 1}
    assert log.events == [{"event": "choose", "object": 0, "behaviour": "Reselect", "how": "reselect",
                           "test": HEIGHT, "at": [6, 0], "gain": pytest.approx(1.3232, abs=1e-4),
                           "move_s": 36.0, "sense_s": 84.0}]


def test_reselect_of_a_grasp_makes_it_the_steps_attempt(services, log) -> None:  # noqa: ANN001
    record, step = start_object(services)
    measure(record, 8.5, 4.8)
    assert run(Reselect(ROBOT), services) == Status.SUCCESS
    assert str(step.test.test) == "Front-Wrap(6,*)"
    assert step.attempt == GraspAttempt("Front-Wrap", P(6, 0), as_feature=step.test)
    assert (log.events[0]["move_s"], log.events[0]["sense_s"], log.events[0]["gain"]) == (0.0, 90.0, 1.0)


def test_reselect_fails_when_n_alternatives_were_tried() -> None:
    services = make_services(params=Params(max_alternatives=1))
    record, step = start_object(services)
    measure(record, 13.5)
    assert record.session.decide() == Exhausted(1)
    assert run(Reselect(ROBOT), services) == Status.FAILURE
    assert step.test is None and not record.ledger.recoveries


# -- Backtrack -------------------------------------------------------------------------------


def test_backtrack_fails_while_a_test_is_left_here(services, log) -> None:  # noqa: ANN001
    record, step = start_object(services)
    assert run(Backtrack(ROBOT), services) == Status.FAILURE
    assert not step.no_alternative and log.events == [] and record.session.depth == 0


def test_backtrack_chooses_a_different_test_at_the_parent() -> None:
    """N = 2: at the cup/tumbler node the height (4.8) and Front-Wrap (unusable) were
    tried; backtracking invalidates the root's width and takes the height measured at
    (6,0), free (gain 1.3232, 0 s)."""
    services = make_services(params=Params(max_alternatives=2))
    record, step = start_object(services)
    measure(record, 8.5, 4.8)
    record.session.unusable(record.session.decide())
    assert record.session.decide() == Exhausted(2)
    assert run(Backtrack(ROBOT), services) == Status.SUCCESS
    session = record.session
    assert session.depth == 0 and ("Width-Degree-1°", P(24, 0)) not in session.measurements
    assert str(step.test.test) == HEIGHT and step.test.cost == 0 and not step.no_alternative
    assert record.ledger.recoveries == {"backtrack": 1}
    assert [(e["event"], e.get("depth"), e.get("how")) for e in services.log.events] == [
        ("backtrack", 0, None), ("choose", None, "backtrack")]


def test_backtrack_up_to_the_root_sets_no_alternative() -> None:
    """N = 1: the height at depth 1 exhausts it; the root's one alternative is used up too."""
    services = make_services(params=Params(max_alternatives=1))
    record, step = start_object(services)
    measure(record, 8.5, 4.8)
    assert run(Backtrack(ROBOT), services) == Status.FAILURE
    assert step.no_alternative and step.test is None and record.session.depth == 0
    assert record.ledger.recoveries == {"backtrack": 1}
    assert services.log.kinds() == ["backtrack"]


def test_backtrack_at_the_root_has_nothing_to_undo() -> None:
    services = make_services(params=Params(max_alternatives=1))
    record, step = start_object(services)
    measure(record, 14.0)
    assert run(Backtrack(ROBOT), services) == Status.FAILURE
    assert step.no_alternative and not record.ledger.recoveries and services.log.events == []


def test_backtrack_gives_way_when_nearest_neighbour_is_due() -> None:
    services = make_services(params=Params(max_alternatives=1, nearest_after=1))
    record, step = start_object(services)
    measure(record, 8.5, 4.8)
    assert run(Backtrack(ROBOT), services) == Status.FAILURE
    assert not step.no_alternative and record.session.depth == 1 and services.log.events == []


# -- NearestNeighbour ------------------------------------------------------------------------


def test_nearest_neighbour_waits_for_the_last_resort(services, log) -> None:  # noqa: ANN001
    record, step = start_object(services)
    measure(record, 14.0)
    assert run(NearestNeighbour(ROBOT), services) == Status.FAILURE
    assert record.session.depth == 0 and log.events == []


def test_nearest_neighbour_follows_the_nearest_branch_when_nothing_else_is_left(services, log) -> None:  # noqa: ANN001
    record, step = start_object(services)
    measure(record, 14.0)
    step.no_alternative = True  # as Backtrack leaves it
    assert run(NearestNeighbour(ROBOT), services) == Status.SUCCESS
    assert record.session.candidates == ("box",) and record.session.depth == 1
    assert record.ledger.recoveries == {"nearest neighbour": 1}
    assert log.events == [{"event": "nearest", "object": 0, "behaviour": "NearestNeighbour",
                           "branch": [18.0, 18.0], "value": 14.0}]


def test_nearest_neighbour_when_due() -> None:
    services = make_services(params=Params(nearest_after=1))
    record, step = start_object(services)
    measure(record, 14.0)
    assert run(NearestNeighbour(ROBOT), services) == Status.SUCCESS
    assert record.session.candidates == ("box",)


def test_nearest_neighbour_has_nothing_to_be_near_to_after_a_dropout(services) -> None:  # noqa: ANN001
    record, step = start_object(services)
    measure(record, None)
    step.no_alternative = True
    assert run(NearestNeighbour(ROBOT), services) == Status.FAILURE
    assert not record.ledger.recoveries


def test_nearest_neighbour_stays_out_of_a_failed_grasp(services) -> None:  # noqa: ANN001
    record, step = start_object(services)
    measure(record, 14.0)
    step.no_alternative = True
    step.attempt = GraspAttempt("Front-Pinch", P(6, 0), success=False)
    assert run(NearestNeighbour(ROBOT), services) == Status.FAILURE
    assert record.session.depth == 0


# -- AmbiguousLeaf ---------------------------------------------------------------------------


def test_ambiguous_leaf_tries_the_cheapest_grasp(services, log) -> None:  # noqa: ANN001
    """Mug and jar differ by less than the width's error, and (grasps not offered as
    features) nothing splits them: an ambiguous leaf. From (60,0) Front-Wrap costs
    108 + 60 + 30 s as a feature, Top-Pinch 108 + 63 + 40 s."""
    library = [desc("mug", "Front-Wrap", ("Width-Degree-1°", P(24, 0), 8)),
               desc("jar", "Top-Pinch", ("Width-Degree-1°", P(24, 0), 8.5))]
    record, step = start_object(services, matrix=DescriptionMatrix(library, hero(), grasps_as_features=False))
    assert run(AmbiguousGrasp(ROBOT), services) == Status.SUCCESS
    assert step.attempt == GraspAttempt("Front-Wrap", P(6, 0))
    assert record.ledger.recoveries == {"ambiguous leaf": 1}
    assert log.events == [{"event": "choose_grasp", "object": 0, "behaviour": "AmbiguousLeaf", "how": "ambiguous",
                           "grasp": "Front-Wrap", "at": [6, 0], "move_s": 108.0, "candidates": ["jar", "mug"]}]


def test_ambiguous_leaf_after_a_classification_failure() -> None:
    """N = 1 and the width unusable (no value, so no nearest neighbour): every grasp of the
    root is offered; Front-Pinch is cheapest (108 + 45 + 30 s), No-Grab last."""
    services = make_services(params=Params(max_alternatives=1))
    record, step = start_object(services)
    record.session.unusable(record.session.decide())
    step.no_alternative = True
    assert run(AmbiguousGrasp(ROBOT), services) == Status.SUCCESS
    assert step.attempt == GraspAttempt("Front-Pinch", P(6, 0))
    assert services.log.events[0]["candidates"] == ["box", "closed", "cup", "tumbler"]


def test_ambiguous_leaf_fails_where_a_test_is_left(services, log) -> None:  # noqa: ANN001
    record, step = start_object(services)
    assert run(AmbiguousGrasp(ROBOT), services) == Status.FAILURE
    assert step.attempt is None and log.events == [] and not record.ledger.recoveries


def test_ambiguous_leaf_waits_for_backtracking_to_give_up() -> None:
    services = make_services(params=Params(max_alternatives=1))
    record, step = start_object(services)
    record.session.unusable(record.session.decide())  # exhausted, but no_alternative not yet set
    assert run(AmbiguousGrasp(ROBOT), services) == Status.FAILURE


# -- GraspFailed? ----------------------------------------------------------------------------


@pytest.mark.parametrize(("attempt", "expected"), [
    (None, Status.FAILURE),
    (GraspAttempt("Front-Pinch", P(6, 0)), Status.FAILURE),
    (GraspAttempt("Front-Pinch", P(6, 0), success=True), Status.FAILURE),
    (GraspAttempt("Front-Pinch", P(6, 0), success=False), Status.SUCCESS),
])
def test_grasp_failed_is_true_only_for_a_failed_attempt(services, attempt, expected) -> None:  # noqa: ANN001
    _, step = start_object(services)
    step.attempt = attempt
    assert run(GraspFailed(ROBOT), services) == expected


# -- OtherEnd --------------------------------------------------------------------------------


def _unreachable_grasp(services, nav, at=P(6, 0)):  # noqa: ANN001, ANN202
    record, step = start_object(services)
    measure(record, 18.0)  # the box, robot at (24,0)
    put("pose", pose_at(nav, P(24, 0)))
    step.attempt = GraspAttempt("Front-Pinch", at)
    nav.block(REGION, at)
    return record, step


def test_other_end_reaches_a_blocked_grasp_from_the_other_side(services, driver, nav, log) -> None:  # noqa: ANN001
    record, step = _unreachable_grasp(services, nav)
    far_side = DriverPose(94.0, 50.0, 0.0)  # (6,180): 6 in on the other side, facing +x
    driver.script("move", moved(far_side, 50.0))
    reach = Selector("reach the grasp", memory=True, children=[MoveTo(ROBOT, "grasp"), OtherEnd(ROBOT)])
    assert run(reach, services) == Status.SUCCESS
    assert [(g.x_in, g.y_in) for _, g in nav.plans] == [(106.0, 50.0), (94.0, 50.0)]
    assert driver.calls == [("move", (far_side,), (100.0, 50.0))]
    assert step.attempt == GraspAttempt("Front-Pinch", P(6, 180))
    assert record.session.position == P(6, 180) and record.ledger.moving_s == 50.0
    assert log.kinds() == ["no_path", "other_end", "move"]
    assert log.events[1] == {"event": "other_end", "object": 0, "behaviour": "OtherEnd", "to": [6, 180],
                             "instead_of": [6, 0]}
    assert log.events[2]["to"] == [6, 180] and log.events[2]["behaviour"] == "OtherEnd"


def test_other_end_wraps_the_orientation(services, driver, nav, log) -> None:  # noqa: ANN001
    record, step = _unreachable_grasp(services, nav, at=P(6, 270))
    driver.script("move", moved(DriverPose(100.0, 56.0, 270.0), 50.0))
    assert run(OtherEnd(ROBOT), services) == Status.SUCCESS
    assert step.attempt.position == P(6, 90) and record.session.position == P(6, 90)
    assert log.events[0]["to"] == [6, 90] and log.events[0]["instead_of"] == [6, 270]


def test_other_end_with_no_path_either_fails_the_grasp(services, driver, nav, log) -> None:  # noqa: ANN001
    record, step = _unreachable_grasp(services, nav)
    nav.block(REGION, P(6, 180), "start and goal not connected")
    assert run(OtherEnd(ROBOT), services) == Status.FAILURE
    assert step.attempt == GraspAttempt("Front-Pinch", P(6, 0), success=False)
    assert driver.calls == [] and record.session.position == P(24, 0)
    assert log.events == [{"event": "no_path", "object": 0, "behaviour": "OtherEnd", "to": [6, 180],
                           "reason": "start and goal not connected"}]


def test_other_end_leaves_a_failed_grasp_alone(services, driver, nav) -> None:  # noqa: ANN001
    record, step = _unreachable_grasp(services, nav)
    step.attempt = GraspAttempt("Front-Pinch", P(6, 0), success=False)
    assert run(OtherEnd(ROBOT), services) == Status.FAILURE
    assert nav.plans == [] and driver.calls == []


def test_other_end_move_refused_fails_the_grasp(services, driver, nav) -> None:  # noqa: ANN001
    record, step = _unreachable_grasp(services, nav)
    driver.script("move", refused(INTERNAL, "motor fault"))
    assert run(OtherEnd(ROBOT), services) == Status.FAILURE
    assert step.attempt.failed and step.attempt.position == P(6, 180)


# -- SideEffects? ----------------------------------------------------------------------------


def _after_failed_grasp(services, driver, nav, *seen):  # noqa: ANN001, ANN202
    record, step = start_object(services)  # the object at (100, 50), 200 pixels
    measure(record, 18.0)
    step.attempt = GraspAttempt("Front-Pinch", P(6, 0), success=False)
    driver.script("camera", image())
    nav.see(*seen)
    return record, step


def test_side_effects_pushed(services, driver, nav, log) -> None:  # noqa: ANN001
    pushed = region(103, 54, pixels=210)  # 5 in away, 5 % more pixels
    record, step = _after_failed_grasp(services, driver, nav, region(30, 40), pushed)
    assert run(CheckSideEffects(ROBOT), services) == Status.SUCCESS
    assert step.side_effect == "pushed"
    assert record.region == pushed and record.pixels_before == 210 and record.first_region == REGION
    assert record.estimator.region == pushed and record.session.orientation_free is False
    assert log.events == [{"event": "side_effect", "object": 0, "behaviour": "SideEffects?", "effect": "pushed",
                           "shift_in": 5.0, "pixels": 210}]


def test_side_effects_pushed_onto_a_round_footprint(services, driver, nav) -> None:  # noqa: ANN001
    record, step = _after_failed_grasp(services, driver, nav, region(103, 54, pixels=190, round_=True))
    assert run(CheckSideEffects(ROBOT), services) == Status.SUCCESS
    assert step.side_effect == "pushed" and record.session.orientation_free is True


def test_side_effects_changed(services, driver, nav, log) -> None:  # noqa: ANN001
    fallen = region(100, 50, pixels=120)  # in place, 40 % fewer pixels: knocked over
    record, step = _after_failed_grasp(services, driver, nav, fallen)
    assert run(CheckSideEffects(ROBOT), services) == Status.SUCCESS
    assert step.side_effect == "changed" and record.region == fallen and record.pixels_before == 120
    assert log.events[0] == {"event": "side_effect", "object": 0, "behaviour": "SideEffects?", "effect": "changed",
                             "shift_in": 0.0, "pixels": 120}


def test_side_effects_none(services, driver, nav, log) -> None:  # noqa: ANN001
    still = region(100.5, 50, pixels=230)  # half an inch, 15 %: within both thresholds
    record, step = _after_failed_grasp(services, driver, nav, still)
    assert run(CheckSideEffects(ROBOT), services) == Status.FAILURE
    assert step.side_effect is None and record.region == REGION and record.pixels_before == 200
    assert record.estimator.region == REGION
    assert log.events[0] == {"event": "side_effect", "object": 0, "behaviour": "SideEffects?", "effect": "none",
                             "shift_in": 0.5, "pixels": 230}


def test_side_effects_region_lost(services, driver, nav, log) -> None:  # noqa: ANN001
    record, step = _after_failed_grasp(services, driver, nav, region(120, 50))  # 20 in away: not it
    assert run(CheckSideEffects(ROBOT), services) == Status.SUCCESS
    assert step.side_effect == "changed" and record.region == REGION
    assert log.events == [{"event": "side_effect", "object": 0, "behaviour": "SideEffects?", "effect": "changed",
                           "reason": "region lost"}]


def test_side_effects_runs_while_the_camera_works(services, driver, nav) -> None:  # noqa: ANN001
    record, step = start_object(services)
    driver.script("camera", PENDING)
    behaviour = setup(CheckSideEffects(ROBOT), services)
    assert tick(behaviour, max_ticks=2) == Status.RUNNING and nav.observed == 0


# -- StartOver -------------------------------------------------------------------------------


def _with_side_effect(services, nav, effect: str):  # noqa: ANN001, ANN202
    record, step = start_object(services)
    measure(record, 18.0)  # width measured at (24,0), the box predicted
    record.session.position = P(6, 0)
    put("pose", pose_at(nav, P(6, 0)))  # (106, 50) facing the object
    step.attempt = GraspAttempt("Front-Pinch", P(6, 0), success=False)
    step.side_effect = effect
    return record, step


def test_start_over_pushed_keeps_what_was_measured(services, nav, log) -> None:  # noqa: ANN001
    record, step = _with_side_effect(services, nav, "pushed")
    assert run(StartOver(ROBOT), services) == Status.SUCCESS
    session = record.session
    assert session.depth == 0 and session.position == P(6, 0)
    assert session.measurements == {("Width-Degree-1°", P(24, 0)): 18.0}
    assert session.pushes == {"Front-Pinch": 1} and session.dropped_grasps == set()
    assert session.wrong_predictions == []  # a push says nothing about the prediction
    assert record.ledger.recoveries == {"start over (pushed)": 1}
    assert log.events == [{"event": "start_over", "object": 0, "behaviour": "StartOver", "changed": False,
                           "at": [6, 0]}]


def test_start_over_changed_voids_everything_sensed(services, nav, log) -> None:  # noqa: ANN001
    record, step = _with_side_effect(services, nav, "changed")
    record.session.grasp_failed("Top-Pinch", side_effects=False)  # dropped earlier: restored now
    record.session.unreliable_count = 2  # two values distrusted on the object as it was
    assert run(StartOver(ROBOT), services) == Status.SUCCESS
    session = record.session
    assert session.measurements == {} and session.dropped_grasps == set() and session.unreliable_count == 0
    assert record.ledger.recoveries == {"start over (changed)": 1}
    assert log.events[0]["changed"] is True
    # everything to measure again: from (6,0) the height is best (1.3232^2 / 84 s beats
    # the width's 1.5^2 / (36 + 100) s), and it is no longer free
    again = session.decide()
    assert str(again.test) == HEIGHT and again.cost == 84.0


def test_side_effects_then_start_over_from_where_the_object_now_lies(services, driver, nav, log) -> None:  # noqa: ANN001
    """Pushed from (100,50) to (103,54): the robot at (106,50) is now 5 in away at 306.9°
    (atan2(-4, 3))."""
    record, step = _with_side_effect(services, nav, None)
    driver.script("camera", image())
    nav.see(region(103, 54, pixels=200))
    side_effects = Sequence("side effects", memory=True, children=[CheckSideEffects(ROBOT), StartOver(ROBOT)])
    assert run(side_effects, services) == Status.SUCCESS
    assert record.session.position == P(5.0, 306.9)
    assert log.events[-1]["at"] == [5, 306.9]


# -- DropFailedGrasp -------------------------------------------------------------------------


def test_drop_failed_grasp_tried_as_a_feature_follows_its_failure_branch(services, log) -> None:  # noqa: ANN001
    record, step = start_object(services)
    measure(record, 8.5, 4.8)
    test = record.session.decide()
    step.test, step.attempt = test, GraspAttempt("Front-Wrap", P(6, 0), as_feature=test, success=False)
    assert run(DropFailedGrasp(ROBOT), services) == Status.SUCCESS
    session = record.session
    assert session.candidates == ("tumbler",) and session.depth == 2
    assert session.wrong_predictions == ["Front-Wrap"] and session.dropped_grasps == {"Front-Wrap"}
    assert record.ledger.recoveries == {"grasp feature failed": 1} and record.outcome is None
    assert log.events == [{"event": "grasp_feature_failed", "object": 0, "behaviour": "DropFailedGrasp",
                           "grasp": "Front-Wrap"}]
    assert session.decide().grasp == "Top-Pinch"


def test_drop_failed_grasp_at_a_leaf_drops_its_descriptions(services, log) -> None:  # noqa: ANN001
    record, step = start_object(services)
    measure(record, 18.0)
    record.session.position = P(6, 0)
    step.attempt = GraspAttempt("Front-Pinch", P(6, 0), success=False)
    assert run(DropFailedGrasp(ROBOT), services) == Status.SUCCESS
    session = record.session
    assert session.candidates == ("closed", "cup", "tumbler") and session.depth == 0
    assert session.measurements == {("Width-Degree-1°", P(24, 0)): 18.0}  # kept
    assert session.wrong_predictions == ["Front-Pinch"] and session.dropped_grasps == {"Front-Pinch"}
    assert record.ledger.recoveries == {"drop failed grasp": 1} and record.ledger.computing_s == 0.25
    assert log.events == [{"event": "drop_grasp", "object": 0, "behaviour": "DropFailedGrasp",
                           "grasp": "Front-Pinch", "candidates": ["closed", "cup", "tumbler"]}]


def test_drop_failed_grasp_gives_up_when_every_grasp_failed(services, log) -> None:  # noqa: ANN001
    record, step = start_object(services)
    for grasp in ("Front-Wrap", "Top-Pinch", "No-Grab"):
        record.session.grasp_failed(grasp, side_effects=False)
    assert record.session.candidates == ("box",)
    step.attempt = GraspAttempt("Front-Pinch", P(6, 0), success=False)
    assert run(DropFailedGrasp(ROBOT), services) == Status.SUCCESS
    assert record.outcome == "failed" and record.grasp is None and not record.ledger.recoveries
    assert log.events == [{"event": "gave_up", "object": 0, "behaviour": "DropFailedGrasp",
                           "reason": "every grasp in the library failed"}]


# -- Discriminate ----------------------------------------------------------------------------


def _wrongly_predicted(services, grasp: str = "Front-Pinch", width: float = 18.0, at=P(6, 0)):  # noqa: ANN001, ANN202
    """A clean failure of ``grasp`` (dropped already), the robot at ``at``."""
    record, step = start_object(services)
    measure(record, width)
    record.session.position = at
    record.session.grasp_failed(grasp, side_effects=False)
    step.attempt = GraspAttempt(grasp, at, success=False)
    return record, step


def test_discriminate_when_already_told_apart(services, driver, log) -> None:  # noqa: ANN001
    record, step = _wrongly_predicted(services)
    record.session.record({"Height": 3.0}, P(6, 0))  # the box is 9 in tall, +-0.5
    assert run(Discriminate(ROBOT), services) == Status.SUCCESS
    assert driver.calls == []
    assert log.events == [{"event": "discriminate", "object": 0, "behaviour": "Discriminate", "already": True,
                           "wrong": "Front-Pinch"}]


def test_discriminate_measures_the_wrong_classs_cheapest_feature(services, driver, log) -> None:  # noqa: ANN001
    """The width (18) matches the box's; its Height(6,*) is measured here with D-Scan-0.3."""
    record, step = _wrongly_predicted(services)
    values = {"Height": 3.0, "Depth": 2.0, "Top-Hole?": 0.0}
    driver.script("sense", SenseResult("D-Scan-0.3", values, 84.0, 6.0))
    assert run(Discriminate(ROBOT), services) == Status.SUCCESS
    assert driver.calls == [("sense", "D-Scan-0.3")] and record.ledger.sensing_s == 84.0
    assert record.session.measurements[("Height", P(6, 0))] == 3.0
    assert record.session.measurements[("Depth", P(6, 0))] == 2.0
    assert log.events == [{"event": "discriminate", "object": 0, "behaviour": "Discriminate",
                           "procedure": "D-Scan-0.3", "values": values, "seconds": 84.0, "told_apart": True}]


def test_discriminate_keeps_measuring_until_told_apart(services, driver, log) -> None:  # noqa: ANN001
    """Wrongly Top-Pinch (the tumbler: height 6, top hole 1). A height of 6.2 does not
    tell them apart and the hole dropped out; the next procedure yields no hole: apart."""
    record, step = _wrongly_predicted(services, "Top-Pinch", width=8.5)
    driver.script("sense", SenseResult("D-Scan-0.3", {"Height": 6.2, "Depth": 4.0, "Top-Hole?": None}, 84.0, 6.0),
                  SenseResult("D-Scan-0.3", {"Height": 6.1, "Depth": 4.0, "Top-Hole?": 0.0}, 84.0, 6.0))
    behaviour = setup(Discriminate(ROBOT), services)
    behaviour.tick_once()
    assert behaviour.status == Status.RUNNING  # the second procedure under way
    assert tick(behaviour) == Status.SUCCESS
    assert driver.verbs() == ["sense", "sense"] and record.ledger.sensing_s == 168.0
    assert [e["told_apart"] for e in log.of("discriminate")] == [False, True]
    assert record.session.measurements[("Top-Hole?", P(6, 0))] == 0.0


def test_discriminate_does_not_ask_a_silent_procedure_again_on_the_object(services, driver, log) -> None:  # noqa: ANN001
    """Nothing measured yet, Front-Pinch (the box) fails: its Height(6,*) is asked of the
    D-Scan here, which gives nothing. Top-Pinch (the tumbler) fails next: the tumbler's
    Height(6,*) and Depth would come from the same D-Scan, which is not asked again on
    this object: one sense in all, not one per failed grasp."""
    record, step = start_object(services)
    record.session.position = P(6, 0)
    record.session.grasp_failed("Front-Pinch", side_effects=False)
    step.attempt = GraspAttempt("Front-Pinch", P(6, 0), success=False)
    driver.script("sense", SenseResult("D-Scan-0.3", {"Height": None, "Depth": None, "Top-Hole?": None}, 84.0, 6.0))
    behaviour = setup(Discriminate(ROBOT), services)
    assert tick(behaviour) == Status.SUCCESS
    record.session.grasp_failed("Top-Pinch", side_effects=False)
    step.attempt = GraspAttempt("Top-Pinch", P(6, 0), success=False)
    assert tick(behaviour) == Status.SUCCESS
    assert driver.verbs() == ["sense"] and record.ledger.sensing_s == 84.0
    assert [e.get("procedure") for e in log.of("discriminate")] == ["D-Scan-0.3"]


def test_discriminate_does_not_move_for_a_feature(services, driver, log) -> None:  # noqa: ANN001
    record, step = _wrongly_predicted(services, at=P(24, 0))  # the height is at (6,0): 36 s away
    assert run(Discriminate(ROBOT), services) == Status.SUCCESS
    assert driver.calls == [] and log.events == []


def test_discriminate_skips_a_grasp_tried_as_a_feature(services, driver, log) -> None:  # noqa: ANN001
    record, step = start_object(services)
    measure(record, 8.5, 4.8)
    test = record.session.decide()
    step.attempt = GraspAttempt("Front-Wrap", P(6, 0), as_feature=test, success=False)
    assert run(Discriminate(ROBOT), services) == Status.SUCCESS
    assert driver.calls == [] and log.events == []


def test_discriminate_skips_an_object_given_up_on(services, driver) -> None:  # noqa: ANN001
    record, step = _wrongly_predicted(services)
    record.finish("failed")
    assert run(Discriminate(ROBOT), services) == Status.SUCCESS
    assert driver.calls == []


def test_discriminate_refused_is_no_failure(services, driver, log) -> None:  # noqa: ANN001
    record, step = _wrongly_predicted(services)
    driver.script("sense", refused(NO_TARGET, "nothing in front of the sonar"))
    assert run(Discriminate(ROBOT), services) == Status.SUCCESS
    assert log.kinds() == ["driver_error"] and ("Height", P(6, 0)) not in record.session.measurements


def test_discriminate_raises_when_the_driver_is_gone(services, driver) -> None:  # noqa: ANN001
    _wrongly_predicted(services)
    driver.script("sense", refused(UNAVAILABLE, "gone"))
    with pytest.raises(DriverError):
        run(Discriminate(ROBOT), services)
