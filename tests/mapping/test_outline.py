"""An object's outline from scans round it, and the training orientations it gives.

The scans: a 360-beam range finder (1° apart), range noise sigma 0.5 in, 10 % of the
beams lost, from the four poses of the survey (24 in from the object, facing it), each
scanned ``SCANS`` times there.

Tolerance on a box's orientation, worked out for the 9 x 4 in box at its worst yaw (its
faces square to the views, so each face is seen by one view only). A 9 in face 22 in
away spans 9 / (22 x 0.01745) = 23 beams, 21 after the losses; the angle of a line
fitted to N returns spread evenly over a length L, each off by sigma, has a standard
error of sigma / sqrt(N L^2 / 12). Eight scans give N = 168 per long face (1,134 in^2 each)
and 8 x 10.6 = 85 per 4 in end 19.5 in away (113 in^2 each): 0.5 / sqrt(2,494) = 0.010 rad
= 0.57°, so ±3° is over five standard errors. One scan per view gives 1.6°, and ±3°
would fail about one box in twenty: hence ``SCANS``. (At other yaws two views see each
face and the error is smaller.)
"""

from __future__ import annotations

import math

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from learner.position import Position
from learner.training.inputs import TrainingObject
from learner.training.stage import face_normals, training_orientations
from mapping.outline import Outline, outline, survey_plan
from mapping.scan import PlanarScan
from planner.geometry import Pose
from tests.mapping.synthetic import Lidar, circle, rect, scene, square_room

CENTRE = (60.0, 60.0)  # in a 120 in room: its walls 60 in away, outside the outline's reach
SIGMA_IN = 0.5
SCANS = 8
LIDAR = Lidar(sigma_in=SIGMA_IN, dropout=0.1)
TOLERANCE_DEG = 3.0


def room_with(*objects: list[tuple[float, float, float, float]]) -> np.ndarray:
    return scene([tuple(w) for w in square_room(120.0)], *objects)


def scans_from(world: np.ndarray, poses: tuple[Pose, ...] | list[Pose], seed: int,
               scans: int = SCANS) -> list[tuple[PlanarScan, Pose]]:
    """``scans`` scans from each pose, taken where the robot really is (the corrected
    pose is the true one here)."""
    rng = np.random.default_rng(seed)
    out = []
    for pose in poses:
        for _ in range(scans):
            ranges = LIDAR.scan(world, (pose.x_in, pose.y_in, math.radians(pose.heading_deg)), rng)
            out.append((PlanarScan(LIDAR.angles_rad, ranges, pose.x_in, pose.y_in, pose.heading_deg, 0.0,
                                   LIDAR.max_range_in), pose))
    return out


def off(a: float, b: float) -> float:
    """How far apart two directions are, in degrees."""
    return abs((a - b + 180.0) % 360.0 - 180.0)


def training(polygon: tuple[tuple[float, float], ...], round_: bool = False) -> list[float]:
    return training_orientations([TrainingObject("box", "Front-Wrap", Position(6.0, 0.0), polygon, round_)])


def box_outline(yaw_deg: float, seed: int) -> Outline:
    return outline(scans_from(room_with(rect(*CENTRE, 9.0, 4.0, yaw_deg)), survey_plan(CENTRE), seed),
                   CENTRE, SIGMA_IN)


# -- The survey -----------------------------------------------------------------------------
def test_the_survey_is_four_poses_round_the_object_facing_it() -> None:
    """Bearings 0, 90, 180, 270 from (60, 60) at 24 in, each heading back at the object."""
    poses = survey_plan(CENTRE)
    assert [(round(p.x_in, 9), round(p.y_in, 9), p.heading_deg) for p in poses] == [
        (84.0, 60.0, 180.0), (60.0, 84.0, 270.0), (36.0, 60.0, 0.0), (60.0, 36.0, 90.0)]


def test_the_survey_starts_on_the_robots_side() -> None:
    """The robot at (60, 10) is at bearing -90°: the first view is there, then
    counter-clockwise."""
    poses = survey_plan(CENTRE, start=Pose(60.0, 10.0, 45.0), views=2)
    assert [(round(p.x_in, 9), round(p.y_in, 9), p.heading_deg) for p in poses] == [(60.0, 36.0, 90.0),
                                                                                     (60.0, 84.0, 270.0)]


@pytest.mark.parametrize(("kwargs", "message"), [
    ({"views": 0}, "views must be a whole number >= 1"),
    ({"standoff_in": 8.0}, "standoff_in must be over 8.5 in"),
    ({"standoff_in": math.nan}, "standoff_in must be over"),
])
def test_a_survey_that_cannot_be_driven_is_refused(kwargs: dict[str, float], message: str) -> None:
    with pytest.raises(ValueError, match=message):
        survey_plan(CENTRE, **kwargs)


# -- A box ------------------------------------------------------------------------------------
def test_a_box_at_30_degrees_gives_its_four_faces() -> None:
    """9 x 4 in at yaw 30°: faces facing 30, 120, 210 and 300°, every one seen; the
    training orientations are those of the true footprint, in the world's frame and in
    the object's own (0, 90, 180, 270 from its long axis)."""
    found = box_outline(30.0, seed=1)
    assert not found.round and found.complete and found.seen == (True,) * 4
    normals = sorted(direction for direction, _ in face_normals(found.polygon))
    assert all(off(n, truth) <= TOLERANCE_DEG for n, truth in zip(normals, (30.0, 120.0, 210.0, 300.0)))
    truth = training(tuple((x0, y0) for x0, y0, _, _ in rect(*CENTRE, 9.0, 4.0, 30.0)))
    assert truth == [30, 120, 210, 300]
    got = training(found.polygon)
    assert len(got) == 4 and all(off(g, t) <= TOLERANCE_DEG for g, t in zip(got, truth))
    assert off(found.axis_deg, 30.0) <= TOLERANCE_DEG
    own = training(found.object_frame())
    assert len(own) == 4 and all(off(g, t) <= TOLERANCE_DEG for g, t in zip(own, (0, 90, 180, 270)))
    # its size: sides fitted to ~200 returns each are good to a few hundredths of an inch
    corners = np.asarray(found.polygon)
    sides = sorted(math.dist(corners[i], corners[(i + 1) % 4]) for i in range(4))
    assert sides == pytest.approx([4.0, 4.0, 9.0, 9.0], abs=0.5)
    assert math.dist(found.centre, CENTRE) < 0.5


@settings(max_examples=25, deadline=None)
@given(yaw=st.floats(min_value=0.0, max_value=360.0, exclude_max=True), seed=st.integers(0, 2**16))
def test_the_orientation_error_bound_holds_at_any_yaw(yaw: float, seed: int) -> None:
    found = box_outline(yaw, seed)
    assert not found.round and found.complete
    normals = sorted(direction for direction, _ in face_normals(found.polygon))
    truths = sorted((yaw + k * 90.0) % 360.0 for k in range(4))
    assert len(normals) == 4
    assert max(min(off(n, t) for t in truths) for n in normals) <= TOLERANCE_DEG
    assert all(min(off(g, t) for t in truths) <= TOLERANCE_DEG + 0.5 for g in training(found.polygon))  # rounded


def test_a_box_seen_square_on_from_one_side_is_that_face_alone() -> None:
    """From one pose on the normal of the long face facing 120°: only that face has
    returns on it (the ends are edge-on, the back hidden), nothing says how deep the box
    is, and the outline is the face alone, flat. Its polygon's faces are the seen one and
    its back (the same line, facing 300°): training gets 120 and 300 and misses the ends'
    30 and 210, so the outline is not complete."""
    bearing = math.radians(120.0)
    pose = Pose(CENTRE[0] + 24.0 * math.cos(bearing), CENTRE[1] + 24.0 * math.sin(bearing), 300.0)
    found = outline(scans_from(room_with(rect(*CENTRE, 9.0, 4.0, 30.0)), [pose], seed=3), CENTRE, SIGMA_IN)
    assert not found.round and not found.complete
    assert sum(found.seen) == 1
    assert len(found.seen_normals_deg()) == 1 and off(found.seen_normals_deg()[0], 120.0) <= TOLERANCE_DEG
    corners = np.asarray(found.polygon)
    assert math.dist(corners[0], corners[3]) == pytest.approx(0.0, abs=1e-9)  # no depth
    assert math.dist(corners[1], corners[2]) == pytest.approx(0.0, abs=1e-9)
    got = training(found.polygon)
    assert len(got) == 2 and off(got[0], 120.0) <= TOLERANCE_DEG and off(got[1], 300.0) <= TOLERANCE_DEG


def test_a_box_seen_from_one_corner_is_inferred_whole() -> None:
    """From bearing 75° (between the faces facing 30 and 120°) both those faces are seen
    whole: the hidden two are parallel to them and end where they end, so training gets
    all four orientations, though only two faces were seen."""
    bearing = math.radians(75.0)
    pose = Pose(CENTRE[0] + 24.0 * math.cos(bearing), CENTRE[1] + 24.0 * math.sin(bearing), 255.0)
    found = outline(scans_from(room_with(rect(*CENTRE, 9.0, 4.0, 30.0)), [pose], seed=4), CENTRE, SIGMA_IN)
    assert not found.complete and sum(found.seen) == 2
    assert sorted(round(n) for n in found.seen_normals_deg()) == pytest.approx([30, 120], abs=TOLERANCE_DEG)
    got = training(found.polygon)
    assert len(got) == 4 and all(off(g, t) <= TOLERANCE_DEG for g, t in zip(got, (30, 120, 210, 300)))


# -- A round object ----------------------------------------------------------------------------
def test_a_can_is_round() -> None:
    """A 3.5 in can: its returns fit a circle of radius 1.75 within the range noise; a
    circle's centre and radius from ~240 returns are good to a few hundredths of an inch.
    Round footprints give no orientation of their own."""
    found = outline(scans_from(room_with(circle(*CENTRE, 1.75, sides=90)), survey_plan(CENTRE), seed=5), CENTRE, SIGMA_IN)
    assert found.round and found.complete and found.seen == ()
    assert math.dist(found.centre, CENTRE) < 0.25
    assert max(math.dist(p, found.centre) for p in found.polygon) == pytest.approx(1.75, abs=0.25)
    assert training(found.polygon, found.round) == [0.0]


def test_a_can_seen_from_one_side_is_round_but_not_complete() -> None:
    """One view shows just under half the can (2 acos(1.75 / 24) = 172°): more than the
    120° a circle needs to be told from a flat face, less than all round."""
    found = outline(scans_from(room_with(circle(*CENTRE, 1.75, sides=90)), survey_plan(CENTRE)[:1], seed=6), CENTRE, SIGMA_IN)
    assert found.round and not found.complete


def test_a_box_is_not_round() -> None:
    """The 9 x 4 in box's corners stand 1-2 in off any circle: far beyond the noise."""
    assert not box_outline(0.0, seed=7).round


def test_a_circle_wider_than_any_round_catalogue_object_is_a_rectangle() -> None:
    """A lying 20 oz tumbler (7 x 4 in) at 30° under a 1.5 in range noise: a circle 6.3-6.9
    in across explains its returns as well as the rectangle does (seeds 4-7). No round
    footprint in the catalogue is wider than 4 in (``ROUND_MAX_ACROSS_IN``), so it is
    the rectangle, with its axis: the lying tumbler's grasp is placed along it."""
    noisy = Lidar(sigma_in=1.5, dropout=0.1)
    world = room_with(rect(*CENTRE, 7.0, 4.0, 30.0))
    for seed in (4, 5, 6, 7):
        rng = np.random.default_rng(seed)
        views = []
        for pose in survey_plan(CENTRE):
            for _ in range(2):
                ranges = noisy.scan(world, (pose.x_in, pose.y_in, math.radians(pose.heading_deg)), rng)
                views.append((PlanarScan(noisy.angles_rad, ranges, pose.x_in, pose.y_in, pose.heading_deg, 0.0,
                                         noisy.max_range_in), pose))
        found = outline(views, CENTRE, 1.5)
        assert not found.round and off(found.axis_deg % 180.0, 30.0) <= 6.0, seed


# -- The catalogue's limit and what stands near ------------------------------------------------------
def test_the_largest_catalogue_object_is_outlined() -> None:
    """The 11 x 9 in closed box (half-diagonal 7.1 in, within the 12 in square's 8.5)."""
    world = room_with(rect(*CENTRE, 11.0, 9.0, 20.0))
    found = outline(scans_from(world, survey_plan(CENTRE), seed=8), CENTRE, SIGMA_IN)
    corners = np.asarray(found.polygon)
    assert sorted(math.dist(corners[i], corners[(i + 1) % 4]) for i in range(4)) == pytest.approx(
        [9.0, 9.0, 11.0, 11.0], abs=0.5)


def test_an_object_longer_than_12_in_is_refused() -> None:
    """16 x 4 in: its returns reach 8.2 in from its centre, within the gathering circle,
    but its outline is 16 in long."""
    world = room_with(rect(*CENTRE, 16.0, 4.0, 20.0))
    with pytest.raises(ValueError, match=r"16\.\d in across, more than the catalogue's 12 in"):
        outline(scans_from(world, survey_plan(CENTRE), seed=9), CENTRE, SIGMA_IN)


def test_a_wall_near_the_object_is_refused() -> None:
    """A wall 12 in from the centre: returns between the farthest a 12 in object's can
    reach (8.5 + 4 x 0.5 = 10.5 in) and the gathering circle (14.5 in)."""
    world = room_with(rect(*CENTRE, 9.0, 4.0, 20.0), [(CENTRE[0] + 12.0, 0.0, CENTRE[0] + 12.0, 120.0)])
    with pytest.raises(ValueError, match=r"returns lie 10\.5-14\.5 in from the object near \(60\.0, 60\.0\), "
                                         r"beyond a 12 in object's reach: it is not alone, or bigger"):
        outline(scans_from(world, survey_plan(CENTRE), seed=10, scans=1), CENTRE, SIGMA_IN)


def test_nothing_there_is_refused() -> None:
    with pytest.raises(ValueError, match=r"outline: 0 returns within 14\.5 in of \(60\.0, 60\.0\), too few"):
        outline(scans_from(room_with(), survey_plan(CENTRE), seed=11, scans=1), CENTRE, SIGMA_IN)


@pytest.mark.parametrize("sigma", [0.0, -1.0, math.inf, math.nan])
def test_a_range_noise_that_is_not_positive_is_refused(sigma: float) -> None:
    with pytest.raises(ValueError, match="range_sigma_in must be positive"):
        outline([], CENTRE, sigma)
