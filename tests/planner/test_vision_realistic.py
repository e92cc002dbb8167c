"""Vision on realistic images: every lab object found where it is, at several poses,
within the stated errors; the robot's pose; pixel counts a side-effect check can
trust; the empty floor taken from an image that had objects on it."""

from __future__ import annotations

import dataclasses
import math
from pathlib import Path

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from camera_model.image import CameraImage
from hero_driver.sim.worldfile import Placement
from planner.segmentation import Camera, load_camera, save_camera, segment
from planner.vision import look
from tests.planner.vision_truth import ROBOT_PARKED, lab_at, lab_camera, measure, overhead, pixel_spread

POSES = len(ROBOT_PARKED) + 1  # the last one with the robot right at the magazine box


@pytest.fixture(scope="module")
def camera() -> Camera:
    return lab_camera()


@pytest.fixture(scope="module")
def realistic(camera: Camera):
    return measure("realistic", POSES, camera)


def test_every_object_is_found_at_every_pose(realistic) -> None:
    assert len(realistic) == 7 * POSES
    assert all(s.found for s in realistic)


def test_objects_are_located_within_half_an_inch(realistic) -> None:
    """The calibration maps the floor to ~0.1 in (0.3 in RMS at the marker corners) and
    a region's centroid averages its pixels (0.8 in each), so its error stays well
    under a pixel; measured: mean 0.2 in, max 0.41 in (BENCHMARKS.md)."""
    errors = [s.location_error_in for s in realistic]
    assert float(np.mean(errors)) < 0.35
    assert max(errors) < 0.7


def test_elongated_objects_are_oriented_within_a_few_degrees(realistic) -> None:
    """Objects of 25 pixels or more (the 9 x 4 box is 11 x 5 pixels): a third of a
    pixel of outline error at an end turns the axis by atan(0.33 / 5.6) = 3.4°;
    measured max 3-4°. Smaller objects show no usable axis (vision.py)."""
    errors = [s.orientation_error_deg for s in realistic
              if s.orientation_error_deg is not None and s.pixel_count >= 25]
    assert len(errors) >= 3 * POSES
    assert max(errors) < 6.0


def test_pixel_counts_keep_the_side_effect_check_meaningful(realistic) -> None:
    """A pushed object must not read as "changed" (count change over 25 %), a knocked
    over one must: the soda bottle upright against lying."""
    assert max(pixel_spread(realistic).values()) < 0.25
    upright = [s.pixel_count for s in realistic if s.entry_id == "soda-bottle-16oz/upright"]
    lying = [s.pixel_count for s in realistic if s.entry_id == "soda-bottle-16oz/lying"]
    assert min(lying) > 2 * max(upright)


def test_the_robot_pose_is_read_from_its_paint(camera: Camera) -> None:
    for pose in range(POSES):
        sim = lab_at(pose)
        robot = look(overhead(sim, "realistic"), camera).robot
        assert robot is not None
        assert math.hypot(robot.x_in - sim.pose.x_in, robot.y_in - sim.pose.y_in) < 0.6
        off = (robot.heading_deg - sim.pose.heading_deg) % 360
        assert min(off, 360 - off) < 4.0


def test_objects_on_the_floor_when_calibrating_are_still_seen(camera: Camera) -> None:
    """The calibration image had all seven objects on it; painted out of the empty
    floor, they are found in that very image, and nothing else is (no shadow, texture
    or lighting gradient region)."""
    scene = look(overhead(lab_at(0), "realistic"), camera)
    assert len(scene.regions) == 7


def test_a_change_of_exposure_changes_nothing(camera: Camera) -> None:
    image = overhead(lab_at(1), "realistic")
    brighter = CameraImage(np.clip(image.pixels.astype(float) * 1.2, 0, 255).astype(np.uint8),
                             image.inches_per_pixel, image.origin_x_in, image.origin_y_in)
    before, after = look(image, camera).regions, look(brighter, camera).regions
    assert len(before) == len(after) == 7
    for a, b in zip(before, after):
        assert math.hypot(a.centroid[0] - b.centroid[0], a.centroid[1] - b.centroid[1]) < 0.3


def test_furniture_and_walls_are_obstacles_and_the_floor_is_free(camera: Camera) -> None:
    scene = look(overhead(lab_at(0), "realistic"), camera)

    def at(x: float, y: float) -> bool:
        row, col = scene.image.to_pixel(x, y)
        return bool(scene.furniture[round(row), round(col)])

    assert at(200.0, 150.0) and at(30.0, 172.0) and at(-3.0, 90.0)  # table, cabinet, wall
    assert not at(120.0, 80.0) and not at(10.0, 90.0)  # bare floor, a printed marker


def test_the_camera_file_round_trips_and_says_what_is_missing(camera: Camera, tmp_path: Path) -> None:
    pixels = overhead(lab_at(0), "realistic").pixels
    save_camera(camera.calibration, camera.calibration.rectify(pixels), tmp_path / "r1.json")
    again = load_camera(tmp_path / "r1.json")
    image = overhead(lab_at(2), "realistic")
    assert [r.centroid for r in look(image, again).regions] == [r.centroid for r in look(image, camera).regions]
    (tmp_path / "r1.floor.png").unlink()
    with pytest.raises(ValueError, match=r"r1.floor.png: missing or not an image"):
        load_camera(tmp_path / "r1.json")


def test_an_image_of_another_size_is_one_clear_error(camera: Camera) -> None:
    small = CameraImage(np.zeros((100, 120), np.uint8), 0.5, 0.0, 50.0)
    with pytest.raises(ValueError, match="camera image is 120x100 pixels, the calibration's 504x384"):
        look(small, camera)
    flat = camera.calibration.rectify(overhead(lab_at(0), "realistic").pixels)
    wrong = CameraImage(flat.pixels[:-1], flat.inches_per_pixel, flat.origin_x_in, flat.origin_y_in)
    with pytest.raises(ValueError, match="on the floor grid"):
        segment(wrong, camera.empty_floor)



@settings(max_examples=15, deadline=None)
@given(entry=st.sampled_from(["closed-box-2x2x2/upright", "soda-bottle-16oz/lying", "magazine-box-9x4x7/upright",
                              "tumbler-20oz/upright"]),
       x=st.floats(50, 200), y=st.floats(30, 125), yaw=st.floats(0, 180))
def test_one_object_anywhere_on_the_open_floor_is_found_where_it_is(camera: Camera, entry: str, x: float, y: float,
                                                                   yaw: float) -> None:
    """Whatever the light there: alone in the lab (robot at its start), within 0.7 in."""
    sim = lab_at(0)
    sim.load(dataclasses.replace(sim.spec, objects=(Placement(entry, x, y, yaw),)), 0)
    regions = look(overhead(sim, "realistic"), camera).regions
    assert len(regions) == 1
    assert math.hypot(regions[0].centroid[0] - x, regions[0].centroid[1] - y) < 0.7
