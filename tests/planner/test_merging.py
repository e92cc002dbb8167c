"""Objects that came to touch since the last image (planner/merging.py, docs/planner.md
"Clutter"): one image shows one region no different from a bigger object; the image
before, where they stood apart, makes it a cluster. A lone object, pushed, turned or
left alone beside a neighbour's empty place, never is."""

from __future__ import annotations

import dataclasses

import pytest
from hypothesis import example, given, settings
from hypothesis import strategies as st

from hero_driver.sim.noise import NoiseConfig
from hero_driver.sim.world import SimWorld
from planner import Navigator, Pose, Region, Scene, look
from planner.merging import flag_merged, within_push
from robot_profile import load_profile
from tests.planner.test_vision_clutter import CATALOGUE, floor

BASE_RADIUS_IN = load_profile().robot.geometry.base_radius_in
Placed = tuple[str, float, float, float]


def scene(*objects: Placed, noise: NoiseConfig | None = None, seed: int = 0) -> Scene:
    return look(SimWorld(floor(*objects), seed, noise=noise).camera())


# Seen 1.5 in apart, then pushed to 0.1-0.3 in apart (the second object moved 1.2-1.4 in,
# as a failed grasp pushes): pairs the clutter study met merged into one region that one
# image calls neither two objects nor a cluster (nearly convex, no pinch to cut at).
PUSHED_TOGETHER = {
    "2 in box and upright bottle": lambda g: [("closed-box-2x2x2/upright", 100, 90, 0),
                                              ("soda-bottle-16oz/upright", 102.3 + g, 90, 0)],
    "upright and upside-down tumbler": lambda g: [("tumbler-20oz/upright", 100, 90, 0),
                                                  ("tumbler-20oz/upside-down", 103.6 + g, 90, 0)],
    "lying bottle along a 10 in box": lambda g: [("closed-box-10x10x10/upright", 100, 90, 0),
                                                 ("soda-bottle-16oz/lying", 100, 96.3 + g, 0)],
}
TOUCHING_GAP_IN = {"2 in box and upright bottle": 0.1, "upright and upside-down tumbler": 0.1,
                   "lying bottle along a 10 in box": 0.3}


@pytest.mark.parametrize("pair", sorted(PUSHED_TOGETHER))
def test_objects_pushed_together_are_one_region_that_the_image_before_makes_a_cluster(pair: str) -> None:
    apart = scene(*PUSHED_TOGETHER[pair](1.5))
    touching = scene(*PUSHED_TOGETHER[pair](TOUCHING_GAP_IN[pair]))
    assert len(apart.regions) == 2 and len(touching.regions) == 1 and not touching.regions[0].cluster
    merged = flag_merged(apart, touching, BASE_RADIUS_IN)
    assert [r.cluster for r in merged.regions] == [True]
    assert merged.regions[0] == dataclasses.replace(touching.regions[0], cluster=True)  # nothing else changed
    assert flag_merged(None, touching, BASE_RADIUS_IN) is touching  # no image before: nothing to tell by


def test_a_cluster_stays_one_until_an_object_is_taken_out_of_it() -> None:
    pair = PUSHED_TOGETHER["upright and upside-down tumbler"]
    merged = flag_merged(scene(*pair(1.5)), scene(*pair(0.1)), BASE_RADIUS_IN)
    again = flag_merged(merged, scene(*pair(0.1), seed=1), BASE_RADIUS_IN)  # the same pair, seen anew
    assert [r.cluster for r in again.regions] == [True]
    # the upright tumbler grasped and gone: its neighbour is about half the pair's area
    left = flag_merged(again, scene(pair(0.1)[1]), BASE_RADIUS_IN)
    assert [r.cluster for r in left.regions] == [False]


@pytest.mark.parametrize("pair", sorted(PUSHED_TOGETHER))
def test_a_cluster_pushed_apart_is_two_objects_again(pair: str) -> None:
    """One of the two pushed 1.2-1.4 in off the other: a region no earlier one became
    turns up within a push of the cluster, so neither piece inherits the flag."""
    merged = flag_merged(scene(*PUSHED_TOGETHER[pair](1.5)), scene(*PUSHED_TOGETHER[pair](TOUCHING_GAP_IN[pair])),
                         BASE_RADIUS_IN)
    apart = flag_merged(merged, scene(*PUSHED_TOGETHER[pair](1.5), seed=1), BASE_RADIUS_IN)
    assert [r.cluster for r in apart.regions] == [False, False]


# Seen apart (the bottle pushed 3.3 in off the box), then the box pushed 4.1 in into
# the bottle, where the clutter study's floor 1 at 1 in had them. The box's centroid
# ends 4.6 in from the pair's (4 + 10 pixels, then 16), beyond a push of its outline,
# so it has no successor.
BOX_APART = [("closed-box-2x2x2/upright", 46.9, 40.4, 0.0), ("soda-bottle-16oz/upright", 52.3, 41.6, 0.0)]
BOX_PUSHED_IN = [("closed-box-2x2x2/upright", 50.0, 43.1, 0.0), ("soda-bottle-16oz/upright", 52.3, 41.6, 0.0)]


@pytest.mark.parametrize(("robot", "cluster"), [
    (Pose(34.0, 28.7, 45.0), True),  # 17 in off, as in the study: the box went, the bottle's region grew by its area
    (Pose(40.0, 34.0, 45.0), False),  # 9.4 in from where the box was, within 9 + 2 in: hidden, not pushed
])
def test_an_object_pushed_further_than_a_push_into_its_neighbour_makes_a_cluster(robot: Pose, cluster: bool) -> None:
    before, after = scene(*BOX_APART), scene(*BOX_PUSHED_IN)
    assert len(before.regions) == 2 and len(after.regions) == 1
    box = min(before.regions, key=lambda r: r.pixel_count)
    assert not within_push(after.regions[0], box.centroid)  # beyond the short reach: only the long push joins them
    after = dataclasses.replace(after, robot=robot)
    assert [r.cluster for r in flag_merged(before, after, BASE_RADIUS_IN).regions] == [cluster]


def test_a_neighbour_left_alone_when_an_object_further_than_a_push_was_taken_is_not_a_cluster() -> None:
    """The box taken away from beside the bottle (nothing within a push): the bottle's
    region does not grow by the box's area, so it stays one object."""
    before, after = scene(*BOX_APART), scene(BOX_APART[1])
    assert [r.cluster for r in flag_merged(before, after, BASE_RADIUS_IN).regions] == [False]


def test_an_object_beside_a_neighbour_taken_away_is_not_a_cluster() -> None:
    """The 2 in box 1.5 in from the 10 in box's side, then grasped: its centroid (2.5 in
    off the big box's outline) is within a push of the big box, which stays one object:
    its region (156 pixels) is short of the pair's 156 + half the small box's 6."""
    big, small = ("closed-box-10x10x10/upright", 100, 90, 0), ("closed-box-2x2x2/upright", 100, 97.5, 0)
    before, after = scene(big, small), scene(big)
    assert len(before.regions) == 2
    assert [r.cluster for r in flag_merged(before, after, BASE_RADIUS_IN).regions] == [False]


def _square(x: float, y: float, half: float, pixels: int) -> Region:
    polygon = ((x - half, y - half), (x + half, y - half), (x + half, y + half), (x - half, y + half))
    return Region(polygon, (x, y), pixels, None, True, 2 * half, 2 * half, pixels * 0.64, 1.0)


def _scene(regions: tuple[Region, ...], robot: Pose | None) -> Scene:
    return Scene(image=None, regions=regions, robot=robot, furniture=None, objects=None)  # type: ignore[arg-type]


@pytest.mark.parametrize(("robot", "cluster"), [
    (Pose(120.0, 90.0, 180.0), True),  # 14 in from the nearer piece: further than its base radius (9) + 2 in
    (Pose(103.0, 97.0, 270.0), False),  # 7 in from the gap between them, within 9 + 2 in: it hid the gap
    (None, True),  # no robot in the image before: nothing hid anything
])
def test_two_pieces_the_robot_stood_between_are_not_two_objects(robot: Pose | None, cluster: bool) -> None:
    """Two 12-pixel pieces 6 in apart, then one 26-pixel region over both (12 + 6 <= 26)."""
    before = _scene((_square(100.0, 90.0, 1.5, 12), _square(106.0, 90.0, 1.5, 12)), robot)
    now = _scene((Region(((98.5, 88.5), (107.5, 88.5), (107.5, 91.5), (98.5, 91.5)), (103.0, 90.0), 26, 0.0,
                         False, 9.0, 3.0, 26 * 0.64, 3.0),), None)
    assert [r.cluster for r in flag_merged(before, now, BASE_RADIUS_IN).regions] == [cluster]


LONE = sorted(e for e in CATALOGUE if e.endswith(("upright", "lying", "upside-down")))


@pytest.mark.slow
@settings(max_examples=25, deadline=None)
@given(entry=st.sampled_from(LONE), yaw=st.floats(0.0, 360.0), turn=st.floats(-90.0, 90.0),
       dx=st.floats(-2.5, 2.5), dy=st.floats(-2.5, 2.5))
def test_a_lone_object_pushed_and_turned_is_never_a_cluster(entry: str, yaw: float, turn: float,
                                                            dx: float, dy: float) -> None:
    before, after = scene((entry, 120.0, 90.0, yaw)), scene((entry, 120.0 + dx, 90.0 + dy, yaw + turn))
    assert [r.cluster for r in flag_merged(before, after, BASE_RADIUS_IN).regions] == [False]


PAPER = NoiseConfig.preset("paper")


@settings(max_examples=25, deadline=None)
@given(entry=st.sampled_from(LONE), yaw=st.floats(0.0, 360.0), seed=st.integers(0, 1000),
       x=st.floats(20.0, 220.0), y=st.floats(60.0, 160.0))
@example(entry="magazine-box-9x4x7/upright", yaw=35.0, seed=13, x=36.0, y=60.0).xfail(
    raises=AssertionError, reason="known limit: the fish-eye's noise notches this box's outline to 0.715 of its hull "
    "(2 of 30 seeds at this corner pose, none of 700 random poses): one image calls it a cluster")
def test_a_lone_object_through_the_fish_eye_camera_is_not_a_cluster(entry: str, yaw: float, seed: int,
                                                                     x: float, y: float) -> None:
    """The `paper` preset's fish-eye undistortion roughens outlines (a 2 in box fills
    as little as 0.64 of its hull, a lying bottle 0.75): one image calls a region a
    cluster only when it is clearly far from convex (planner/vision.py). Anywhere on the
    floor: the distortion grows towards the image's edges. (Rarely, 2 of 400 lying
    tumblers, the roughened outline is cut in two at a false pinch: not a cluster either.)"""
    found = scene((entry, x, y, yaw), noise=PAPER, seed=seed).regions
    assert found and not any(r.cluster for r in found)


def test_the_navigator_tells_the_next_plans_a_merge_happened() -> None:
    pair = PUSHED_TOGETHER["lying bottle along a 10 in box"]
    nav = Navigator(load_profile().robot)
    for gap, clusters in ((1.5, [False, False]), (0.3, [True]), (0.3, [True])):
        world = SimWorld(floor(*pair(gap)), 0)
        assert [r.cluster for r in nav.observe(world.camera()).regions] == clusters
        assert nav.scene.regions == nav.observe(world.camera()).regions  # the same image: the same answer
