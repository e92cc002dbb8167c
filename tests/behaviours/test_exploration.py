"""Exploring before the objects are located (behaviours.exploration): the branch ticked
alone on the fake driver and navigator, with a perception whose views the test chooses."""

from __future__ import annotations

import dataclasses
from typing import Any

from py_trees.common import Status

from behaviours.exploration import explore
from behaviours.legs import first_leg
from behaviours.perception import CeilingCamera
from behaviours.services import Params, Services
from hero_driver.interface import Pose as DriverPose  # noqa: I001 (the planner has a Pose too)
from planner import PlanResult, Pose, Scene
from tests.behaviours.conftest import ROBOT, CountedLooks, blank_scene, fresh_board, make_services, moved, run


LEG_IN = 60.0  # the perception's leg


class Views(CountedLooks):
    """A perception offering the views it is given, in turn, and noting those refused."""

    verb = "scan"
    corrects_heading = True
    leg_in = LEG_IN
    stranded = None

    def __init__(self, *views: Pose | None) -> None:
        super().__init__()
        self.views = list(views)
        self.refused: list[Pose] = []

    def scene(self, observation: Any) -> Scene:
        return blank_scene()

    glance = scene

    def next_view(self, robot: Pose) -> Pose | None:
        return self.views.pop(0) if self.views else None

    def unreachable(self, view: Pose) -> None:
        self.refused.append(view)

    def bumped(self, pose: Pose) -> tuple[float, float] | None:
        return None


def with_views(*views: Pose | None, params: Params = Params()) -> tuple[Services, Views]:
    fresh_board()
    perception = Views(*views)
    return dataclasses.replace(make_services(params=params), perception=perception), perception


def test_first_leg_cuts_a_path_at_its_length_along_it() -> None:
    path = [Pose(0.0, 0.0, 0.0), Pose(100.0, 0.0, 0.0), Pose(100.0, 100.0, 90.0)]
    assert first_leg(path, 60.0) == [Pose(0.0, 0.0, 0.0), Pose(60.0, 0.0, 0.0)]
    assert first_leg(path, 150.0) == [Pose(0.0, 0.0, 0.0), Pose(100.0, 0.0, 0.0), Pose(100.0, 50.0, 90.0)]
    assert first_leg(path, 500.0) == path and first_leg([], 60.0) == []


def test_the_robot_looks_and_goes_to_each_view_until_none_is_left() -> None:
    a, b = Pose(30.0, 0.0, 0.0), Pose(30.0, 40.0, 90.0)
    services, views = with_views(a, b, None)
    driver = services.driver
    driver.script("move", moved(DriverPose(30.0, 0.0, 0.0), 50.0), moved(DriverPose(30.0, 40.0, 90.0), 70.0))
    assert run(explore(ROBOT), services, max_ticks=20) == Status.SUCCESS
    assert views.looks == 3 and views.refused == []
    # the fake navigator plans one waypoint, the goal (shorter than a leg): sent as it is
    assert [c[1] for c in driver.calls] == [(DriverPose(30.0, 0.0, 0.0),), (DriverPose(30.0, 40.0, 90.0),)]
    log = services.log
    assert log.kinds() == ["view", "explore_move", "view", "explore_move", "view", "mapped"]
    assert [e["next"] for e in log.of("view")] == [[30.0, 0.0, 0.0], [30.0, 40.0, 90.0], None]
    assert log.of("mapped")[0] == {"event": "mapped", "behaviour": "explore the home", "views": 3, "seconds": 120.0, "candidates": 0,
                                   "reason": "the home is mapped"}


def test_no_view_because_the_robot_is_stranded_is_said_so_not_mapped() -> None:
    services, views = with_views(None)
    views.stranded = "no view can be reached: the robot stands in an obstacle"  # type: ignore[misc]
    assert run(explore(ROBOT), services, max_ticks=20) == Status.SUCCESS
    assert services.log.of("mapped")[0]["reason"] == "no view can be reached: the robot stands in an obstacle"


def test_a_view_with_no_path_or_a_collision_is_unreachable_and_exploring_goes_on() -> None:
    blocked, bumped, fine = Pose(90.0, 0.0, 0.0), Pose(0.0, 50.0, 90.0), Pose(10.0, 0.0, 0.0)
    services, views = with_views(blocked, bumped, fine, None)
    services.navigator.blocked[(90.0, 0.0)] = "goal in an obstacle"
    services.driver.script("move", moved(DriverPose(0.0, 20.0, 90.0), 10.0, collided=True),
                           moved(DriverPose(10.0, 0.0, 0.0), 5.0))
    assert run(explore(ROBOT), services, max_ticks=30) == Status.SUCCESS
    assert views.refused == [blocked, bumped]
    reasons = [e.get("reason") for e in services.log.of("explore_move") if "unreachable" in e]
    assert reasons == ["no path: goal in an obstacle", "the move stopped short"]


def test_the_bound_on_views_ends_a_search_that_would_not() -> None:
    services, views = with_views(*[Pose(float(i), 0.0, 0.0) for i in range(1, 10)], params=Params(max_views=3))
    services.driver.script("move", *[moved(DriverPose(float(i), 0.0, 0.0), 1.0) for i in range(1, 10)])
    assert run(explore(ROBOT), services, max_ticks=30) == Status.SUCCESS
    assert views.looks == 3
    assert services.log.of("mapped")[0]["reason"] == "the bound of 3 views was spent"


def test_a_long_way_to_a_view_is_driven_a_leg_at_a_time() -> None:
    far = Pose(2 * LEG_IN + 10.0, 0.0, 0.0)
    services, views = with_views(far, far, far, None)
    services.driver.script("move", *[moved(DriverPose(LEG_IN * k, 0.0, 0.0), 1.0) for k in (1, 2)],
                           moved(DriverPose(far.x_in, 0.0, 0.0), 1.0))
    services.driver.pose = DriverPose(0.0, 0.0, 0.0)
    # a straight two-point path from where the robot stands: its first leg ends LEG_IN along it
    services.navigator.plan = lambda start, goal, **_: PlanResult(  # type: ignore[method-assign]
        (start, goal), "ok", goal.x_in - start.x_in, 0.0, "fake")
    assert run(explore(ROBOT), services, max_ticks=30) == Status.SUCCESS
    ends = [c[1][-1] for c in services.driver.calls]
    assert [round(e.x_in, 6) for e in ends] == [LEG_IN, 2 * LEG_IN, far.x_in]


def test_the_ceiling_camera_has_no_view_to_offer() -> None:
    services = make_services()
    camera = services.perception
    assert isinstance(camera, CeilingCamera) and camera.verb == "camera" and not camera.corrects_heading
    assert camera.next_view(Pose(0.0, 0.0, 0.0)) is None
