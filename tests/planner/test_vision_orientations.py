"""Training orientations: face normals of region polygons, clustered (method.md §4)."""

from __future__ import annotations

import pytest

from planner import face_normals, look, training_orientations
from planner.geometry import angle_between
from tests.planner.drawing import Canvas


def assert_orientations(found: list[float], expected: list[float], tolerance: float = 6.0) -> None:
    assert len(found) == len(expected), found
    for want in expected:
        assert min(angle_between(f, want) for f in found) < tolerance, (found, want)


def test_upright_cups_alone_give_just_zero():
    scene = look(Canvas().disc(40, 40, 1.65).disc(120, 90, 1.65).disc(200, 140, 1.3).image())
    assert all(r.round for r in scene.regions)
    assert training_orientations(scene.regions) == [0.0]


@pytest.mark.parametrize("yaw", [0.0, 25.0, 60.0, 140.0])
def test_a_box_gives_its_four_faces_relative_to_its_axis(yaw):
    region = look(Canvas().rect(100, 90, 11.0, 9.0, yaw).image()).regions[0]
    assert_orientations(training_orientations([region]), [0.0, 90.0, 180.0, 270.0])


def test_boxes_cans_and_cups_cluster_into_four():
    canvas = (Canvas().rect(50, 50, 9.0, 4.0, 10.0).rect(120, 60, 9.0, 5.0, 75.0).rect(190, 40, 11.0, 9.0, 130.0)
              .rect(60, 130, 4.8, 2.6, 200.0).rect(150, 130, 8.3, 2.9, 35.0).disc(200, 120, 1.65).disc(100, 100, 1.3))
    # Short end faces of small objects are a few pixels: their normals scatter more.
    assert_orientations(training_orientations(look(canvas.image()).regions), [0.0, 90.0, 180.0, 270.0], 10.0)


def test_face_normals_weigh_edges_by_length():
    region = look(Canvas().rect(100, 90, 12.0, 4.0, 0.0).image()).regions[0]
    normals = face_normals(region)
    along = sum(w for a, w in normals if min(angle_between(a, 90), angle_between(a, 270)) < 20)
    across = sum(w for a, w in normals if min(angle_between(a, 0), angle_between(a, 180)) < 20)
    assert along == pytest.approx(2 * 12.0, rel=0.15)
    assert across == pytest.approx(2 * 4.0, rel=0.3)


def test_no_regions_no_orientations():
    assert training_orientations([]) == []


@pytest.mark.parametrize("tolerance", [0.0, -5.0, 180.0, float("nan")])
def test_bad_tolerance_is_refused(tolerance):
    with pytest.raises(ValueError, match="tolerance_deg"):
        training_orientations([], tolerance_deg=tolerance)
