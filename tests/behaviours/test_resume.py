"""How a verb that did not come back ends (behaviours.base.DriverAction,
behaviours.reconnect, behaviours.resume): a timeout gives up the object in hand and
nothing more is sent for it; a lost driver stops the episode, or with
``Params.wait_driver_s`` the lost-driver guard (``driver check``, ticked here alone over
one action) pauses the work until a driver is back, then the objects are located again
and the step starts over.

The FakeNavigator's geometry (conftest): a position (d, o) around an object is the
point d inches from its centroid along bearing o; the fake driver stands at (0, 0).
"""

from __future__ import annotations

import dataclasses

import pytest
from py_trees.common import Status

from behaviours.actions import ApplyTest, Grasp, Learn, LocateObjects
from behaviours.reconnect import DriverLost, reconnecting
from behaviours.records import GraspAttempt, Step
from behaviours.services import Params
from hero_driver.interface import TIMEOUT, UNAVAILABLE, DriverError
from robot_profile import ProfileStamp
from tests.behaviours.conftest import (REGION, ROBOT, FakeDriver, P, fresh_board, get, image, make_services, put,
                                       refused, region, run, setup, start_object, tick)


class ComingBack(FakeDriver):
    """A FakeDriver whose driver process can be gone and come back (``back``), as the
    zenoh client tells by the liveliness token."""

    def __init__(self) -> None:
        super().__init__()
        self.back = False

    @property
    def alive(self) -> bool:
        return self.back

    def wait_ready(self, timeout_s: float) -> bool:
        return self.back


# -- a verb the robot did not answer ---------------------------------------------------------


def test_a_timeout_gives_up_the_object_and_nothing_more_is_sent_for_it(services, driver, log) -> None:  # noqa: ANN001
    fresh_board()
    record, step = start_object(services)
    step.test = record.session.decide()
    driver.script("sense", refused(TIMEOUT, "sense: no reply within 1 s"))
    assert run(ApplyTest(ROBOT), services) == Status.FAILURE
    assert record.outcome == "failed"
    assert log.of("gave_up") == [{"event": "gave_up", "object": 0, "behaviour": "ApplyTest",
                                  "reason": "the robot did not answer in time (sense: no reply within 1 s)"}]
    assert not record.session.awaiting_reselection  # unanswered is not refused: the test was not judged
    step.attempt = GraspAttempt("Front-Pinch", P(24, 0))
    grasp = Grasp(ROBOT)
    assert run(grasp, services) == Status.FAILURE  # the rest of the step sends nothing
    assert grasp.feedback_message == "object 0 was given up: no verb is sent for it"
    assert driver.verbs() == ["sense"]


def test_a_grasped_object_stays_grasped_when_its_release_is_unanswered(services, driver, log) -> None:  # noqa: ANN001
    fresh_board()
    record, _ = start_object(services)
    record.finish("grasped", "Front-Pinch", P(24, 0))
    driver.script("release", refused(TIMEOUT, "release: no reply within 2 s"))
    assert run(Learn(ROBOT), services) == Status.FAILURE
    assert record.outcome == "grasped" and log.of("gave_up") == []


def test_the_next_object_is_worked_on(services, driver) -> None:  # noqa: ANN001
    fresh_board()
    given_up, step = start_object(services)
    step.test = given_up.session.decide()
    driver.script("sense", refused(TIMEOUT, "sense: no reply within 1 s"))
    run(ApplyTest(ROBOT), services)
    record, step = start_object(services, index=1, where=region(30, 40))
    step.test = record.session.decide()
    driver.script("sense", refused(TIMEOUT, "sense: no reply within 1 s"))
    assert run(ApplyTest(ROBOT), services) == Status.FAILURE
    assert driver.verbs() == ["sense", "sense"]  # the new object's verb was sent


# -- a lost driver ---------------------------------------------------------------------------------


def waiting(wait_s: float = 10.0):  # noqa: ANN201
    driver = ComingBack()
    return make_services(driver=driver, params=Params(wait_driver_s=wait_s)), driver


def test_a_driver_that_comes_back_has_the_objects_located_again() -> None:
    services, driver = waiting()
    nav, log = services.navigator, services.log
    fresh_board()
    handled, _ = start_object(services, where=region(30, 40), index=0)
    handled.finish("grasped", "Front-Pinch", P(24, 0))
    record, step = start_object(services, index=1)  # REGION, at (100, 50)
    put("results", [handled, record])
    step.test = record.session.decide()
    driver.script("sense", refused(UNAVAILABLE, "sense: driver for r1 went away"))
    action = ApplyTest(ROBOT)
    behaviour = setup(reconnecting(action, ROBOT), services)
    assert tick(behaviour, max_ticks=3) == Status.RUNNING  # paused: no driver yet
    assert action.feedback_message == "driver for r1 lost: waiting up to 10 s for one to come back"
    driver.back = True
    # The world was put back: the handled object lies where it was, the one in hand a
    # little off; two others.
    nav.see(region(30.5, 40), region(101, 50, pixels=180), region(150, 60), region(10, 5))
    driver.script("camera", image())
    assert tick(behaviour) == Status.FAILURE  # the step under way starts over
    assert get("objects") == [region(10, 5), region(150, 60)]  # 11.2 and 161.6 in from (0, 0)
    assert record.region == region(101, 50, pixels=180) and record.pixels_before == 180
    assert record.outcome is None and handled.outcome == "grasped"
    assert record.session.position == P(112.7, 206.3)  # (0, 0) seen from (101, 50)
    assert get("step") is not step and get("step") == Step() and get("pose") is None
    assert driver.verbs() == ["sense", "camera"]
    [again] = [e for e in log.of("located") if "again" in e]
    assert str(again["again"]).startswith("driver for r1 came back after ")
    assert [r["centroid"] for r in again["regions"]] == [[10.0, 5.0], [150.0, 60.0]]


def test_no_driver_within_the_wait_stops_the_episode_in_one_line() -> None:
    services, driver = waiting(wait_s=1.0)  # the conftest clock moves 0.25 s per reading
    fresh_board()
    record, step = start_object(services)
    step.test = record.session.decide()
    driver.script("sense", refused(UNAVAILABLE, "sense: driver for r1 went away"))
    behaviour = setup(reconnecting(ApplyTest(ROBOT), ROBOT), services)
    with pytest.raises(DriverError, match=r"^unavailable: no driver for robot r1 came back within 1 s$"):
        tick(behaviour, max_ticks=20)


def test_without_a_wait_or_a_driver_that_can_come_back_the_episode_stops(services, driver) -> None:  # noqa: ANN001
    with_wait = make_services(params=Params(wait_driver_s=10.0))  # a FakeDriver: no liveliness to follow
    for chosen in (services, with_wait):
        fresh_board()
        record, step = start_object(chosen)
        step.test = record.session.decide()
        gone = refused(UNAVAILABLE, "sense: driver for r1 went away")
        chosen.driver.script("sense", gone)  # type: ignore[attr-defined]
        with pytest.raises(DriverError, match="went away"):
            run(ApplyTest(ROBOT), chosen)


class Stateless(ComingBack):
    """Gone between two verbs: asked its state with no driver alive, it raises as the
    zenoh client does (``no current state``)."""

    def state(self):  # noqa: ANN201
        if not self.back:
            raise DriverError(UNAVAILABLE, "no current state for r1: no driver alive")
        return super().state()


class WhereFirst(ApplyTest):
    """A verb whose start asks where the robot stands before sending it (as a move does)."""

    def start(self):  # noqa: ANN201
        self.services.driver.state()
        return super().start()


def test_a_driver_gone_between_two_verbs_is_waited_for_as_a_lost_verb() -> None:
    """The driver went while nothing was in flight: the next behaviour's start asks the
    state and is refused. With a wait that is the verb lost with its driver (the guard
    waits); without one the episode stops, as for a verb in flight."""
    driver = Stateless()
    services = make_services(driver=driver, params=Params(wait_driver_s=10.0))
    fresh_board()
    record, step = start_object(services)
    step.test = record.session.decide()
    action = WhereFirst(ROBOT)
    behaviour = setup(reconnecting(action, ROBOT), services)
    assert tick(behaviour, max_ticks=3) == Status.RUNNING
    assert action.feedback_message == "driver for r1 lost: waiting up to 10 s for one to come back"
    assert driver.verbs() == []  # nothing was sent to a driver that is not there
    plain = make_services(driver=Stateless())
    fresh_board()
    record, step = start_object(plain)
    step.test = record.session.decide()
    with pytest.raises(DriverError, match="no current state"):
        run(WhereFirst(ROBOT), plain)


def test_a_first_image_lost_with_its_driver_is_asked_again() -> None:
    services, driver = waiting()
    fresh_board()
    driver.script("camera", refused(UNAVAILABLE, "camera: driver for r1 went away"), image())
    services.navigator.see(REGION)  # type: ignore[attr-defined]
    behaviour = setup(reconnecting(LocateObjects(ROBOT), ROBOT), services)
    assert tick(behaviour, max_ticks=3) == Status.RUNNING
    driver.back = True
    assert tick(behaviour) == Status.SUCCESS
    assert get("objects") == [REGION] and driver.verbs() == ["camera", "camera"]


def test_a_driver_that_comes_back_as_another_robot_stops_the_episode() -> None:
    services, driver = waiting()
    services = dataclasses.replace(services, served=ProfileStamp("hero2000", "a" * 64))
    driver.profile = ProfileStamp("rover", "b" * 64)  # type: ignore[attr-defined]
    fresh_board()
    record, step = start_object(services)
    step.test = record.session.decide()
    driver.script("sense", refused(UNAVAILABLE, "sense: driver for r1 went away"))
    behaviour = setup(reconnecting(ApplyTest(ROBOT), ROBOT), services)
    assert tick(behaviour, max_ticks=2) == Status.RUNNING
    driver.back = True
    said = (r"^unavailable: the driver that came back for robot r1 serves robot profile rover "
            r"\(sha256 bbbbbbbbbbbb\), not hero2000 \(sha256 aaaaaaaaaaaa\)$")
    with pytest.raises(DriverError, match=said):
        tick(behaviour)
    assert driver.verbs() == ["sense"]  # nothing was asked of the other robot


def test_a_driver_that_comes_back_as_the_same_robot_is_used() -> None:
    services, driver = waiting()
    services = dataclasses.replace(services, served=ProfileStamp("hero2000", "a" * 64))
    driver.profile = ProfileStamp("hero2000", "a" * 64)  # type: ignore[attr-defined]
    fresh_board()
    record, step = start_object(services)
    step.test = record.session.decide()
    driver.script("sense", refused(UNAVAILABLE, "sense: driver for r1 went away"))
    driver.script("camera", image())
    services.navigator.see(REGION)  # type: ignore[attr-defined]
    behaviour = setup(reconnecting(ApplyTest(ROBOT), ROBOT), services)
    assert tick(behaviour, max_ticks=2) == Status.RUNNING
    driver.back = True
    assert tick(behaviour) == Status.FAILURE and driver.verbs() == ["sense", "camera"]


def test_a_driver_gone_again_before_its_image_came_is_waited_for_again() -> None:
    services, driver = waiting()
    fresh_board()
    record, step = start_object(services)
    step.test = record.session.decide()
    driver.script("sense", refused(UNAVAILABLE, "sense: driver for r1 went away"))
    driver.script("camera", refused(UNAVAILABLE, "camera: driver for r1 went away"), image())
    services.navigator.see(REGION)  # type: ignore[attr-defined]
    driver.back = True
    behaviour = setup(reconnecting(ApplyTest(ROBOT), ROBOT), services)
    assert tick(behaviour) == Status.FAILURE  # the second image came: located again, the step starts over
    assert driver.verbs() == ["sense", "camera", "camera"] and get("step") == Step()
    assert [e["behaviour"] for e in services.log.of("located")] == ["relocate"]  # type: ignore[attr-defined]


def test_with_no_verb_lost_the_guard_lets_the_work_run(services, driver) -> None:  # noqa: ANN001
    fresh_board()
    condition = DriverLost(ROBOT)
    assert run(condition, services) == Status.FAILURE and not condition.fired
    services.navigator.see(REGION)  # type: ignore[attr-defined]
    driver.script("camera", image())
    assert run(reconnecting(LocateObjects(ROBOT), ROBOT), services) == Status.SUCCESS
    assert get("objects") == [REGION] and driver.verbs() == ["camera"]
