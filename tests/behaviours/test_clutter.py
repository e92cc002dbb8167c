"""``BeamClear?`` (behaviours.clutter) ticked alone on the fake driver and navigator.

Geometry: the object is conftest's 4 x 4 in square at (100, 50) (axis +x); the session
starting at (60, 0) chooses the Width test at (24, 0) (test_choosing), so the sonar
stands at x = 100 + 2 + 24 = 126 and the beam's corridor spans x 98..126, y 48..52.
"""

from __future__ import annotations

import dataclasses
import math

from py_trees.common import Status

from behaviours.choosing import BestTest
from behaviours.clutter import BeamClear, LookForTheRest
from behaviours.services import Params
from planner import Region
from tests.behaviours.conftest import (REGION, ROBOT, WIDTH, FakeNavigator, P, get, image, make_services, put, region, run,
                                      start_object)


def chosen(*regions: Region, params: Params = Params()):  # noqa: ANN201 - the test's tuple
    services = make_services(navigator=FakeNavigator(latest=regions), params=params)
    record, step = start_object(services)
    assert run(BestTest(ROBOT), services) == Status.SUCCESS
    assert str(step.test.test) == WIDTH and step.test.target == P(24, 0)
    return services, record, step


def test_a_neighbour_in_the_beam_makes_the_test_unusable_there() -> None:
    neighbour = region(115.0, 50.0)
    services, record, step = chosen(REGION, neighbour)
    assert run(BeamClear(ROBOT), services) == Status.FAILURE
    assert record.session.awaiting_reselection  # the learner reselects; nothing measured
    assert services.driver.verbs() == []
    event = services.log.of("beam_blocked")[-1]
    assert event["cluster"] is False and event["blockers"] == [[115.0, 50.0]]
    assert services.log.of("no_path") == []  # a beam, not a path
    # the reselected test is another one
    assert run(BestTest(ROBOT), services) == Status.FAILURE  # a fresh best choice is not asked now
    assert record.session.decide() != step.test


def test_a_neighbour_six_inches_beside_the_beam_is_clear() -> None:
    services, record, _ = chosen(REGION, region(115.0, 60.0))  # near edge y = 58: 6 in from y = 52
    assert run(BeamClear(ROBOT), services) == Status.SUCCESS
    assert not record.session.awaiting_reselection and services.log.of("beam_blocked") == []


def test_the_object_seen_anew_is_not_its_own_neighbour() -> None:
    services, _, _ = chosen(region(100.4, 50.3))  # within pushed_in (1 in) of the object's centroid
    assert run(BeamClear(ROBOT), services) == Status.SUCCESS


def test_with_the_check_off_a_blocked_beam_passes() -> None:
    services, record, _ = chosen(REGION, region(115.0, 50.0), params=Params(beam_check=False))
    assert run(BeamClear(ROBOT), services) == Status.SUCCESS
    assert not record.session.awaiting_reselection


def test_a_grasp_or_a_value_already_measured_needs_no_check() -> None:
    services, record, step = chosen(REGION, region(115.0, 50.0))
    step.test = dataclasses.replace(step.test, move_cost=0.0, sense_cost=0.0)  # a free re-use
    assert math.isclose(step.test.cost, 0.0)
    assert run(BeamClear(ROBOT), services) == Status.SUCCESS


def test_no_sensing_of_a_cluster_is_used_even_with_nothing_else_in_view() -> None:
    services, record, _ = chosen()
    record.region = dataclasses.replace(record.region, cluster=True)
    assert run(BeamClear(ROBOT), services) == Status.FAILURE
    assert record.session.awaiting_reselection
    assert services.log.of("beam_blocked")[-1]["cluster"] is True


# -- LookForTheRest: after a cluster's grasp, what is left of it is queued next ------------

def _grasped(services, where: Region):  # noqa: ANN001, ANN202
    record, _ = start_object(services, where=where)
    record.finish("grasped", "Top-Pinch", P(6, 0))
    return record


def test_what_is_left_of_a_grasped_cluster_goes_to_the_front_of_the_list() -> None:
    cluster = dataclasses.replace(REGION, cluster=True)  # the 4 x 4 in square at (100, 50)
    # the new image: the other object 1.5 in off the square's side (within 3 in), a far
    # one already queued, and one seen anew 0.5 in from the queued one (the same object)
    left, far = region(103.5, 50.0), region(160.0, 50.0)
    services = make_services(navigator=FakeNavigator().see(left, far, region(160.5, 50.0)))
    services.driver.script("camera", image())
    _grasped(services, cluster)
    put("objects", [far])
    assert run(LookForTheRest(ROBOT), services) == Status.SUCCESS
    assert get("objects") == [left, far]
    assert services.log.of("rest_of_cluster")[-1]["regions"] == [[103.5, 50.0]]


def test_an_object_that_was_no_cluster_or_was_left_needs_no_second_look() -> None:
    for where, outcome in ((REGION, "grasped"), (dataclasses.replace(REGION, cluster=True), "left")):
        services = make_services()
        record, _ = start_object(services, where=where)
        record.finish(outcome, "Top-Pinch" if outcome == "grasped" else "No-Grab", P(6, 0))
        put("objects", [])
        assert run(LookForTheRest(ROBOT), services) == Status.SUCCESS
        assert services.driver.verbs() == [] and get("objects") == []
