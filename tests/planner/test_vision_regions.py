"""Vision on synthetic images whose answers are known by hand."""

from __future__ import annotations

import math

import numpy as np
import pytest

from camera_model.image import CameraImage
from planner import look
from planner.geometry import angle_between
from tests.planner.drawing import IPP, OBJECT, WALL, Canvas

PIXEL_AREA = IPP * IPP
HALF_PIXEL = IPP / 2 + 0.05


def drawn(canvas: Canvas) -> int:
    """How many object pixels the canvas holds."""
    return int(np.count_nonzero(canvas.pixels == OBJECT))


def only_region(canvas: Canvas):
    scene = look(canvas.image())
    assert len(scene.regions) == 1
    return scene.regions[0]


@pytest.mark.parametrize("yaw", [0.0, 30.0, 75.0, 120.0])
def test_box_centroid_size_pixels_and_axis(yaw):
    canvas = Canvas().rect(60.0, 50.0, 9.0, 4.0, yaw)
    region = only_region(canvas)
    assert math.dist(region.centroid, (60.0, 50.0)) < HALF_PIXEL
    assert region.pixel_count == drawn(canvas)
    # A pixel shows the box when the box covers half of it: counts track the true area.
    assert region.pixel_count * PIXEL_AREA == pytest.approx(9 * 4, rel=0.15)
    assert not region.round
    # A box is symmetric: either end of its major axis is the half with more pixels.
    assert angle_between(region.orientation_deg % 180, yaw % 180) < 4.0 or \
        angle_between(region.orientation_deg % 180, yaw % 180) > 176.0
    # Extents take the outermost vertices: within a pixel of the true size.
    assert region.length_in == pytest.approx(9.0, abs=IPP)
    assert region.width_in == pytest.approx(4.0, abs=IPP)


@pytest.mark.parametrize("yaw", [0.0, 40.0, 200.0, 290.0])
def test_orientation_points_into_the_half_with_more_pixels(yaw):
    # A wedge whose wide end is at local -x: the wide half has more pixels, so the
    # orientation is the wedge's local 180°.
    c, s = math.cos(math.radians(yaw)), math.sin(math.radians(yaw))
    local = [(-8.0, -3.0), (8.0, -0.5), (8.0, 0.5), (-8.0, 3.0)]
    canvas = Canvas().polygon([(100 + c * a - s * b, 80 + s * a + c * b) for a, b in local], 220)
    region = only_region(canvas)
    assert angle_between(region.orientation_deg, yaw + 180.0) < 4.0


def test_upright_cup_is_round_without_orientation():
    canvas = Canvas().disc(40.0, 120.0, 1.65)
    region = only_region(canvas)
    assert region.round and region.orientation_deg is None
    assert region.reference_axis_deg == 0.0
    assert math.dist(region.centroid, (40.0, 120.0)) < HALF_PIXEL
    assert region.pixel_count == drawn(canvas)


def test_large_disc_is_round_but_large_square_is_not():
    scene = look(Canvas().disc(60.0, 60.0, 8.0).rect(150.0, 60.0, 10.0, 10.0, 20.0).image())
    disc, square = scene.regions
    assert disc.round and not square.round
    # The square's axis follows one of its sides.
    assert angle_between(square.orientation_deg % 90, 20.0) < 4.0


def test_robot_pose_and_nothing_else_from_the_robot():
    scene = look(Canvas().robot(120.0, 90.0, 35.0).image())
    assert scene.regions == ()
    assert scene.robot is not None
    assert math.dist((scene.robot.x_in, scene.robot.y_in), (120.0, 90.0)) < 0.5
    assert angle_between(scene.robot.heading_deg, 35.0) < 5.0
    assert not scene.furniture[60:-60, 60:-60].any() and not scene.objects.any()


def test_furniture_is_an_obstacle_not_a_region():
    scene = look(Canvas().rect(120.0, 90.0, 30.0, 20.0, 0.0, WALL).disc(40.0, 40.0, 2.0).image())
    assert len(scene.regions) == 1
    row, col = (int(v) for v in scene.image.to_pixel(120.0, 90.0))
    assert scene.furniture[row, col]
    assert scene.robot is None


def test_noise_does_not_change_the_answer():
    clean = Canvas().rect(60.0, 50.0, 9.0, 4.0, 30.0).disc(150.0, 100.0, 1.65).robot(200.0, 40.0, 90.0)
    noisy = Canvas().rect(60.0, 50.0, 9.0, 4.0, 30.0).disc(150.0, 100.0, 1.65).robot(200.0, 40.0, 90.0).noisy(3)
    a, b = look(clean.image()), look(noisy.image())
    assert [r.pixel_count for r in a.regions] == [r.pixel_count for r in b.regions]
    assert a.robot == b.robot


def test_pixel_count_tells_pushed_from_changed():
    # A 12 oz soda can: upright 2.6 in across, lying 4.8 x 2.6 in.
    upright = only_region(Canvas().disc(80.0, 80.0, 1.3))
    pushed = only_region(Canvas().disc(83.1, 79.7, 1.3))
    knocked_over = only_region(Canvas().rect(80.0, 80.0, 4.8, 2.6, 30.0))
    assert abs(pushed.pixel_count - upright.pixel_count) <= 0.25 * upright.pixel_count
    assert knocked_over.pixel_count >= 1.4 * upright.pixel_count


def test_regions_are_sorted_and_polygons_counter_clockwise():
    scene = look(Canvas().disc(150.0, 40.0, 2.0).rect(50.0, 100.0, 9.0, 4.0, 10.0).disc(100.0, 150.0, 1.0).image())
    xs = [r.centroid[0] for r in scene.regions]
    assert xs == sorted(xs)
    for region in scene.regions:
        p = region.polygon_array()
        area = 0.5 * np.sum(p[:, 0] * np.roll(p[:, 1], -1) - np.roll(p[:, 0], -1) * p[:, 1])
        assert area > 0


def test_polygon_lies_on_the_true_outline():
    region = only_region(Canvas().rect(60.3, 50.3, 12.0, 6.0, 0.0))
    p = region.polygon_array()
    assert p[:, 0].min() == pytest.approx(54.3, abs=HALF_PIXEL)
    assert p[:, 0].max() == pytest.approx(66.3, abs=HALF_PIXEL)
    assert p[:, 1].min() == pytest.approx(47.3, abs=HALF_PIXEL)
    assert p[:, 1].max() == pytest.approx(53.3, abs=HALF_PIXEL)


@pytest.mark.parametrize("pixels", [np.zeros((0, 0), np.uint8), np.zeros((3,), np.uint8)])
def test_empty_image_is_refused(pixels):
    with pytest.raises(ValueError, match="non-empty"):
        look(CameraImage(pixels, IPP, 0.0, 0.0))


def test_bad_scale_is_refused():
    with pytest.raises(ValueError, match="inches_per_pixel"):
        look(CameraImage(np.zeros((4, 4), np.uint8), float("nan"), 0.0, 0.0))


def test_fisheye_without_camera_matrix_is_refused():
    with pytest.raises(ValueError, match="camera_matrix"):
        look(CameraImage(np.zeros((4, 4), np.uint8), IPP, 0.0, 0.0, fisheye=(0.05, 0.01, 0.0, 0.0)))


def test_content_key_tells_images_apart():
    a, b = Canvas().disc(50.0, 50.0, 2.0).image(), Canvas().disc(50.0, 50.0, 2.0).image()
    c = Canvas().disc(51.0, 50.0, 2.0).image()
    assert a.content_key() == b.content_key() != c.content_key()
