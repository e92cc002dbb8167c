"""Moving obstacles in the simulator: world-file movers, the --movers preset, the
blocked_moves safety stop, movers giving way, and the contact count."""

from __future__ import annotations

import json
import math

import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from hero_driver.interface import BlockedMoves, Pose
from hero_driver.sim.movers import YIELD_GAP_IN, MoverPreset, parse_movers
from hero_driver.sim.world import SAFETY_IN, SimWorld
from hero_driver.sim_driver import SimulatedHero
from robot_profile import load_profile

BASE_R = load_profile().robot.geometry.base_radius_in  # the simulator's robot is the shipped profile's


def world(tmp_path, movers, robot=(30, 90, 0), name="crossing"):
    path = tmp_path / f"{name}.json"
    path.write_text(json.dumps({"room": {"width_in": 240, "depth_in": 180},
                                "robot": {"x_in": robot[0], "y_in": robot[1], "heading_deg": robot[2]},
                                "objects": [], "movers": movers}))
    return path


PERSON_ACROSS = {"shape": "disc", "path": [[100, 12], [100, 168]], "speed_in_s": 12}


def test_parse_movers_reads_count_and_speed():
    assert parse_movers("3") == MoverPreset(3, 12.0)
    assert parse_movers("2:30") == MoverPreset(2, 30.0)


@pytest.mark.parametrize("text", ["x", "-1", "21", "2:0", "2:fast", "2:nan"])
def test_parse_movers_refuses_in_one_line_naming_the_flag(text):
    with pytest.raises(ValueError) as err:
        parse_movers(text)
    assert str(err.value).startswith("--movers: ") and "\n" not in str(err.value)


@pytest.mark.parametrize(("mover", "field"), [
    ({"shape": "ball", "path": [[1, 1], [2, 2]], "speed_in_s": 1}, "shape"),
    ({"shape": "disc", "path": [[1, 1], [300, 2]], "speed_in_s": 1}, "path"),
    ({"shape": "disc", "path": [[1, 1]], "speed_in_s": 1}, "path"),
    ({"shape": "disc", "path": [[1, 1], [1, 1]], "speed_in_s": 1}, "path"),
    ({"shape": "disc", "path": [[1, 1], [5, 5]], "speed_in_s": 0}, "speed_in_s"),
    ({"shape": "disc", "path": [[1, 1], [5, 5]], "speed_in_s": 1, "length_in": 4}, "length_in"),
])
def test_a_bad_mover_is_one_line_naming_its_field(tmp_path, mover, field):
    with pytest.raises(ValueError) as err:
        SimWorld(world(tmp_path, [mover]))
    assert f"movers[0]: field {field!r}" in str(err.value) and "\n" not in str(err.value)


def test_a_person_crossing_ahead_stops_the_move_short_with_its_position(tmp_path):
    hero = SimulatedHero(world=world(tmp_path, [PERSON_ACROSS]))
    assert isinstance(hero, BlockedMoves) and hero.safety_in() == SAFETY_IN
    result = hero.move([Pose(200, 90, 0)]).result()
    # 340 s of driving to x=200 while the person crosses x=100 every 13 s: it meets the path
    assert result.blocked is not None and not result.collided
    assert result.blocked.x_in == pytest.approx(100.0) and result.blocked.radius_in == 9.0
    gap = math.dist((result.pose.x_in, result.pose.y_in), (result.blocked.x_in, result.blocked.y_in)) - 2 * BASE_R
    assert 0.0 <= gap < SAFETY_IN
    assert result.pose.x_in < 100.0 - 2 * BASE_R and hero.contacts == 0


def test_without_the_feature_the_base_drives_into_the_person(tmp_path):
    hero = SimulatedHero(world=world(tmp_path, [PERSON_ACROSS]), stop_for_movers=False)
    assert hero.safety_in() is None
    result = hero.move([Pose(200, 90, 0)]).result()
    assert result.collided and result.blocked is None and hero.contacts == 1


def test_a_person_walking_into_a_standing_robot_gives_way(tmp_path):
    # the robot stands on the person's path: the person waits YIELD_GAP_IN from it
    hero = SimulatedHero(world=world(tmp_path, [PERSON_ACROSS], robot=(100, 90, 0)))
    start = hero.state().clock_s
    assert hero.wait(120.0).result().clock_s == pytest.approx(start + 120.0)
    (person,) = hero.movers()
    gap = math.dist((person.x_in, person.y_in), (100, 90)) - 2 * BASE_R
    assert YIELD_GAP_IN <= gap < YIELD_GAP_IN + 3.0 and hero.contacts == 0


def test_movers_advance_with_the_clock_back_and_forth(tmp_path):
    hero = SimulatedHero(world=world(tmp_path, [PERSON_ACROSS], robot=(30, 30, 0)))
    hero.wait(5.0).result()  # 60 in along a 156 in path from (100, 12)
    assert (hero.movers()[0].x_in, hero.movers()[0].y_in) == pytest.approx((100.0, 72.0))
    hero.wait(10.0).result()  # 180 in: the far end at 156, then 24 back
    assert hero.movers()[0].y_in == pytest.approx(168.0 - 24.0)


def test_the_preset_is_seeded_and_keeps_the_robot_start_clear():
    one = SimWorld("lab", seed=3, movers=MoverPreset(4, 12.0)).movers()
    two = SimWorld("lab", seed=3, movers=MoverPreset(4, 12.0)).movers()
    assert one == two and [m.shape for m in one] == ["disc", "box", "disc", "box"]
    assert SimWorld("lab", seed=4, movers=MoverPreset(4, 12.0)).movers() != one


def test_movers_leave_the_rest_of_the_world_as_it_was():
    plain, busy = SimWorld("lab", seed=2), SimWorld("lab", seed=2, movers=MoverPreset(3, 12.0))
    assert plain.truth() == busy.truth()
    assert plain.physics.ray((0.0, 90.0), (240.0, 90.0)) is not None  # the east wall
    assert busy.physics.ray((30.0, 90.0), (230.0, 90.0)) == plain.physics.ray((30.0, 90.0), (230.0, 90.0))


@settings(max_examples=12, deadline=None, suppress_health_check=[HealthCheck.function_scoped_fixture])
@given(seed=st.integers(0, 10_000), count=st.integers(1, 4), speed=st.sampled_from([6.0, 12.0, 40.0]),
       goals=st.lists(st.tuples(st.floats(20, 220), st.floats(20, 160)), min_size=1, max_size=4))
def test_with_the_feature_the_base_never_touches_a_mover(tmp_path, seed, count, speed, goals):
    hero = SimulatedHero(world=world(tmp_path, []), seed=seed, movers=MoverPreset(count, speed))
    for x, y in goals:
        hero.move([Pose(x, y, 0)]).result()
        hero.wait(7.0).result()
    assert hero.contacts == 0  # an empty room: walls are out of the goals' reach


def test_driver_sim_takes_movers_and_refuses_a_bad_value_in_one_line(capsys: pytest.CaptureFixture[str]) -> None:
    from csl_cli.main import main

    assert main(["driver", "sim", "--movers", "2:fast"]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1
    assert "argument --movers: '2:fast': SPEED must be a number of inches per second" in err[0]
