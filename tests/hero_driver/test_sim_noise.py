"""Noise presets, scaling, and the echo, odometry and camera effects of real sensors:
each moves readings the expected way at the configured rate (seeded)."""

from __future__ import annotations

import dataclasses
import math

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from csl_cli.main import main
from hero_driver.interface import Pose
from hero_driver.sim import sonar
from hero_driver.sim.camera import YawErrors
from hero_driver.sim.noise import NOISE_PRESETS, PROBABILITIES, SIGMAS, NoiseConfig
from hero_driver.sim.odometry import slip
from hero_driver.sim.readings import perturb, specular_miss
from hero_driver.sim.catalogue import profile_and_catalogue
from hero_driver.sim.world import SimWorld
from hero_driver.sim.worldfile import parse_world
from tests.hero_driver.test_sim_support import lone

CLEAN = NoiseConfig.off()
DRAWS = 2000


def within_binomial(hits: int, n: int, p: float) -> bool:
    """``hits`` of ``n`` is within 4 standard deviations of n p (a false alarm about
    once in 15,000 seeds; the draws are seeded, so it is fixed either way)."""
    return abs(hits - n * p) <= 4.0 * math.sqrt(n * p * (1.0 - p))


# -- presets and scaling --------------------------------------------------------------

def test_presets_are_found_by_name() -> None:
    assert list(NOISE_PRESETS) == ["clean", "mild", "paper", "harsh"]
    assert NoiseConfig.preset("clean") == NoiseConfig.off()
    assert NoiseConfig.preset("mild") == NoiseConfig()
    assert NoiseConfig.preset("harsh").multipath_p > NoiseConfig.preset("paper").multipath_p > 0


def test_mild_is_todays_default_with_every_new_effect_off() -> None:
    mild = NoiseConfig.preset("mild")
    assert (mild.outlier_p, mild.dropout_p, mild.curved_depth_p) == (0.02, 0.01, 0.3)
    assert (mild.odometry_frac, mild.odometry_heading_deg, mild.pixel_sigma) == (0.005, 1.0, 4.0)
    assert mild.sonar and not mild.fisheye
    assert (mild.specular_p, mild.multipath_p, mild.crosstalk_p, mild.odometry_drift, mild.camera_yaw_deg) == (0,) * 5


def test_an_unknown_preset_names_the_valid_ones() -> None:
    with pytest.raises(ValueError) as info:
        NoiseConfig.preset("loud")
    assert str(info.value) == "unknown noise preset 'loud' (valid: clean, mild, paper, harsh)"


@pytest.mark.parametrize("name", list(NOISE_PRESETS))
def test_scaled_zero_is_clean_and_one_is_the_preset(name: str) -> None:
    assert NoiseConfig.preset(name).scaled(0) == NoiseConfig.preset("clean")
    assert NoiseConfig.preset(name).scaled(1) == NoiseConfig.preset(name)


@settings(max_examples=40, deadline=None)
@given(name=st.sampled_from(list(NOISE_PRESETS)), factor=st.floats(0.0, 50.0))
def test_scaled_multiplies_rates_and_caps_probabilities(name: str, factor: float) -> None:
    base = NoiseConfig.preset(name)
    got = base.scaled(factor)
    for field in PROBABILITIES:
        assert getattr(got, field) == pytest.approx(min(1.0, getattr(base, field) * factor))
        assert getattr(got, field) <= 1.0
    for field in SIGMAS:
        assert getattr(got, field) == pytest.approx(getattr(base, field) * factor)
    assert got.specular_angle_deg == base.specular_angle_deg
    assert got.sonar == (base.sonar and factor > 0) and got.fisheye == (base.fisheye and factor > 0)


@pytest.mark.parametrize("factor", [-1.0, math.nan])
def test_a_negative_scale_is_refused(factor: float) -> None:
    with pytest.raises(ValueError, match="noise scale factor must be a number >= 0"):
        NoiseConfig.preset("paper").scaled(factor)


def test_a_world_file_names_a_preset_with_overrides() -> None:
    data = {"room": {"width_in": 100, "depth_in": 100}, "robot": {"x_in": 20, "y_in": 20},
            "noise": {"preset": "harsh", "outlier_p": 0.5}}
    spec = parse_world(data, "w.json", profile_and_catalogue()[1])
    assert spec.noise == dataclasses.replace(NoiseConfig.preset("harsh"), outlier_p=0.5)


@pytest.mark.parametrize("table, message", [
    ({"preset": "loud"}, "w.json: noise: field 'preset' must be one of clean, mild, paper, harsh, got 'loud'"),
    ({"multipath_p": 1.5}, "w.json: noise: field 'multipath_p' must be a probability <= 1, got 1.5"),
    ({"camera_yaw_deg": -2}, "w.json: noise: field 'camera_yaw_deg' must be a number >= 0, got -2"),
])
def test_bad_noise_tables_fail_in_one_line(table: dict[str, object], message: str) -> None:
    data = {"room": {"width_in": 100, "depth_in": 100}, "robot": {"x_in": 20, "y_in": 20}, "noise": table}
    with pytest.raises(ValueError) as info:
        parse_world(data, "w.json", profile_and_catalogue()[1])
    assert str(info.value) == message


def test_driver_sim_refuses_an_unknown_preset_in_one_line(capsys: pytest.CaptureFixture[str]) -> None:
    assert main(["driver", "sim", "--noise", "loud"]) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and "'loud'" in err
    assert all(f"'{name}'" in err for name in NOISE_PRESETS)


# -- multipath and cross-talk -------------------------------------------------------

def _readings(noise: NoiseConfig, ideal: float, error: float, step: float, seed: int = 3) -> list[float]:
    rng = np.random.default_rng(seed)
    out = [perturb(ideal, error, step, rng, noise) for _ in range(DRAWS)]
    assert all(v is not None for v in out)
    return [float(v) for v in out if v is not None]


def test_multipath_reads_long_at_its_rate() -> None:
    """A 10 in Depth (error 0.5 in): a second bounce reads 15-25 in (at least 11 in)."""
    values = _readings(dataclasses.replace(CLEAN, multipath_p=0.1), 10.0, 0.5, 0.0)
    long = [v for v in values if v > 10.0]
    assert all(15.0 <= v <= 25.0 for v in long)
    assert all(v == 10.0 for v in values if v <= 10.0)
    assert within_binomial(len(long), DRAWS, 0.1)


def test_multipath_on_a_sweep_is_at_least_two_errors_long_and_on_the_grid() -> None:
    """A 4° Height-Degree-1° (±3°): 1.5-2.5x would be 6-10°; the floor of two errors
    makes it at least 10°."""
    values = _readings(dataclasses.replace(CLEAN, multipath_p=0.2), 4.0, 3.0, 1.0)
    long = [v for v in values if v != 4.0]
    assert long and all(v == 10.0 for v in long)
    assert within_binomial(len(long), DRAWS, 0.2)


def test_crosstalk_reads_far_too_short_at_its_rate() -> None:
    values = _readings(dataclasses.replace(CLEAN, crosstalk_p=0.05), 10.0, 0.5, 0.0)
    short = [v for v in values if v < 10.0]
    assert all(v <= 2.5 for v in short)
    assert within_binomial(len(short), DRAWS, 0.05)


def test_gross_errors_exclude_each_other() -> None:
    """Outliers are drawn first, then multipath, then cross-talk: the rates of the
    later ones are of the values the earlier ones left."""
    noise = dataclasses.replace(CLEAN, outlier_p=0.1, multipath_p=0.1, crosstalk_p=0.1)
    values = _readings(noise, 10.0, 0.5, 0.0)
    assert within_binomial(sum(v == 10.0 for v in values), DRAWS, 0.9 ** 3)


# -- specular misses ----------------------------------------------------------------

BOX = "magazine-box-9x4x7/upright"  # 9 x 4 in footprint, major axis along local x


@pytest.mark.parametrize("orientation, incidence", [
    (0.0, 0.0),  # square to the 4 in end face
    (10.0, 10.0),  # the ray from the centre leaves through the end face (x = 4.5 first)
    (30.0, 60.0),  # ... through the long face (y = 2 at 4 in, before x = 4.5 at 5.2 in)
])
def test_incidence_on_the_face_the_heading_meets(orientation: float, incidence: float) -> None:
    sim = lone(BOX, 16.0, orientation)
    aim = sim._aim("H-Sweep-1°", (6.0, 127.0))
    assert sonar.incidence_deg(aim) == pytest.approx(incidence, abs=1e-6)


def test_a_round_footprint_has_no_incidence() -> None:
    sim = lone("cup-8oz/upright", 16.0, 30.0)
    assert sonar.incidence_deg(sim._aim("H-Sweep-1°", (6.0, 127.0))) is None


SPECULAR = dataclasses.replace(CLEAN, specular_p=1.0)


@pytest.mark.parametrize("procedure, feature, step", [
    ("H-Sweep-1°", "Width-Degree-1°", 1.0), ("V-Sweep-5°", "Height-Degree-5°", 5.0)])
def test_a_grazing_face_loses_its_echo_and_a_square_one_does_not(procedure: str, feature: str, step: float) -> None:
    for orientation, grazing in ((30.0, True), (0.0, False), (10.0, False)):
        exact = lone(BOX, 16.0, orientation).sense(procedure).values[feature]
        got = [lone(BOX, 16.0, orientation, seed=s, noise=SPECULAR).sense(procedure).values[feature]
               for s in range(8)]
        assert exact is not None and exact > 2 * step
        if grazing:
            assert all(v is not None and v <= 0.5 * exact + step / 2 for v in got)
        else:
            assert got == [exact] * 8


def test_a_specular_miss_spares_the_hole_bits_and_the_s_sweep() -> None:
    exact = lone(BOX, 6.0, 30.0).sense("D-Scan-0.3").values
    got = lone(BOX, 6.0, 30.0, noise=SPECULAR).sense("D-Scan-0.3").values
    assert got["Top-Hole?"] == exact["Top-Hole?"] == 1.0
    assert got["Height"] <= 0.5 * exact["Height"]
    assert lone(BOX, 6.0, 30.0, noise=SPECULAR).sense("S-Sweep-1°").values == \
        lone(BOX, 6.0, 30.0).sense("S-Sweep-1°").values


def test_specular_misses_happen_at_their_rate_beyond_the_critical_angle() -> None:
    noise = dataclasses.replace(CLEAN, specular_p=0.3)
    rng = np.random.default_rng(5)
    assert within_binomial(sum(specular_miss(60.0, rng, noise) for _ in range(DRAWS)), DRAWS, 0.3)
    assert not any(specular_miss(a, rng, noise) for a in (None, 0.0, 10.0, noise.specular_angle_deg))


# -- odometry drift -----------------------------------------------------------------

def test_slip_is_a_random_walk_over_the_distance_driven() -> None:
    """Per axis N(0, drift² s): the variance grows in proportion to the distance."""
    rng = np.random.default_rng(9)
    short = np.array([slip(25.0, 0.1, rng) for _ in range(DRAWS)])
    long = np.array([slip(400.0, 0.1, rng) for _ in range(DRAWS)])
    # The sample variance of 2,000 normals is within ±13% of the true one at 4 sigma.
    assert np.var(short) == pytest.approx(0.01 * 25.0, rel=0.13)
    assert np.var(long) == pytest.approx(0.01 * 400.0, rel=0.13)
    assert slip(400.0, 0.0, rng) == (0.0, 0.0) and slip(0.0, 0.1, rng) == (0.0, 0.0)


def _shuttle(seed: int, legs: int) -> SimWorld:
    """Drive 100 in legs up and down the lab's clear west side with drift only."""
    sim = SimWorld("lab", seed, noise=dataclasses.replace(CLEAN, odometry_drift=0.1))
    for leg in range(legs):
        y = 130.0 if leg % 2 == 0 else 30.0
        result = sim.move([Pose(30.0, y, 90.0)], face=None)
        assert not result.collided
        # The robot believes it arrived; the truth is off by the drift so far.
        assert (result.pose.x_in, result.pose.y_in) == pytest.approx((30.0, y))
        assert (sim.pose.x_in - 30.0, sim.pose.y_in - y) == pytest.approx((sim.drift.dx_in, sim.drift.dy_in))
    return sim


def test_odometry_drift_accumulates_with_distance_travelled() -> None:
    """After n legs of 100 in, E|drift|² = 2 x 0.1² x 100 n = 2n in²; over 40 seeds the
    mean squared drift after 8 legs is far above that after 1."""
    one = [_shuttle(s, 1).drift.size_in ** 2 for s in range(40)]
    eight = [_shuttle(s, 8).drift.size_in ** 2 for s in range(40)]
    assert 0.5 < float(np.mean(one)) < 4.0
    assert 8.0 < float(np.mean(eight)) < 32.0
    assert np.mean(eight) > 3 * np.mean(one)


def test_the_reported_pose_is_the_truth_less_the_drift_and_resets() -> None:
    sim = _shuttle(4, 3)
    state = sim.state().pose
    assert (state.x_in, state.y_in) == pytest.approx((sim.pose.x_in - sim.drift.dx_in, sim.pose.y_in - sim.drift.dy_in))
    assert sim.drift.size_in > 0
    sim.load(sim.spec, 4)
    assert sim.drift.size_in == 0 and sim.state().pose == sim.pose


# -- camera orientation error -------------------------------------------------------

def _box_world(seed: int, sigma: float, yaw_deg: float = 20.0) -> SimWorld:
    data = {"room": {"width_in": 60, "depth_in": 60}, "robot": {"x_in": 12, "y_in": 12},
            "objects": [{"id": BOX, "x_in": 40, "y_in": 40, "yaw_deg": yaw_deg}]}
    spec = parse_world(data, "box.json", profile_and_catalogue()[1])
    return SimWorld(spec, seed, noise=dataclasses.replace(CLEAN, camera_yaw_deg=sigma))


def test_the_camera_draws_the_object_off_by_its_orientation_error() -> None:
    """The image is exactly that of a clean world with the box turned by the error."""
    straight = _box_world(0, 0.0).camera().pixels
    for seed in range(3):
        sim = _box_world(seed, 10.0)
        image = sim.camera().pixels
        box = sim.physics.objects[0]
        error = sim.camera_yaw.error(0, (box.x_in, box.y_in, box.yaw_deg), sim.noise, sim.rng)
        assert abs(error) > 0.5 and not np.array_equal(image, straight)
        assert np.array_equal(image, _box_world(0, 0.0, 20.0 + error).camera().pixels)
        assert np.array_equal(sim.camera().pixels, image)  # the same object at rest reads the same


def test_orientation_errors_have_the_configured_sigma_and_redraw_when_moved() -> None:
    rng, noise = np.random.default_rng(2), dataclasses.replace(CLEAN, camera_yaw_deg=6.0)
    errors = YawErrors()
    draws = [errors.error(0, (float(k), 0.0, 0.0), noise, rng) for k in range(DRAWS)]
    assert np.std(draws) == pytest.approx(6.0, rel=0.07)
    assert errors.error(0, (float(DRAWS - 1), 0.0, 0.0), noise, rng) == draws[-1]
    assert YawErrors().error(0, (0.0, 0.0, 0.0), CLEAN, rng) == 0.0
