"""Moving the base: time charged, collisions, final turn and sonar centring, odometry."""

from __future__ import annotations

import dataclasses
import math

import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from hero_driver.interface import BAD_REQUEST, DriverError, Pose
from hero_driver.sim.noise import NoiseConfig
from hero_driver.sim.world import SimWorld

VISION, CENTRING, SPEED, TURN = 5.0, 15.0, 0.5, 5.0  # the profile's [robot] table


def lab() -> SimWorld:
    return SimWorld("lab", noise=NoiseConfig.off())


def test_move_time_is_vision_turns_path_and_centring() -> None:
    sim = lab()
    result = sim.move([Pose(30.0, 80.0, 90.0)], face=None)
    assert result.duration_s == pytest.approx(VISION + 90 / TURN + 50 / SPEED)
    assert not result.collided and not result.centred and result.pose == Pose(30.0, 80.0, 90.0)
    face = (60.0, 115.0)  # the upside-down tumbler
    result = sim.move([Pose(30.0, 80.0, 0.0)], face=face)
    bearing = math.degrees(math.atan2(35.0, 30.0))
    assert result.duration_s == pytest.approx(VISION + (90 - bearing) / TURN + CENTRING)
    assert result.centred and result.pose.heading_deg == pytest.approx(bearing)
    assert sim.clock_s == pytest.approx(VISION + 90 / TURN + 50 / SPEED + VISION + (90 - bearing) / TURN + CENTRING)


def test_centring_corrects_a_face_point_off_the_object() -> None:
    sim = lab()
    result = sim.move([Pose(30.0, 80.0, 0.0)], face=(63.0, 112.0))
    assert result.centred and result.pose.heading_deg == pytest.approx(math.degrees(math.atan2(35.0, 30.0)))
    miss = sim.move([Pose(30.0, 80.0, 0.0)], face=(30.0, 140.0))
    assert not miss.centred and miss.pose.heading_deg == pytest.approx(90.0)


def test_the_base_stops_short_of_furniture() -> None:
    sim = lab()
    result = sim.move([Pose(30.0, 60.0, 90.0), Pose(30.0, 200.0, 90.0)], face=(30.0, 170.0))
    cabinet_front = 170.0 - 9.0
    assert result.collided and not result.centred
    assert result.pose.y_in == pytest.approx(cabinet_front - 9.0 - 0.1, abs=1e-3)
    assert result.duration_s == pytest.approx(VISION + 90 / TURN + (result.pose.y_in - 30.0) / SPEED)


def test_the_base_stops_short_of_an_object() -> None:
    sim = lab()
    result = sim.move([Pose(30.0, 60.0, 0.0), Pose(150.0, 60.0, 0.0)], face=None)
    assert result.collided and result.pose.x_in == pytest.approx(70.0 - 1.0 - 9.0 - 0.1, abs=1e-3)
    assert sim.truth()[0].x_in == 70.0


@settings(max_examples=25, deadline=None)
@given(points=st.lists(st.tuples(st.floats(20, 380), st.floats(20, 380)), min_size=1, max_size=4))
def test_move_time_formula_in_an_empty_room(points: list[tuple[float, float]]) -> None:
    from hero_driver.sim.catalogue import profile_and_catalogue
    from hero_driver.sim.worldfile import parse_world
    spec = parse_world({"room": {"width_in": 400, "depth_in": 400}, "robot": {"x_in": 200, "y_in": 200}},
                       "<empty>", profile_and_catalogue()[1])
    sim = SimWorld(spec, noise=NoiseConfig.off())
    result = sim.move([Pose(x, y, 0.0) for x, y in points], face=None)
    heading, x0, y0, expected = 0.0, 200.0, 200.0, VISION
    for x, y in points:
        if math.hypot(x - x0, y - y0) < 1e-6:
            continue
        course = math.degrees(math.atan2(y - y0, x - x0))
        expected += abs((course - heading + 180) % 360 - 180) / TURN + math.hypot(x - x0, y - y0) / SPEED
        heading, x0, y0 = course, x, y
    expected += abs((0.0 - heading + 180) % 360 - 180) / TURN
    assert not result.collided and result.duration_s == pytest.approx(expected)


def test_odometry_noise_is_seeded() -> None:
    noisy = dataclasses.replace(NoiseConfig.off(), odometry_frac=0.02, odometry_heading_deg=2.0)

    def end(seed: int) -> Pose:
        return SimWorld("lab", seed, noise=noisy).move([Pose(30.0, 80.0, 90.0)], face=None).pose
    assert end(3) == end(3) and end(3) != end(4)
    assert end(3) != Pose(30.0, 80.0, 90.0) and math.hypot(end(3).x_in - 30, end(3).y_in - 80) < 5


def test_bad_waypoints() -> None:
    for waypoints in ([], [(1.0, 2.0, 3.0)]):
        with pytest.raises(DriverError) as info:
            lab().move(waypoints, face=None)  # type: ignore[arg-type]
        assert info.value.code == BAD_REQUEST


def test_a_base_in_contact_can_back_away_but_not_push_on() -> None:
    sim = lab()
    sim.pose = Pose(70.0 - 1.0 - 9.0 + 0.05, 60.0, 0.0)  # touching the 2 in box at (70, 60)
    assert sim.move([Pose(75.0, 60.0, 0.0)], face=None).collided
    back = sim.move([Pose(30.0, 60.0, 0.0)], face=None)
    assert not back.collided and back.pose.x_in == pytest.approx(30.0)


@pytest.mark.parametrize("goal", [Pose(1e308, 1e308, 0.0), Pose(-301.0, 40.0, 0.0), Pose(40.0, 10_000.0, 0.0)])
def test_a_waypoint_far_outside_the_room_is_refused_and_the_robot_stays(goal: Pose) -> None:
    """Sent more than the room's diagonal (300 in for the 240 x 180 in lab) beyond a wall,
    or to 1e308, the robot refuses: its pose and clock are as before. Driving at a wall
    stays allowed: the bumper stops the base (test_the_base_stops_short_of_furniture)."""
    sim = lab()
    before, clock = sim.pose, sim.clock_s
    with pytest.raises(DriverError) as refused:
        sim.move([Pose(30.0, 80.0, 90.0), goal], face=None)
    assert refused.value.code == BAD_REQUEST and "waypoints[1]" in refused.value.message
    assert "far outside the room (0-240 x 0-180 in)" in refused.value.message
    assert sim.pose == before and sim.clock_s == clock
