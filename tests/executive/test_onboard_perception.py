"""The onboard perception (executive/onboard.py) on synthetic scans and the real planner:
scans become a scene whose regions are the objects, whose map the planner plans on, and
whose next view looks into what is still unknown."""

from __future__ import annotations

import math
from concurrent.futures import Future

import numpy as np
import pytest

from executive.onboard import OnboardPerception, OnboardSettings, planar_scan
from hero_driver.interface import Pose as DriverPose
from hero_driver.interface import RangeScan
from planner import Navigator, Pose, Scene
from robot_profile import load_profile
from tests.mapping.synthetic import Lidar, box

LIDAR = Lidar(sigma_in=0.0, dropout=0.0)
# Two rooms, 120 x 100 in each, a 36 in doorway at y 32-68 in the wall x = 120; a 6 in box
# at (60, 30) in the first room.
WALLS = np.array(box(0.0, 0.0, 240.0, 100.0) + [(120.0, 0.0, 120.0, 32.0), (120.0, 68.0, 120.0, 100.0)]
                 + box(57.0, 27.0, 63.0, 33.0), dtype=float)


class Scans:
    """A driver with the scan feature whose robot stands where the test puts it."""

    robot = "r1"

    def __init__(self) -> None:
        self.pose = DriverPose(30.0, 70.0, 0.0)
        self.clock_s = 0.0
        self.walls = WALLS

    def scan(self) -> Future[RangeScan]:
        self.clock_s += 1.0
        ranges = LIDAR.scan(self.walls, (self.pose.x_in, self.pose.y_in, math.radians(self.pose.heading_deg)),
                            np.random.default_rng(0))
        done: Future[RangeScan] = Future()
        done.set_result(RangeScan(self.pose, self.clock_s, tuple(np.degrees(LIDAR.angles_rad).tolist()),
                                  tuple(float(r) for r in ranges), 0.5, LIDAR.max_range_in))
        return done


def perception() -> tuple[OnboardPerception, Scans, Navigator]:
    scans, navigator = Scans(), Navigator(load_profile().robot)
    return OnboardPerception(scans, navigator, OnboardSettings(half_extent_in=300.0)), scans, navigator


def look_from(seen: OnboardPerception, scans: Scans, *at: tuple[float, float]) -> Scene:
    """Scans from each of ``at`` (facing +x) read in turn; the last one's scene."""
    for x, y in at:
        scans.pose = DriverPose(x, y, 0.0)
        scene = seen.scene(seen.look().result())
    return scene


def test_a_driver_scan_in_degrees_with_no_echo_as_none_or_inf() -> None:
    scan = RangeScan(DriverPose(1.0, 2.0, 90.0), 3.0, (-90.0, 0.0, 90.0), (10.0, None, math.inf), 0.5, 100.0)  # type: ignore[arg-type]
    planar = planar_scan(scan)
    assert planar.angles_rad == pytest.approx([-math.pi / 2, 0.0, math.pi / 2])
    assert planar.ranges_in[0] == 10.0 and math.isinf(planar.ranges_in[1]) and math.isinf(planar.ranges_in[2])
    assert (planar.x_in, planar.y_in, planar.heading_deg, planar.stamp_s) == (1.0, 2.0, 90.0, 3.0)


def test_scans_make_a_scene_of_the_box_and_a_map_the_planner_plans_on() -> None:
    seen, scans, navigator = perception()
    scene = look_from(seen, scans, (30.0, 70.0), (90.0, 70.0))  # a candidate is reported once seen twice
    robot = scene.robot
    assert navigator.scene is scene and robot is not None
    assert (robot.x_in, robot.y_in, robot.heading_deg) == pytest.approx((90.0, 70.0, 0.0), abs=0.1)
    assert len(scene.regions) == 1
    box_region = scene.regions[0]
    assert box_region.centroid == pytest.approx((60.0, 30.0), abs=1.5) and box_region.area_in2 is None
    # the planner plans on it: round the box, within the first room; the second, seen
    # only through the doorway's wedge, is not all free yet
    plan = navigator.plan(Pose(30.0, 70.0, 0.0), Pose(90.0, 20.0, 0.0))
    assert plan.found, plan.reason
    assert not navigator.vision_map.is_free(200.0, 90.0)


def test_the_next_view_looks_through_the_doorway_and_a_refused_one_is_not_offered_again() -> None:
    seen, scans, _ = perception()
    look_from(seen, scans, (30.0, 70.0), (90.0, 50.0))
    view = seen.next_view(Pose(90.0, 50.0, 0.0))
    assert view is not None and view.x_in > 60.0, "toward the unknown second room"
    seen.unreachable(view)
    again = seen.next_view(Pose(90.0, 50.0, 0.0))
    assert again is None or math.hypot(again.x_in - view.x_in, again.y_in - view.y_in) > 12.0


def test_settings_are_checked_in_one_line() -> None:
    with pytest.raises(ValueError, match="onboard setting inches_per_cell must be positive, got 0"):
        OnboardSettings(inches_per_cell=0.0)
    with pytest.raises(ValueError, match="settled_seen must be at least 1"):
        OnboardSettings(settled_seen=0)


def test_the_view_driven_to_is_kept_until_reached() -> None:
    seen, scans, _ = perception()
    look_from(seen, scans, (30.0, 70.0), (90.0, 50.0))
    view = seen.next_view(Pose(90.0, 50.0, 0.0))
    assert view is not None
    assert seen.next_view(Pose(80.0, 50.0, 0.0)) == view  # on the way (the costs shifted): the same view
    arrived = seen.next_view(Pose(view.x_in, view.y_in, view.heading_deg))
    assert arrived != view  # standing there: another view, or none


def test_an_object_seen_again_off_its_kept_region_is_outlined_anew_not_lost() -> None:
    """A 2 in post at (60, 30) in the first room, scanned from (40, 70) and (80, 70) until
    its region settles; then it is knocked 5 in east. The next scan, from (60, 70), looks
    through where its kept region lies (the returns nearest it are 3 in off, past the
    2 in a return on it may be), but the same track is seen (its centroid moved 5 in,
    within the 6 in that keep a track): its region is outlined anew there, not dropped
    as gone."""
    seen, scans, _ = perception()
    room = np.array(box(0.0, 0.0, 240.0, 100.0) + [(120.0, 0.0, 120.0, 32.0), (120.0, 68.0, 120.0, 100.0)],
                    dtype=float)
    scans.walls = np.concatenate([room, np.array(box(59.0, 29.0, 61.0, 31.0), dtype=float)])
    scene = look_from(seen, scans, *[(40.0 + 40.0 * (k % 2), 70.0) for k in range(8)])
    assert [r.centroid for r in scene.regions] == [pytest.approx((60.0, 30.0), abs=1.5)]
    scans.walls = np.concatenate([room, np.array(box(64.0, 29.0, 66.0, 31.0), dtype=float)])
    scene = look_from(seen, scans, (60.0, 70.0))
    assert [r.centroid for r in scene.regions] == [pytest.approx((65.0, 30.0), abs=1.5)]


def test_a_bump_where_the_map_sees_nothing_is_kept_out_of_the_plans_at_once() -> None:
    """The base (radius 9) stopped collided at (40, 70) facing +x on floor the scans saw
    free: the disc of 3 in centred 12 in ahead, at (52, 70), is furniture of the
    navigator's map from then on (inflated by the base: no plan through (52, 70)),
    and the robot's own place stays plannable (it is 12 in away: the inflation's edge)."""
    seen, scans, navigator = perception()
    look_from(seen, scans, (30.0, 70.0), (90.0, 70.0))
    assert navigator.vision_map.is_free(52.0, 70.0)
    kept = seen.bumped(Pose(40.0, 70.0, 0.0))
    assert kept == pytest.approx((52.0, 70.0))
    assert not navigator.vision_map.is_free(52.0, 70.0) and not navigator.vision_map.is_free(45.0, 70.0)
    assert navigator.plan(Pose(40.0, 70.0, 180.0), Pose(30.0, 40.0, 0.0)).found
    scene = seen.scene(seen.look().result())  # and it stays so after the next look
    assert scene.furniture is not None and not navigator.vision_map.is_free(52.0, 70.0)


def test_a_bump_the_map_explains_is_not_kept() -> None:
    """Stopped facing the box (at 57-63, 27-33) or a wall: the map holds what the base
    met, so nothing is kept out (a disc there would close the box's positions)."""
    seen, scans, navigator = perception()
    look_from(seen, scans, (30.0, 70.0), (90.0, 70.0))
    assert seen.bumped(Pose(60.0, 50.0, 270.0)) is None  # 12 in ahead: (60, 38), 5 in from the box
    assert seen.bumped(Pose(30.0, 12.0, 270.0)) is None  # 12 in ahead: (30, 0), the wall
    assert seen.bumped(Pose(40.0, 70.0, 0.0)) is not None


def test_no_view_from_inside_an_obstacle_of_the_map_is_stranded_not_mapped() -> None:
    """The robot put inside the box (60, 30) of its own map, 10 in from free floor once
    inflated: no view can be reached, and the perception says why; from the open floor
    a view is offered and nothing is stranded."""
    seen, scans, _ = perception()
    look_from(seen, scans, (30.0, 70.0), (90.0, 70.0))
    assert seen.next_view(Pose(90.0, 70.0, 0.0)) is not None and seen.stranded is None
    assert seen.next_view(Pose(60.0, 30.0, 0.0)) is None
    assert seen.stranded == ("no view can be reached: the robot at (60, 30) stands in an obstacle of its map, "
                             "more than 4 in from free floor")
