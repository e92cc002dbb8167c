"""The seven sonar procedures against hand-computed geometry, their preconditions and
their noise."""

from __future__ import annotations

import dataclasses
import math

import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from hero_driver.interface import NO_TARGET, OUT_OF_RANGE, UNKNOWN_PROCEDURE, DriverError, Pose
from hero_driver.sim.noise import NoiseConfig
from hero_driver.sim.probe import probe
from hero_driver.sim.world import SimWorld
from tests.hero_driver.test_sim_support import lone

SENSOR_HEIGHT = 4.0
S_SWEEP_HEIGHT = 18.0


def value(entry: str, procedure: str, d: float, theta: float, feature: str) -> float:
    result = probe(entry, procedure, d, theta)
    assert result.distance_in == pytest.approx(d, abs=1e-6)
    return result.values[feature]


def test_the_briefs_example_box_at_24_in() -> None:
    """A face 4 in wide at 24 in subtends 2 atan(2/24) = 9.53°."""
    exact = math.degrees(2 * math.atan(2.0 / 24.0))
    assert abs(value("magazine-box-9x4x7/upright", "H-Sweep-1°", 24, 0, "Width-Degree-1°") - exact) <= 3
    assert abs(value("magazine-box-9x4x7/upright", "H-Sweep-5°", 24, 0, "Width-Degree-5°") - exact) <= 5


@settings(max_examples=30, deadline=None)
@given(d=st.floats(6, 127), side=st.sampled_from([0, 90, 180, 270]))
def test_horizontal_sweep_of_a_box_face(d: float, side: int) -> None:
    half_face = 2.0 if side in (0, 180) else 4.5
    exact = math.degrees(2 * math.atan(half_face / d))
    got = value("magazine-box-9x4x7/upright", "H-Sweep-1°", d, side, "Width-Degree-1°")
    assert got % 1 == 0 and abs(got - exact) <= 1.0 + 1e-6
    got5 = value("magazine-box-9x4x7/upright", "H-Sweep-5°", d, side, "Width-Degree-5°")
    assert got5 % 5 == 0 and abs(got5 - exact) <= 5.0 + 1e-6


@settings(max_examples=30, deadline=None)
@given(d=st.floats(6, 127), theta=st.floats(0, 360))
def test_horizontal_sweep_of_a_round_object_ignores_orientation(d: float, theta: float) -> None:
    r = 1.65
    exact = math.degrees(2 * math.asin(r / (d + r)))
    assert abs(value("cup-8oz/upright", "H-Sweep-1°", d, theta, "Width-Degree-1°") - exact) <= 1.0 + 1e-6


@settings(max_examples=30, deadline=None)
@given(d=st.floats(6, 127))
def test_vertical_sweep_of_a_tall_box_spans_foot_to_top_edge(d: float) -> None:
    exact = math.degrees(math.atan(SENSOR_HEIGHT / d) + math.atan((10.0 - SENSOR_HEIGHT) / d))
    assert abs(value("closed-box-10x10x10/upright", "V-Sweep-1°", d, 0, "Height-Degree-1°") - exact) <= 1.0 + 1e-6
    assert abs(value("closed-box-10x10x10/upright", "V-Sweep-5°", d, 0, "Height-Degree-5°") - exact) <= 5.0 + 1e-6


@settings(max_examples=30, deadline=None)
@given(d=st.floats(6, 127))
def test_vertical_sweep_of_a_low_object_reaches_the_far_top_edge(d: float) -> None:
    """A lying can (2.6 in) is lower than the sonar: the beam sees its top up to the
    far end, 4.8 in back when approached end-on."""
    exact = math.degrees(math.atan(SENSOR_HEIGHT / d) - math.atan((SENSOR_HEIGHT - 2.6) / (d + 4.8)))
    got = value("soda-can-12oz/lying", "V-Sweep-1°", d, 0, "Height-Degree-1°")
    assert abs(got - exact) <= 1.0 + 1e-6


@pytest.mark.parametrize("entry, theta, depth", [
    ("closed-box-2x2x2/upright", 0, 2.0), ("closed-box-11x9x12/upright", 0, 11.0),
    ("closed-box-11x9x12/upright", 90, 9.0), ("soda-can-12oz/lying", 0, 4.8)])
def test_depth_sweep_from_the_raised_wrist(entry: str, theta: float, depth: float) -> None:
    height = {"closed-box-2x2x2/upright": 2.0, "closed-box-11x9x12/upright": 12.0, "soda-can-12oz/lying": 2.6}[entry]
    drop = S_SWEEP_HEIGHT - height
    exact = math.degrees(math.atan(drop / 6.0) - math.atan(drop / (6.0 + depth)))
    assert abs(value(entry, "S-Sweep-1°", 6, theta, "Depth-Degree-1°") - exact) <= 3.0


def test_the_raised_wrist_height_comes_from_the_profile() -> None:
    """``[robot] raised_sensor_height_in`` (docs/conventions.md, "Adding a robot
    constant"): a robot that lifts its wrist to 30 in sees the 2x2x2 box's 2 in top
    under a smaller angle than the HERO at 18 in."""
    import dataclasses

    from robot_profile import load_profile

    hero = load_profile()
    tall = dataclasses.replace(hero, robot=dataclasses.replace(hero.robot, geometry=dataclasses.replace(
        hero.robot.geometry, raised_sensor_height_in=30.0)))
    angle = {}
    for name, profile, raised in (("hero", hero, S_SWEEP_HEIGHT), ("tall", tall, 30.0)):
        drop = raised - 2.0
        exact = math.degrees(math.atan(drop / 6.0) - math.atan(drop / 8.0))
        angle[name] = probe("closed-box-2x2x2/upright", "S-Sweep-1°", 6, 0, profile=profile).values["Depth-Degree-1°"]
        assert abs(angle[name] - exact) <= 1.0
    assert angle["tall"] <= angle["hero"] - 2  # 3.9° against 6.0°: atan(d/6) - atan(d/8), d = raised - 2


@pytest.mark.parametrize("entry, theta, width, depth, height, front, top", [
    ("closed-box-11x9x12/upright", 0, 9.0, 11.0, 12.0, 0, 0),
    ("closed-box-11x9x12/upright", 90, 11.0, 9.0, 12.0, 0, 0),
    ("open-box-9x4x5/lying-facing-sideways", 90, 9.0, 4.0, 5.0, 1, 0),
    ("open-box-9x4x5/lying-facing-sideways", 270, 9.0, 4.0, 5.0, 0, 0),
    ("open-box-9x4x5/lying-facing-up", 0, 5.0, 9.0, 4.0, 0, 1),
    ("tumbler-16oz/lying", 0, 3.6, 4.6, 3.6, 1, 0),
    ("tumbler-16oz/lying", 180, 3.6, 4.6, 3.6, 0, 0),
    ("cup-8oz/upright", 45, 3.3, 3.3, 3.75, 0, 1),
])
def test_scans_at_6_in(entry: str, theta: float, width: float, depth: float, height: float,
                       front: int, top: int) -> None:
    h = probe(entry, "H-Scan-0.3", 6, theta).values
    v = probe(entry, "D-Scan-0.3", 6, theta).values
    assert abs(h["Width"] - width) <= 0.3 + 1e-6 and h["Front-Hole?"] == front
    assert abs(v["Depth"] - depth) <= 0.3 + 1e-6 and v["Top-Hole?"] == top
    assert abs(v["Height"] - height) <= 0.15 + 1e-6


@pytest.mark.parametrize("procedure, d", [
    ("H-Sweep-1°", 3.0), ("V-Sweep-5°", 130.0), ("H-Scan-0.3", 16.0), ("D-Scan-0.3", 3.0), ("S-Sweep-1°", 24.0)])
def test_out_of_range(procedure: str, d: float) -> None:
    with pytest.raises(DriverError) as info:
        probe("cup-8oz/upright", procedure, d, 0)
    assert info.value.code == OUT_OF_RANGE


def test_range_tolerance_accepts_within_1_5_in() -> None:
    assert probe("cup-8oz/upright", "H-Scan-0.3", 7.4, 0).distance_in == pytest.approx(7.4)


def test_unknown_procedure() -> None:
    with pytest.raises(DriverError) as info:
        probe("cup-8oz/upright", "X-Ray", 6, 0)
    assert info.value.code == UNKNOWN_PROCEDURE


def test_nothing_in_front_is_no_target() -> None:
    sim = SimWorld("lab", noise=NoiseConfig.off())
    sim.pose = Pose(30.0, 30.0, 225.0)  # facing the corner
    with pytest.raises(DriverError) as info:
        sim.sense("H-Sweep-5°")
    assert info.value.code == NO_TARGET


def test_sensing_charges_the_profile_time_and_refusals_charge_nothing() -> None:
    sim = lone("cup-8oz/upright", 6.0)
    assert sim.sense("H-Scan-0.3").duration_s == 105.0 and sim.clock_s == 105.0
    sim.pose = Pose(sim.pose.x_in + 20, sim.pose.y_in, sim.pose.heading_deg)
    with pytest.raises(DriverError):
        sim.sense("H-Scan-0.3")
    assert sim.clock_s == 105.0


BAND_ONLY = dataclasses.replace(NoiseConfig.off(), sonar=True)


@settings(max_examples=40, deadline=None)
@given(seed=st.integers(0, 10_000), d=st.floats(6, 60))
def test_noise_stays_within_the_expected_error(seed: int, d: float) -> None:
    exact = probe("closed-box-10x10x10/upright", "H-Sweep-1°", d, 0).values["Width-Degree-1°"]
    sim = lone("closed-box-10x10x10/upright", d, seed=seed, noise=BAND_ONLY)
    got = sim.sense("H-Sweep-1°").values["Width-Degree-1°"]
    assert got is not None and got % 1 == 0 and abs(got - exact) <= 3
    got5 = sim.sense("H-Sweep-5°").values["Width-Degree-5°"]
    exact5 = probe("closed-box-10x10x10/upright", "H-Sweep-5°", d, 0).values["Width-Degree-5°"]
    assert got5 % 5 == 0 and abs(got5 - exact5) <= 5


def test_scan_noise_within_half_an_inch() -> None:
    exact = probe("closed-box-10x10x10/upright", "D-Scan-0.3", 6, 0).values
    for seed in range(30):
        got = lone("closed-box-10x10x10/upright", 6, seed=seed, noise=BAND_ONLY).sense("D-Scan-0.3").values
        assert abs(got["Height"] - exact["Height"]) <= 0.5 + 1e-9
        assert got["Top-Hole?"] == exact["Top-Hole?"]


def test_dropouts_and_outliers() -> None:
    dropped = lone("cup-8oz/upright", 6, noise=dataclasses.replace(NoiseConfig.off(), dropout_p=1.0))
    assert all(v is None for v in dropped.sense("D-Scan-0.3").values.values())
    wild = lone("cup-8oz/upright", 6, noise=dataclasses.replace(NoiseConfig.off(), outlier_p=1.0))
    exact = probe("cup-8oz/upright", "D-Scan-0.3", 6, 0).values
    got = wild.sense("D-Scan-0.3").values
    assert got["Top-Hole?"] == 1 - exact["Top-Hole?"]
    assert abs(got["Height"] - exact["Height"]) > 0.5 or got["Height"] == 0.0


def test_curved_lying_object_end_on_gives_a_small_depth() -> None:
    curved = dataclasses.replace(NoiseConfig.off(), curved_depth_p=1.0)
    end_on = lone("tennis-can/lying", 6, 0, noise=curved).sense("D-Scan-0.3").values["Depth"]
    side_on = lone("tennis-can/lying", 6, 90, noise=curved).sense("D-Scan-0.3").values["Depth"]
    assert end_on < 0.5 * 8.3 + 0.3
    assert side_on == pytest.approx(3.0, abs=0.3)
    box = lone("closed-box-11x9x12/upright", 6, 0, noise=curved).sense("D-Scan-0.3").values["Depth"]
    assert box == pytest.approx(11.0, abs=0.3)


def test_noisy_probes_are_deterministic_per_seed() -> None:
    def run(seed: int) -> list:
        return [probe(e, p, 6, 0, seed=seed, noise=True).values for e in ("cup-8oz/upright", "tennis-can/lying")
                for p in ("H-Sweep-1°", "V-Sweep-1°", "S-Sweep-1°", "H-Scan-0.3", "D-Scan-0.3")]
    assert run(7) == run(7)
    assert any(run(s) != run(7) for s in range(8, 12))
