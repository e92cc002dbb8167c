"""Moving obstacles drawn into the planner's map (Navigator.avoid): the next plan goes
around the disc, the map's key changes with it, and a new image drops it."""

from __future__ import annotations

import json
import math

import pytest

from hero_driver.sim.world import SimWorld
from planner import Navigator, Pose
from planner.vision_map import build_vision_map, draw_discs


@pytest.fixture(scope="module")
def empty_room(tmp_path_factory: pytest.TempPathFactory) -> SimWorld:
    path = tmp_path_factory.mktemp("avoid") / "empty.json"
    path.write_text(json.dumps({"room": {"width_in": 240, "depth_in": 180},
                                "robot": {"x_in": 30, "y_in": 90, "heading_deg": 0}, "objects": []}))
    return SimWorld(path)


def _clearance(path: tuple[Pose, ...], start: Pose, centre: tuple[float, float]) -> float:
    """The least distance from ``centre`` to the polyline start -> path."""
    points = [(start.x_in, start.y_in)] + [(p.x_in, p.y_in) for p in path]
    best = math.inf
    for (ax, ay), (bx, by) in zip(points, points[1:]):
        dx, dy = bx - ax, by - ay
        t = max(0.0, min(1.0, ((centre[0] - ax) * dx + (centre[1] - ay) * dy) / (dx * dx + dy * dy or 1.0)))
        best = min(best, math.hypot(ax + t * dx - centre[0], ay + t * dy - centre[1]))
    return best


def test_a_plan_goes_around_a_drawn_disc_until_the_next_image(empty_room: SimWorld) -> None:
    nav = Navigator(empty_room.profile.robot)
    image = empty_room.camera()
    nav.observe(image)
    start, goal = Pose(30.0, 90.0, 0.0), Pose(200.0, 90.0, 0.0)
    straight = nav.plan(start, goal)
    assert straight.found and _clearance(straight.path, start, (110.0, 90.0)) < 1.0  # straight through
    plain_key = nav.vision_map.key
    nav.avoid(((110.0, 90.0, 12.0),))
    around = nav.plan(start, goal)
    assert around.found and nav.avoided == ((110.0, 90.0, 12.0),) and nav.vision_map.key != plain_key
    # the base (9 in) never overlaps the 12 in disc: its centre keeps 21 in away
    assert _clearance(around.path, start, (110.0, 90.0)) >= 21.0
    assert not nav.vision_map.is_free(110.0, 90.0 + 20.0)
    nav.observe(image)
    assert nav.avoided == () and nav.vision_map.key == plain_key


def test_draw_discs_marks_the_pixels_whose_centres_lie_within_the_radius(empty_room: SimWorld) -> None:
    nav = Navigator(empty_room.profile.robot)
    scene = nav.observe(empty_room.camera())
    drawn = draw_discs(scene, ((120.0, 90.0, 5.0),)) & ~(scene.furniture | scene.objects)
    ipp = scene.image.inches_per_pixel
    assert drawn.sum() == pytest.approx(math.pi * 25.0 / ipp ** 2, rel=0.15)
    assert build_vision_map(scene, empty_room.profile.robot.geometry, ((120.0, 90.0, 5.0),)).occupied[drawn].all()
