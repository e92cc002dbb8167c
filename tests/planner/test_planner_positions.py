"""Learner positions <-> robot poses (docs/conventions.md), and their round trip."""

from __future__ import annotations

import math

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from planner import Pose, Region, face_distance_in, look, pose_for_position, position_of
from robot_profile import load_profile
from planner.geometry import angle_between
from tests.planner.drawing import Canvas, rect_corners

HERO = load_profile().robot.geometry  # the shipped profile's: base radius 9 in, sonar 11 in ahead of the centre


def box_region(x: float, y: float, length: float, width: float, yaw: float) -> Region:
    return Region(polygon=tuple(rect_corners(x, y, length, width, yaw)), centroid=(x, y), pixel_count=100,
                  orientation_deg=yaw % 360, round=False, length_in=length, width_in=width)


def disc_region(x: float, y: float, r: float) -> Region:
    polygon = tuple((x + r * math.cos(a), y + r * math.sin(a)) for a in np.linspace(0, 2 * math.pi, 48, endpoint=False))
    return Region(polygon=polygon, centroid=(x, y), pixel_count=20, orientation_deg=None, round=True,
                  length_in=2 * r, width_in=2 * r)


def test_box_face_on_positions_by_hand():
    # A 10 x 4 box along +30°: at orientation 0 the face is 5 in out, at 90° it is 2 in.
    box = box_region(100.0, 80.0, 10.0, 4.0, 30.0)
    pose = pose_for_position(box, 6.0, 0.0, HERO)
    ux, uy = math.cos(math.radians(30)), math.sin(math.radians(30))
    assert pose.x_in == pytest.approx(100 + (5 + 6 + 11) * ux)
    assert pose.y_in == pytest.approx(80 + (5 + 6 + 11) * uy)
    assert pose.heading_deg == pytest.approx(210.0)
    side = pose_for_position(box, 16.0, 90.0, HERO)
    assert math.dist((side.x_in, side.y_in), (100, 80)) == pytest.approx(2 + 16 + 11)
    assert side.heading_deg == pytest.approx(300.0)


def test_round_region_uses_world_x_as_axis():
    cup = disc_region(50.0, 50.0, 1.65)
    pose = pose_for_position(cup, 24.0, 90.0, HERO)
    assert pose.x_in == pytest.approx(50.0, abs=1e-9)
    assert pose.y_in == pytest.approx(50.0 + 1.65 + 24 + 11, abs=0.01)
    assert pose.heading_deg == pytest.approx(270.0)


def test_sonar_distance_to_a_vision_region_matches_the_drawn_box():
    region = look(Canvas().rect(100.0, 80.0, 9.0, 4.0, 20.0).image()).regions[0]
    for orientation in (0.0, 90.0, 180.0, 270.0):
        pose = pose_for_position(region, 6.0, orientation, HERO)
        sonar = np.array([pose.x_in, pose.y_in]) + 11.0 * np.array(
            [math.cos(math.radians(pose.heading_deg)), math.sin(math.radians(pose.heading_deg))])
        # The true face is 4.5 in (ends) or 2 in (sides) from the centre.
        true_face = 4.5 if orientation in (0.0, 180.0) else 2.0
        assert math.dist(sonar, (100.0, 80.0)) - true_face == pytest.approx(6.0, abs=0.6)


regions = st.one_of(
    st.builds(box_region, st.floats(20, 200), st.floats(20, 150), st.floats(2, 12), st.floats(2, 12),
              st.floats(0, 360)),
    st.builds(disc_region, st.floats(20, 200), st.floats(20, 150), st.floats(1, 4)),
)


@pytest.mark.slow
@settings(max_examples=200, deadline=None)
@given(region=regions, distance=st.floats(0, 127), orientation=st.floats(0, 359.999))
def test_position_round_trip(region, distance, orientation):
    pose = pose_for_position(region, distance, orientation, HERO)
    d, theta = position_of(region, pose, HERO)
    assert d == pytest.approx(distance, abs=1e-6)
    assert angle_between(theta, orientation) < 1e-6
    # The base faces the centroid.
    bearing = math.degrees(math.atan2(region.centroid[1] - pose.y_in, region.centroid[0] - pose.x_in))
    assert angle_between(pose.heading_deg, bearing) < 1e-6


@settings(max_examples=100, deadline=None)
@given(region=regions, orientation=st.floats(0, 360))
def test_face_distance_reaches_the_outline(region, orientation):
    r_face = face_distance_in(region, orientation)
    assert 0 < r_face <= max(region.length_in, region.width_in)


@pytest.mark.parametrize("bad", [(math.nan, 0.0), (6.0, math.inf)])
def test_non_finite_position_is_refused(bad):
    with pytest.raises(ValueError, match="finite"):
        pose_for_position(box_region(50, 50, 9, 4, 0), *bad, HERO)


def test_non_finite_pose_is_refused():
    with pytest.raises(ValueError, match="not finite"):
        position_of(box_region(50, 50, 9, 4, 0), Pose(math.nan, 0.0, 0.0), HERO)
