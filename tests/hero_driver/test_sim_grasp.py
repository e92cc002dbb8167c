"""Grasping: which procedure lifts which object from which approach, preconditions,
and the physical side effects of failed grasps."""

from __future__ import annotations

import math

import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from hero_driver.interface import BAD_REQUEST, OUT_OF_RANGE, DriverError
from hero_driver.sim.grasping import JAMMED, KNOCKED_OVER, LIFTED, NOTHING, PUSHED
from hero_driver.sim.noise import NoiseConfig
from hero_driver.sim.physics import OVERLAP_IN
from hero_driver.sim.probe import approach_pose, grasp_probe
from hero_driver.sim.catalogue import profile_and_catalogue
from hero_driver.sim.world import SimWorld
from hero_driver.sim.worldfile import parse_world
from tests.hero_driver.test_sim_support import lone, object_pixels

GRASPS = ["Front-Pinch", "Front-Wrap", "Top-Pinch", "Top-Vert-Grip", "Top-Hor-Grip", "No-Grab"]


@pytest.mark.parametrize("entry", sorted(profile_and_catalogue()[1]))
def test_each_object_is_lifted_by_exactly_its_grasps(entry: str) -> None:
    rules = profile_and_catalogue()[1][entry].grasps
    for theta, end_on in ((0, True), (90, False), (180, True), (270, False)):
        expected = {r.procedure for r in rules if r.procedure != "No-Grab"
                    and (r.approach == "any" or (r.approach == "end") == end_on)}
        lifted = {g for g in GRASPS if grasp_probe(entry, g, theta)}
        assert lifted == expected, (entry, theta)


@pytest.mark.parametrize("entry", ["soda-can-12oz/lying", "tennis-can/lying", "soda-bottle-16oz/lying"])
def test_lying_cans_vertical_grip_end_on_horizontal_from_the_side(entry: str) -> None:
    for theta in (0, 30, 150, 200):
        assert grasp_probe(entry, "Top-Vert-Grip", theta) and not grasp_probe(entry, "Top-Hor-Grip", theta)
    for theta in (60, 90, 120, 250):
        assert grasp_probe(entry, "Top-Hor-Grip", theta) and not grasp_probe(entry, "Top-Vert-Grip", theta)


@settings(max_examples=25, deadline=None)
@given(theta=st.floats(0, 360))
def test_round_upright_objects_do_not_care_about_approach(theta: float) -> None:
    assert grasp_probe("cup-8oz/upright", "Front-Wrap", theta)
    assert grasp_probe("tumbler-32oz/upright", "Top-Pinch", theta)
    assert not grasp_probe("tumbler-32oz/upright", "Front-Wrap", theta)


def test_no_grab_objects_cannot_be_lifted_and_no_grab_holds_nothing() -> None:
    for entry in ("closed-box-11x9x12/upright", "open-box-9x4x5/lying-facing-down", "closed-box-10x10x10/upright"):
        assert not any(grasp_probe(entry, g, 0) for g in GRASPS)
    sim = lone("cup-8oz/upright", 40.0)
    before = sim.truth()
    result = sim.grasp("No-Grab")
    assert not result.success and result.duration_s == 0 and sim.last_effect == NOTHING
    assert sim.truth() == before


def test_grasp_range_precondition() -> None:
    with pytest.raises(DriverError) as info:
        lone("cup-8oz/upright", 16.0).grasp("Front-Wrap")
    assert info.value.code == OUT_OF_RANGE
    assert lone("cup-8oz/upright", 7.4).grasp("Front-Wrap").success
    with pytest.raises(DriverError):
        lone("cup-8oz/upright", 4.0).grasp("Front-Wrap")


def test_a_lifted_object_leaves_the_floor_and_goes_to_the_bin() -> None:
    sim = lone("cup-8oz/upright", 6.0)
    assert object_pixels(sim) > 0
    result = sim.grasp("Front-Wrap")
    assert result.success and result.duration_s == 60.0 and sim.clock_s == 60.0
    assert sim.last_effect == LIFTED and object_pixels(sim) == 0
    assert sim.truth()[0].held and not sim.truth()[0].binned
    with pytest.raises(DriverError) as info:
        sim.grasp("Front-Wrap")
    assert info.value.code == BAD_REQUEST
    sim.release()
    assert sim.truth()[0].binned and not sim.truth()[0].held
    assert sim.release().clock_s == 60.0


def _first_seed_with(entry: str, grasp: str, effect: str, theta: float = 0.0) -> SimWorld:
    for seed in range(200):
        sim = lone(entry, 6.0, theta, seed=seed)
        sim.grasp(grasp)
        if sim.last_effect == effect:
            return sim
    raise AssertionError(f"no seed gives {effect}")


def test_upside_down_tumbler_jams_top_pinch_without_motion() -> None:
    for seed in range(20):
        sim = lone("tumbler-20oz/upside-down", 6.0, seed=seed)
        before = sim.truth()
        assert not sim.grasp("Top-Pinch").success
        assert sim.last_effect == JAMMED and sim.truth() == before


def test_knock_over_turns_an_upright_cup_into_a_lying_one() -> None:
    before = object_pixels(lone("cup-8oz/upright", 6.0))
    sim = _first_seed_with("cup-8oz/upright", "Top-Pinch", KNOCKED_OVER)
    t = sim.truth()[0]
    assert t.entry_id == "cup-8oz/lying" and {g.procedure for g in t.grasps} == {"Front-Pinch"}
    assert object_pixels(sim) > 1.3 * before
    sx, sy = sim.sonar_point()
    assert math.hypot(t.x_in - sx, t.y_in - sy) > 6.0 + 1.65  # fell away from the robot
    assert sim.sense("H-Sweep-1°").distance_in > 7.5  # out of reach of the scans now


def test_a_push_moves_the_object_away_but_keeps_its_class() -> None:
    fresh = lone("closed-box-2x2x2/upright", 6.0)
    start, pixels = fresh.truth()[0], object_pixels(fresh)
    sim = _first_seed_with("closed-box-2x2x2/upright", "Front-Wrap", PUSHED)
    t = sim.truth()[0]
    moved = t.x_in - start.x_in  # the robot is at +x (theta 0), so away is -x
    assert t.entry_id == start.entry_id and -3.0 * 1.4 - 0.5 < moved < -3.0 * 0.6 + 0.5
    assert abs(object_pixels(sim) - pixels) <= 0.5 * pixels


def test_a_lying_round_object_rolls_across_its_axis() -> None:
    start = lone("soda-can-12oz/lying", 6.0, 90).truth()[0]
    side = _first_seed_with("soda-can-12oz/lying", "Front-Wrap", PUSHED, theta=90).truth()[0]
    assert abs(side.y_in - start.y_in) > 3.0 * 0.6 * 2 and abs(side.x_in - start.x_in) < 0.5
    end = _first_seed_with("soda-can-12oz/lying", "Front-Wrap", PUSHED, theta=0).truth()[0]
    assert abs(end.x_in - start.x_in) < 3.0 * 1.4 + 0.5 and abs(end.y_in - start.y_in) < 0.5


def test_side_effects_are_deterministic_per_seed() -> None:
    def outcome(seed: int) -> tuple:
        sim = lone("tumbler-16oz/upright", 6.0, seed=seed)
        sim.grasp("Front-Wrap")
        return sim.last_effect, sim.truth()
    effects = {outcome(seed)[0] for seed in range(40)}
    assert effects == {KNOCKED_OVER, PUSHED, NOTHING}
    for seed in range(5):
        assert outcome(seed) == outcome(seed)


def test_an_object_knocked_over_onto_a_neighbour_is_pushed_clear_of_it() -> None:
    """The upright 16 oz tumbler tips away from the robot (at +x) onto a can standing
    2 in behind it: the lying tumbler lands across the can, and settling must part them
    (pymunk's overlap push never shows in a body's speed, so a rest check alone stops
    at once and leaves them overlapping)."""
    catalogue = profile_and_catalogue()[1]
    tumbler = catalogue["tumbler-16oz/upright"].footprint.radius_in
    can = catalogue["soda-can-12oz/upright"].footprint.radius_in
    data = {"name": "knocked onto a can", "room": {"width_in": 400, "depth_in": 400},
            "robot": {"x_in": 20.0, "y_in": 20.0, "heading_deg": 0.0},
            "objects": [{"id": "tumbler-16oz/upright", "x_in": 200.0, "y_in": 200.0, "yaw_deg": 0.0},
                        {"id": "soda-can-12oz/upright", "x_in": 200.0 - tumbler - 2.0 - can, "y_in": 200.0}]}
    for seed in range(200):
        sim = SimWorld(parse_world(data, "<knocked onto a can>", catalogue), seed, noise=NoiseConfig.off())
        sim.pose = approach_pose(sim, 0, 6.0, 0.0)
        sim.grasp("Front-Wrap")
        if sim.last_effect == KNOCKED_OVER:
            break
    lying, standing = (o.shape for o in sim.physics.objects)
    assert sim.truth()[0].entry_id == "tumbler-16oz/lying"
    assert max((abs(p.distance) for p in lying.shapes_collide(standing).points), default=0.0) <= OVERLAP_IN
