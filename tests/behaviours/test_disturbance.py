"""The camera check before sensing and grasping (behaviours.disturbance), behaviour by
behaviour against the fake driver and a navigator whose camera regions the test sets.

Geometry (conftest's FakeNavigator): the object's region at (100, 50) with 200 pixels;
the default tolerances are 1 in (``pushed_in``), 25 % of the pixels
(``changed_ratio``; for 200 pixels more than the outline's 1.5 sqrt(200) = 21) and
24 in (``search_in``).
"""

from __future__ import annotations

import dataclasses
import math

import py_trees
import pytest
from hypothesis import given
from hypothesis import strategies as st
from py_trees.common import Status

from behaviours.disturbance import (CHANGED, FINDING, GONE, MOVED, Disturbed, Finding, Relocate, ReportGone,
                                    StartAfresh, judge, look_before)
from behaviours.services import Params
from hero_driver.interface import Pose as DriverPose
from learner.position import Position
from planner import Region
from tests.behaviours.conftest import REGION, ROBOT, get, image, make_services, measure, put, region, run, start_object

TOLERANCES = {"in_place_in": 1.0, "search_in": 24.0, "changed_ratio": 0.25}


# -- the check itself -------------------------------------------------------------------


def test_judge_in_place_within_both_tolerances() -> None:
    assert judge(REGION, 200, [region(100.6, 50.8, pixels=240)], [], **TOLERANCES) is None  # 1.0 in, +20 %


def test_judge_moved_same_size_farther_than_the_tolerance() -> None:
    finding = judge(REGION, 200, [region(103.0, 54.0, pixels=210)], [], **TOLERANCES)
    assert finding is not None and finding.kind == MOVED
    assert finding.shift_in == pytest.approx(5.0) and finding.pixel_change == pytest.approx(0.05)


def test_judge_changed_when_the_size_differs_in_place_or_not() -> None:
    here = judge(REGION, 200, [region(100.0, 50.0, pixels=120)], [], **TOLERANCES)
    near = judge(REGION, 200, [region(106.0, 58.0, pixels=300)], [], **TOLERANCES)
    assert here is not None and here.kind == CHANGED and here.pixel_change == pytest.approx(0.4)
    assert near is not None and near.kind == CHANGED and near.shift_in == pytest.approx(10.0)


def test_judge_a_small_objects_count_may_vary_by_its_outline() -> None:
    # 12 pixels: 1.5 sqrt(12) = 5.2 pixels (43 %) of tolerance, not 25 % (3 pixels)
    assert judge(REGION, 12, [region(100.0, 50.0, pixels=8)], [], **TOLERANCES) is None
    swapped = judge(REGION, 12, [region(100.0, 50.0, pixels=18)], [], **TOLERANCES)
    assert swapped is not None and swapped.kind == CHANGED


def test_judge_gone_when_nothing_is_within_the_search_radius() -> None:
    finding = judge(REGION, 200, [region(100.0, 75.0)], [], **TOLERANCES)  # 25 in away
    assert finding is not None and finding.kind == GONE and finding.region is None


def test_judge_never_takes_another_known_object_for_ours() -> None:
    neighbour = region(110.0, 50.0)
    alone = judge(REGION, 200, [neighbour], [(110.0, 50.0)], **TOLERANCES)
    assert alone is not None and alone.kind == GONE
    moved = judge(REGION, 200, [neighbour, region(95.0, 50.0)], [(110.0, 50.0)], **TOLERANCES)
    assert moved is not None and moved.kind == MOVED and moved.region == region(95.0, 50.0)


def test_judge_a_cluster_reaching_where_ours_was_holds_ours_pushed_against_a_known_object() -> None:
    # ours (the 4 x 4 in square at (100, 50)) pushed against the known object at (106, 50):
    # one region from x 101 to 108, a cluster, its centroid 0.5 in from the other's
    pair = Region(((101.0, 48.0), (108.0, 48.0), (108.0, 52.0), (101.0, 52.0)), (105.5, 50.0), 350, 0.0, False,
                  7.0, 4.0, cluster=True)
    finding = judge(REGION, 200, [pair], [(106.0, 50.0)], **TOLERANCES)  # 1 in outside ours: within a push
    assert finding is not None and finding.kind == CHANGED and finding.region == pair  # started afresh on it
    alone = judge(REGION, 200, [dataclasses.replace(pair, cluster=False)], [(106.0, 50.0)], **TOLERANCES)
    assert alone is not None and alone.kind == GONE  # not a cluster: the other object, as before


def test_judge_prefers_the_region_of_the_right_size_among_equally_near_ones() -> None:
    seen = [region(104.0, 50.0, pixels=80), region(96.0, 50.0, pixels=190)]
    finding = judge(REGION, 200, seen, [], **TOLERANCES)
    assert finding is not None and finding.kind == MOVED and finding.region == seen[1]


@given(st.floats(0.0, 360.0), st.floats(1.01, 23.9), st.floats(0.76, 1.25))
def test_judge_a_same_size_region_within_the_search_is_moved_or_in_place(bearing: float, shift: float,
                                                                          scale: float) -> None:
    x = 100.0 + shift * math.cos(math.radians(bearing))
    y = 50.0 + shift * math.sin(math.radians(bearing))
    finding = judge(REGION, 200, [region(x, y, pixels=round(200 * scale))], [], **TOLERANCES)
    assert finding is not None and finding.kind == MOVED and finding.shift_in == pytest.approx(shift)
    assert judge(REGION, 200, [region(100.0, 50.0, pixels=round(200 * scale))], [], **TOLERANCES) is None


# -- Disturbed? ----------------------------------------------------------------------------


def checking(params: Params = Params()):  # noqa: ANN201
    services = make_services(params=params)
    record, step = start_object(services)
    step.test = record.session.decide()  # Width-Degree-1° at (24, 0): a paid test
    put("objects", [])
    put("results", [record])
    return services, record, step


def test_disturbed_fails_when_the_object_is_in_place() -> None:
    services, record, _ = checking()
    services.driver.script("camera", image())  # type: ignore[attr-defined]
    services.navigator.see(region(100.3, 50.0, pixels=205))  # type: ignore[attr-defined]
    assert run(Disturbed(ROBOT, "test"), services) == Status.FAILURE
    assert get(FINDING) is None and not services.log.of("disturbance")  # type: ignore[attr-defined]


def test_disturbed_succeeds_with_its_finding_and_logs_it() -> None:
    services, _, _ = checking()
    services.driver.script("camera", image())  # type: ignore[attr-defined]
    services.navigator.see(region(106.0, 58.0, pixels=200))  # type: ignore[attr-defined]
    assert run(Disturbed(ROBOT, "grasp"), services) == Status.SUCCESS
    assert get(FINDING).kind == MOVED
    [event] = services.log.of("disturbance")  # type: ignore[attr-defined]
    assert event["before"] == "grasp" and event["found"] == MOVED and event["shift_in"] == 10.0


def test_disturbed_does_not_look_when_the_check_is_off() -> None:
    services, _, _ = checking(Params(check_in_place=False))
    assert run(Disturbed(ROBOT, "test"), services) == Status.FAILURE
    assert services.driver.calls == []  # type: ignore[attr-defined]


def test_disturbed_does_not_look_before_a_free_test() -> None:
    services, _, step = checking()
    step.test = None
    assert run(Disturbed(ROBOT, "test"), services) == Status.FAILURE
    assert services.driver.calls == []  # type: ignore[attr-defined]


def test_disturbed_refuses_to_guard_anything_else() -> None:
    with pytest.raises(ValueError, match="'test' or a 'grasp'"):
        Disturbed(ROBOT, "move")


# -- the recoveries -------------------------------------------------------------------------


def found(kind: str, where: tuple[float, float] | None, pixels: int = 200) -> None:
    put(FINDING, Finding(kind, None if where is None else region(*where, pixels=pixels), 0.0, 0.0))


def test_relocate_follows_the_object_and_keeps_every_value() -> None:
    services, record, _ = checking()
    measure(record, 18.0)  # Width-Degree-1° = 18: the box branch
    put("pose", DriverPose(160.0, 50.0, 180.0))
    found(MOVED, (100.0, 110.0))
    assert run(Relocate(ROBOT), services) == Status.SUCCESS
    assert record.region.centroid == (100.0, 110.0) and record.estimator.region is record.region
    assert len(record.session.path) == 1
    # the robot at (160, 50) is sqrt(60^2 + 60^2) = 84.85 in from (100, 110), bearing -45°
    assert record.session.position == Position(84.9, 315.0)
    assert get(FINDING) is None and record.ledger.recoveries["disturbed (moved)"] == 1
    assert services.log.of("relocate")[0]["kept"] == 1  # type: ignore[attr-defined]


def test_start_afresh_forgets_what_was_measured() -> None:
    services, record, _ = checking()
    measure(record, 18.0)
    old = record.session
    put("pose", DriverPose(130.0, 50.0, 180.0))
    found(CHANGED, (100.0, 50.0), pixels=90)
    assert run(StartAfresh(ROBOT), services) == Status.SUCCESS
    assert record.session is not old and record.session.path == [] and record.pixels_before == 90
    assert record.session.position == Position(30.0, 0.0) and not record.done


def test_report_gone_ends_the_object_gone() -> None:
    services, record, _ = checking()
    found(GONE, None)
    assert run(ReportGone(ROBOT), services) == Status.SUCCESS
    assert record.outcome == GONE and record.done
    assert services.log.of("gone")[0]["was_at"] == [100.0, 50.0]  # type: ignore[attr-defined]


@pytest.mark.parametrize("recovery", [Relocate, StartAfresh, ReportGone])
def test_each_recovery_leaves_the_other_findings_alone(recovery: type) -> None:
    services, record, _ = checking()
    for kind in {MOVED, CHANGED, GONE} - {recovery.KIND}:
        found(kind, (100.0, 60.0))
        assert run(recovery(ROBOT), services) == Status.FAILURE
    assert not record.done and record.region is REGION


# -- the subtree ------------------------------------------------------------------------------


class Act(py_trees.behaviour.Behaviour):
    def __init__(self) -> None:
        super().__init__("act")
        self.ticked = 0

    def update(self) -> Status:
        self.ticked += 1
        return Status.SUCCESS


@pytest.mark.parametrize(("seen", "acted", "outcome"), [
    (region(100.0, 50.0), 1, None),  # in place: the sensing or grasp goes ahead
    (region(100.0, 120.0), 0, GONE),  # gone: reported instead, and the step ends
])
def test_look_before_acts_only_on_an_object_in_place(seen, acted, outcome) -> None:  # noqa: ANN001
    services, record, _ = checking()
    services.driver.script("camera", image())  # type: ignore[attr-defined]
    services.navigator.see(seen)  # type: ignore[attr-defined]
    act = Act()
    assert run(look_before(ROBOT, "test", act), services) == Status.SUCCESS
    assert act.ticked == acted and record.outcome == outcome

