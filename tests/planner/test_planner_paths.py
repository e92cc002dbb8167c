"""OMPL paths on the inflated vision map: valid, explicit about failure, reusable."""

from __future__ import annotations

from dataclasses import replace

import math

import numpy as np
import pytest

from planner import Navigator, PathPlanner, PlanResult, Pose, Region, build_vision_map, look
from planner import paths as reasons
from planner.geometry import angle_between
from robot_profile import Robot, load_profile
from tests.planner.drawing import WALL, Canvas

HERO = load_profile().robot.geometry  # the shipped profile's: base radius 9 in, sonar 11 in ahead of the centre
START = Pose(40.0, 40.0, 0.0)
# the constants worked with by hand; any other the profile gains comes from the shipped one
MODEL_FOR_TESTS = replace(load_profile().robot.motion, speed_in_per_s=0.5, turn_deg_per_s=5.0, vision_s=5.0,
                          centring_s=15.0)


def divided_room() -> Canvas:
    """A wall from the floor up to y = 130 at x = 120: the way round is over the top."""
    return Canvas().rect(120.0, 65.0, 6.0, 130.0, 0.0, WALL).rect(180.0, 150.0, 20.0, 10.0, 0.0).robot(40.0, 40.0, 0.0)


@pytest.fixture(scope="module")
def planner() -> PathPlanner:
    return PathPlanner(build_vision_map(look(divided_room().image()), HERO))


def states_along(start: Pose, waypoints, step_in: float = 0.05):
    """Every point of the driven polyline, ``step_in`` apart."""
    points = [(start.x_in, start.y_in)] + [(w.x_in, w.y_in) for w in waypoints]
    for (ax, ay), (bx, by) in zip(points, points[1:]):
        n = max(1, math.ceil(math.dist((ax, ay), (bx, by)) / step_in))
        for k in range(n + 1):
            yield ax + (bx - ax) * k / n, ay + (by - ay) * k / n


def assert_clear(planner: PathPlanner, start: Pose, result) -> None:
    assert result.found, result.reason
    for x, y in states_along(start, result.path):
        assert planner.map.is_free(x, y), (x, y)


@pytest.mark.parametrize("goal", [Pose(200.0, 40.0, 90.0), Pose(160.0, 100.0, 180.0), Pose(215.0, 160.0, 0.0)])
def test_paths_go_round_the_wall_without_touching_inflated_obstacles(planner, goal):
    result = planner.plan(START, goal)
    assert_clear(planner, START, result)
    assert result.path[-1] == goal
    assert max(w.y_in for w in result.path) > 130.0  # over the top of the wall
    assert result.length_in >= math.dist((START.x_in, START.y_in), (goal.x_in, goal.y_in))


def test_roadmap_answers_detours(planner):
    result = planner.plan(START, Pose(200.0, 40.0, 90.0))
    assert result.planner == reasons.ROADMAP


def test_restarted_trees_answer_when_the_roadmap_cannot(planner):
    sparse = PathPlanner(planner.map, roadmap_milestones=2)
    goal = Pose(200.0, 40.0, 90.0)
    result = sparse.plan(START, goal)
    assert result.planner == reasons.TREE
    assert_clear(sparse, START, result)


def test_optimising_planner_also_stays_clear(planner):
    goal = Pose(200.0, 40.0, 90.0)
    result = planner.plan(START, goal, optimise=True, time_limit_s=0.3)
    assert_clear(planner, START, result)
    assert result.planner == "InformedRRTstar"


def test_waypoints_are_spaced_and_face_along_the_path(planner):
    goal = Pose(200.0, 40.0, 90.0)
    result = planner.plan(START, goal, spacing_in=10.0)
    points = [(START.x_in, START.y_in)] + list(result.corners)
    assert all(math.dist(a, b) <= 10.0 + 1e-6 for a, b in zip(points, points[1:]))
    for (a, b), waypoint in zip(zip(points, points[1:]), result.path[:-1]):
        course = math.degrees(math.atan2(b[1] - a[1], b[0] - a[0]))
        assert angle_between(course, waypoint.heading_deg) < 1e-6


def test_straight_line_when_nothing_is_in_the_way(planner):
    result = planner.plan(START, Pose(80.0, 40.0, 90.0), spacing_in=100.0)
    assert result.planner == "straight line"
    assert result.length_in == pytest.approx(40.0)
    assert result.turning_deg == pytest.approx(90.0)  # drive east, then turn north
    assert result.path == (Pose(80.0, 40.0, 90.0),)


@pytest.mark.parametrize("goal, reason", [
    (Pose(120.0, 40.0, 0.0), reasons.GOAL_BLOCKED),  # in the wall
    (Pose(180.0, 137.0, 0.0), reasons.GOAL_BLOCKED),  # next to the object, within the base radius
    (Pose(400.0, 40.0, 0.0), reasons.GOAL_OUTSIDE),
    (Pose(3.0, 90.0, 0.0), reasons.GOAL_BLOCKED),  # too close to the room's wall
])
def test_goals_that_cannot_be_reached_are_reported(planner, goal, reason):
    result = planner.plan(START, goal)
    assert not result.found and result.path is None
    assert result.reason == reason
    assert result.length_in == math.inf and result.turning_deg == math.inf


def test_enclosed_goal_is_unreachable_not_a_crash():
    room = Canvas().rect(170.0, 90.0, 60.0, 4.0, 0.0, WALL).rect(170.0, 150.0, 60.0, 4.0, 0.0, WALL)
    room.rect(140.0, 120.0, 4.0, 64.0, 0.0, WALL).rect(200.0, 120.0, 4.0, 64.0, 0.0, WALL).robot(40, 40, 0)
    planner = PathPlanner(build_vision_map(look(room.image()), HERO))
    result = planner.plan(START, Pose(170.0, 120.0, 0.0))
    assert result.reason == reasons.UNREACHABLE and not result.found


def test_a_doorway_narrower_than_the_base_blocks_the_way():
    room = Canvas().rect(120.0, 70.0, 6.0, 140.0, 0.0, WALL).rect(120.0, 175.0, 6.0, 10.0, 0.0, WALL)
    planner = PathPlanner(build_vision_map(look(room.robot(40, 40, 0).image()), HERO))
    # The gap from y = 140 to 170 is 30 in: wide enough for an 18 in base.
    assert planner.plan(START, Pose(200.0, 40.0, 0.0)).found
    narrow = Canvas().rect(120.0, 70.0, 6.0, 140.0, 0.0, WALL).rect(120.0, 165.0, 6.0, 30.0, 0.0, WALL)
    planner = PathPlanner(build_vision_map(look(narrow.robot(40, 40, 0).image()), HERO))
    # Now the gap is 10 in: the base cannot pass.
    assert planner.plan(START, Pose(200.0, 40.0, 0.0)).reason == reasons.UNREACHABLE


def test_start_in_an_obstacle_is_reported(planner):
    assert planner.plan(Pose(118.0, 40.0, 0.0), Pose(40.0, 100.0, 0.0)).reason == reasons.START_BLOCKED
    assert planner.plan(Pose(-50.0, 40.0, 0.0), Pose(40.0, 100.0, 0.0)).reason == reasons.START_OUTSIDE


@pytest.mark.parametrize("pose", [Pose(math.nan, 40.0, 0.0), Pose(40.0, math.inf, 0.0), Pose(40.0, 40.0, math.nan)])
def test_non_finite_poses_are_bad_input(planner, pose):
    with pytest.raises(ValueError, match="not finite"):
        planner.plan(pose, Pose(80.0, 40.0, 0.0))
    with pytest.raises(ValueError, match="not finite"):
        planner.plan(START, pose)


def test_bad_spacing_is_bad_input(planner):
    with pytest.raises(ValueError, match="spacing_in"):
        planner.plan(START, Pose(80.0, 40.0, 0.0), spacing_in=0.0)


def test_recent_plans_are_reused(planner):
    goal = Pose(200.0, 60.0, 0.0)
    first = planner.plan(START, goal)
    again = planner.plan(Pose(40.02, 39.98, 0.0), goal)
    assert again is first


def test_the_robot_itself_is_not_an_obstacle():
    vision_map = build_vision_map(look(divided_room().image()), HERO)
    assert vision_map.is_free(40.0, 40.0)
    assert not vision_map.occupied[vision_map.cell_of(40.0, 40.0)]


def test_inflation_is_the_base_radius():
    vision_map = build_vision_map(look(Canvas().rect(120.0, 90.0, 10.0, 10.0, 0.0, WALL).image()), HERO)
    # The block's face is at x = 125: the base centre must stay 9 in away, plus the
    # margin for where within a pixel the face and the base centre lie (1.7 pixels).
    assert not vision_map.is_free(125.0 + 9.0, 90.0)
    assert vision_map.is_free(125.0 + 9.0 + 1.71 * 0.8 + 0.8, 90.0)


def test_exact_segment_check_catches_a_grazed_corner():
    vision_map = build_vision_map(look(Canvas().rect(120.0, 90.0, 10.0, 10.0, 0.0, WALL).image()), HERO)
    blocked = np.argwhere(~vision_map.free[40:-40, 40:-40])[0] + 40
    x, y = vision_map.image.to_world(blocked[0], blocked[1])[0]
    assert not vision_map.segment_is_free((x - 30.0, y - 30.0), (x + 30.0, y + 30.0))
    assert vision_map.segment_is_free((30.0, 30.0), (60.0, 30.0))


def test_navigator_caches_scenes_on_image_content():
    navigator = Navigator(Robot(HERO, MODEL_FOR_TESTS))
    image = divided_room().image()
    scene = navigator.observe(image)
    same = navigator.observe(divided_room().image())
    assert same is scene
    other = navigator.observe(divided_room().rect(60.0, 150.0, 9.0, 4.0, 0.0).image())
    assert other is not scene and len(other.regions) == len(scene.regions) + 1
    assert navigator.observe(image) is scene  # back to the earlier world: reused


def test_navigator_keeps_the_map_while_only_the_robot_moves():
    navigator = Navigator(Robot(HERO, MODEL_FOR_TESTS))
    navigator.observe(divided_room().image())
    first_map = navigator.vision_map
    moved = Canvas().rect(120.0, 65.0, 6.0, 130.0, 0.0, WALL).rect(180.0, 150.0, 20.0, 10.0, 0.0).robot(60.0, 80.0, 90.0)
    scene = navigator.observe(moved.image())
    assert math.dist((scene.robot.x_in, scene.robot.y_in), (60.0, 80.0)) < 0.5
    assert navigator.vision_map is first_map
    pushed = Canvas().rect(120.0, 65.0, 6.0, 130.0, 0.0, WALL).rect(185.0, 150.0, 20.0, 10.0, 0.0).robot(60.0, 80.0, 90.0)
    navigator.observe(pushed.image())
    assert navigator.vision_map is not first_map


def test_navigator_needs_an_image_first():
    navigator = Navigator(Robot(HERO, MODEL_FOR_TESTS))
    with pytest.raises(ValueError, match="observe"):
        navigator.plan(START, Pose(80.0, 40.0, 0.0))
    with pytest.raises(ValueError, match="observe"):
        navigator.scene


def test_target_outside_the_map_is_bad_input():
    navigator = Navigator(Robot(HERO, MODEL_FOR_TESTS))
    scene = navigator.observe(divided_room().image())
    region = scene.regions[0]
    far = Region(region.polygon, (900.0, 900.0), region.pixel_count, region.orientation_deg, region.round,
                 region.length_in, region.width_in)
    with pytest.raises(ValueError, match="outside the map"):
        navigator.plan_to(START, far, 6.0, 0.0)
    with pytest.raises(ValueError, match="outside the map"):
        navigator.position_cost(START, far, 6.0, 0.0)


def test_plan_to_a_learner_position_and_price_it():
    navigator = Navigator(Robot(HERO, MODEL_FOR_TESTS))
    region = navigator.observe(divided_room().image()).regions[0]
    plan = navigator.plan_to(START, region, 16.0, 180.0)
    assert plan.found
    assert navigator.position_of(region, plan.path[-1]) == pytest.approx((16.0, 180.0))
    exact = navigator.position_cost(START, region, 16.0, 180.0, exact=True)
    assert exact.seconds == pytest.approx(5 + plan.length_in / 0.5 + plan.turning_deg / 5 + 15)


def test_a_start_just_inside_the_margin_escapes_first(planner):
    start = Pose(107.5, 60.0, 0.0)  # the wall's inflated margin begins at x ≈ 106.6
    assert not planner.map.is_free(start.x_in, start.y_in)
    result = planner.plan(start, Pose(40.0, 100.0, 90.0))
    assert result.found and 0 < result.escape_in < 4.0
    exit_point = result.path[0]
    assert math.dist((start.x_in, start.y_in), (exit_point.x_in, exit_point.y_in)) == pytest.approx(result.escape_in)
    assert_clear(planner, exit_point, PlanResult(result.path[1:], "ok", 0.0, 0.0, "rest"))
    assert result.length_in >= result.escape_in


def test_a_narrow_corridor_round_a_corner():
    # Furniture everywhere but an L-shaped corridor: x 0-46 up the left side, y 140-180
    # along the top; inflated, the base centre has 25 and 19 in of it.
    room = Canvas().rect(143.0, 70.0, 194.0, 140.0, 0.0, WALL).robot(33.0, 20.0, 90.0)
    planner = PathPlanner(build_vision_map(look(room.image()), HERO))
    start, goal = Pose(33.0, 20.0, 90.0), Pose(220.0, 153.0, 0.0)
    result = planner.plan(start, goal)
    assert_clear(planner, start, result)
    assert result.length_in == pytest.approx((153 - 20) + (220 - 33), rel=0.1)


@pytest.mark.slow
def test_the_same_question_gets_the_same_path_whatever_was_planned_before():
    vision_map = build_vision_map(look(divided_room().image()), HERO)
    goal = Pose(200.0, 40.0, 0.0)
    first = PathPlanner(vision_map).plan(START, goal)
    other = PathPlanner(vision_map)
    other.plan(START, Pose(160.0, 100.0, 180.0))
    other.plan(START, goal, optimise=True, time_limit_s=0.05)
    assert PathPlanner(vision_map).plan(START, goal).corners == first.corners
    trees = [PathPlanner(vision_map, roadmap_milestones=2).plan(START, goal).corners for _ in range(2)]
    assert trees[0] == trees[1]
