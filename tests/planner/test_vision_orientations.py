"""Vision's regions as training footprints: faces where the object's faces are.

Training orientations are the learner's (``learner.training.stage``, docs/method.md §4 phase 1):
it clusters the face normals of footprints given in each object's own frame. Here the
planner's side of that contract: a region's polygon, turned into its reference-axis
frame, puts a box's faces along and across the axis, and a round region has none.
"""

from __future__ import annotations

import math

import pytest

from learner.position import Position
from learner.training.inputs import TrainingObject
from learner.training.stage import face_normals, training_orientations
from planner import Region, look
from planner.geometry import angle_between
from tests.planner.drawing import Canvas


def as_training_object(region: Region, name: str = "seen") -> TrainingObject:
    """The region's polygon about its centroid, +x along its reference axis."""
    a = math.radians(region.reference_axis_deg)
    cx, cy = region.centroid
    local = tuple(((x - cx) * math.cos(a) + (y - cy) * math.sin(a), -(x - cx) * math.sin(a) + (y - cy) * math.cos(a))
                  for x, y in region.polygon)
    return TrainingObject(name, "any", Position(6.0, None), local, region.round)


def assert_orientations(found: list[float], expected: list[float], tolerance: float = 8.0) -> None:
    """A face within ``tolerance``: the staircase of a rotated box's pixels tilts a face's
    longest edges by a few degrees."""
    assert len(found) == len(expected), found
    for want in expected:
        assert min(angle_between(f, want) for f in found) < tolerance, (found, want)


def test_upright_cups_alone_give_just_zero():
    scene = look(Canvas().disc(40, 40, 1.65).disc(120, 90, 1.65).disc(200, 140, 1.3).image())
    assert all(r.round for r in scene.regions)
    assert training_orientations([as_training_object(r) for r in scene.regions]) == [0.0]


@pytest.mark.parametrize("yaw", [0.0, 25.0, 60.0, 140.0])
def test_a_box_gives_its_four_faces_relative_to_its_axis(yaw):
    region = look(Canvas().rect(100, 90, 11.0, 9.0, yaw).image()).regions[0]
    assert_orientations(training_orientations([as_training_object(region)]), [0.0, 90.0, 180.0, 270.0])


def test_boxes_cans_and_cups_show_the_four_faces():
    canvas = (Canvas().rect(50, 50, 9.0, 4.0, 10.0).rect(120, 60, 9.0, 5.0, 75.0).rect(190, 40, 11.0, 9.0, 130.0)
              .rect(60, 130, 4.8, 2.6, 200.0).rect(150, 130, 8.3, 2.9, 35.0).disc(200, 120, 1.65).disc(100, 100, 1.3))
    found = training_orientations([as_training_object(r) for r in look(canvas.image()).regions])
    # Short end faces of small objects are a few pixels: their normals scatter more,
    # and may add a stray cluster; the four faces are there all the same.
    for want in (0.0, 90.0, 180.0, 270.0):
        assert min(angle_between(f, want) for f in found) < 10.0, (found, want)


def test_face_normals_weigh_edges_by_length():
    region = look(Canvas().rect(100, 90, 12.0, 4.0, 0.0).image()).regions[0]
    normals = face_normals(as_training_object(region).polygon)
    along = sum(w for a, w in normals if min(angle_between(a, 90), angle_between(a, 270)) < 20)
    across = sum(w for a, w in normals if min(angle_between(a, 0), angle_between(a, 180)) < 20)
    assert along == pytest.approx(2 * 12.0, rel=0.15)
    assert across == pytest.approx(2 * 4.0, rel=0.3)
