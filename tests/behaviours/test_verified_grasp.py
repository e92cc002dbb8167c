"""``GraspVerified?`` (behaviours/verified_grasp.py): which region of the image after a
grasp is the object still on the floor. The whole node runs in the episode fixtures
(tests/executive/test_vendor_mistakes.py: a finger stuck at "held")."""

from __future__ import annotations

from behaviours.verified_grasp import still_on_floor
from planner import Region
from planner.geometry import Pose

BASE_RADIUS_IN = 9.0
ROBOT = Pose(100.0, 30.0, 90.0)  # 20 in from the object at (100, 50)


def _region(x: float, y: float, pixels: int = 200, length_in: float = 4.0) -> Region:
    half = length_in / 2
    return Region(((x - half, y - half), (x + half, y - half), (x + half, y + half), (x - half, y + half)),
                  (x, y), pixels, 0.0, False, length_in, length_in)


LAY = _region(100.0, 50.0)  # a 4 in object, 200 pixels, where the grasp was made


def _still(*regions: Region, others: list[tuple[float, float]] | None = None, robot: Pose = ROBOT) -> Region | None:
    return still_on_floor(LAY, regions, others or [], robot, BASE_RADIUS_IN)


def test_nothing_where_the_object_lay_means_it_left_the_floor() -> None:
    assert _still() is None
    assert _still(_region(160.0, 50.0)) is None  # another object, far away


def test_the_object_seen_again_in_place_or_pushed_is_still_on_the_floor() -> None:
    in_place = _region(100.3, 50.2, pixels=190)
    assert _still(in_place) is in_place
    pushed = _region(104.9, 50.0)  # outlines 4 in across: (4 + 4) / 2 + 1 = 5 in between centres at most
    assert _still(pushed) is pushed
    assert _still(_region(105.1, 50.0)) is None


def test_knocked_over_it_is_found_by_its_new_length() -> None:
    lying = _region(107.0, 50.0, pixels=320, length_in=10.0)  # (4 + 10) / 2 + 1 = 8 in reach
    assert _still(lying) is lying


def test_a_region_a_quarter_smaller_is_what_is_left_of_a_cluster() -> None:
    assert _still(_region(100.0, 50.0, pixels=150)) is not None  # 150 = 0.75 x 200: the object
    assert _still(_region(100.0, 50.0, pixels=149)) is None  # less: the grasp took something away


def test_another_known_object_or_the_robot_itself_does_not_count() -> None:
    neighbour = _region(103.0, 50.0)
    assert _still(neighbour, others=[(103.5, 50.0)]) is None  # within a push (1 in) of a known object
    assert _still(neighbour, others=[(104.5, 50.0)]) is neighbour
    near = Pose(100.0, 38.0, 90.0)  # 12 in from where the object lay
    arm = _region(100.0, 46.5)  # 3.5 in from there, 8.5 in from the robot's centre: over its base
    assert _still(arm, robot=near) is None
    assert _still(arm) is arm  # the robot 20 in away: the object
