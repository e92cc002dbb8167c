"""The simulator's range scan (docs/simulator.md, "Scans"): ray casting worked out by
hand in rectangular rooms, the two scanner models, glass, the scan plane, the reported
pose of a drifting base, the noise of each preset, and a random stream of its own."""

from __future__ import annotations

import dataclasses
import math

import numpy as np
import pytest

from hero_driver.interface import Pose
from hero_driver.sim.catalogue import profile_and_catalogue
from hero_driver.sim.noise import NOISE_PRESETS, NoiseConfig
from hero_driver.sim.odometry import Drift
from hero_driver.sim.scan import beam_angles, scan_rng, scanner_of
from hero_driver.sim.world import SimWorld
from hero_driver.sim.worldfile import parse_world
from hero_driver.sim_driver import SimulatedHero
from robot_profile import SCANNER_DEFAULTS, ScannerSpec, load_profile, profile_from_dict

CLEAN = NoiseConfig.off()
PROFILE = load_profile()


def scanner(model: str, **changes: object) -> ScannerSpec:
    return ScannerSpec(model=model, **{**SCANNER_DEFAULTS[model], **changes})  # type: ignore[arg-type]


def world(width: float, depth: float, robot: tuple[float, float, float], *, furniture: tuple[dict, ...] = (),
          objects: tuple[dict, ...] = (), movers: tuple[dict, ...] = (), model: str = "lidar",
          noise: NoiseConfig = CLEAN, seed: int = 0, **scanner_changes: object) -> SimWorld:
    """A rectangular room with the robot at ``robot`` and the given scanner."""
    data = {"room": {"width_in": width, "depth_in": depth},
            "robot": {"x_in": robot[0], "y_in": robot[1], "heading_deg": robot[2]},
            "furniture": list(furniture), "objects": list(objects), "movers": list(movers)}
    profile = dataclasses.replace(PROFILE, scanner=scanner(model, **scanner_changes))
    spec = parse_world(data, "scan-test.json", profile_and_catalogue(profile)[1])
    return SimWorld(spec, seed, profile, noise)


def at(scan_ranges: tuple[float, ...], angles: tuple[float, ...], angle: float) -> float:
    return scan_ranges[angles.index(angle)]


# -- ray casting, worked out by hand ---------------------------------------------------

def test_a_lidar_reads_the_walls_of_a_rectangular_room() -> None:
    """Room 200 x 100, robot at (50, 40) facing +x: the walls are 150 ahead, 60 to the
    left, 50 behind and 40 to the right; the corner (200, 100) is 150 x 60 away."""
    scan = world(200, 100, (50, 40, 0)).scan()
    assert len(scan.angles_deg) == 360 and scan.angles_deg[0] == -180.0 and scan.angles_deg[-1] == 179.0
    for angle, expected in ((0.0, 150.0), (90.0, 60.0), (-180.0, 50.0), (-90.0, 40.0)):
        assert at(scan.ranges_in, scan.angles_deg, angle) == pytest.approx(expected)
    corner = math.degrees(math.atan2(60, 150))  # 21.8 deg: the beam at 21 meets the far wall, at 22 the left one
    assert at(scan.ranges_in, scan.angles_deg, 21.0) == pytest.approx(150 / math.cos(math.radians(21)))
    assert at(scan.ranges_in, scan.angles_deg, 22.0) == pytest.approx(60 / math.sin(math.radians(22)))
    assert 21 < corner < 22
    assert (scan.range_min_in, scan.range_max_in) == (0.5, 480.0)


def test_angles_are_in_the_robots_frame() -> None:
    """Facing +y (heading 90), the beam straight ahead meets the wall 60 away, the one
    at -90 (the robot's right, world +x) the wall 150 away."""
    scan = world(200, 100, (50, 40, 90)).scan()
    assert at(scan.ranges_in, scan.angles_deg, 0.0) == pytest.approx(60.0)
    assert at(scan.ranges_in, scan.angles_deg, -90.0) == pytest.approx(150.0)
    assert at(scan.ranges_in, scan.angles_deg, 90.0) == pytest.approx(50.0)


@pytest.mark.parametrize("entry_id, expected", [
    ("tumbler-32oz/upright", 70.0 - 2.0),  # a disc of radius 2 centred 70 ahead
    ("closed-box-11x9x12/upright", 70.0 - 5.5),  # an 11 in long box along x: its face 5.5 before its centre
])
def test_an_object_of_known_footprint_at_a_known_distance(entry_id: str, expected: float) -> None:
    scan = world(200, 100, (50, 40, 0), objects=({"id": entry_id, "x_in": 120, "y_in": 40},)).scan()
    assert at(scan.ranges_in, scan.angles_deg, 0.0) == pytest.approx(expected)
    assert at(scan.ranges_in, scan.angles_deg, 10.0) == pytest.approx(150 / math.cos(math.radians(10)))  # past it


def test_an_object_lower_than_the_scan_plane_is_not_seen() -> None:
    """The 2 in box stands above the lidar's 1.5 in plane; a plane at 3 in passes over it."""
    box = ({"id": "closed-box-2x2x2/upright", "x_in": 120, "y_in": 40},)
    low = world(200, 100, (50, 40, 0), objects=box).scan()
    high = world(200, 100, (50, 40, 0), objects=box, height_in=3.0).scan()
    assert at(low.ranges_in, low.angles_deg, 0.0) == pytest.approx(69.0)
    assert at(high.ranges_in, high.angles_deg, 0.0) == pytest.approx(150.0)


def test_a_person_crossing_is_seen() -> None:
    """A person (a disc of radius 9) 30 in along a path from (120, 10) to (120, 90)
    stands at (120, 40), straight ahead: the beam stops 70 - 9 in away; a sonar's
    sensing looks past people, a range scan does not."""
    person = ({"shape": "disc", "path": [[120, 10], [120, 90]], "speed_in_s": 1, "start_in": 30},)
    scan = world(200, 100, (50, 40, 0), movers=person).scan()
    assert at(scan.ranges_in, scan.angles_deg, 0.0) == pytest.approx(61.0)


def test_beyond_the_maximum_range_nothing_echoes() -> None:
    scan = world(200, 100, (50, 40, 0), range_in=(0.5, 100.0)).scan()
    assert at(scan.ranges_in, scan.angles_deg, 0.0) == math.inf  # the wall is 150 away
    assert at(scan.ranges_in, scan.angles_deg, 90.0) == pytest.approx(60.0)


PANE = {"name": "pane", "x_in": 101, "y_in": 50, "width_in": 2, "depth_in": 100}  # x 100-102, wall to wall


def test_glass_passes_a_lidars_light_and_echoes_a_sonars_sound() -> None:
    glass = world(200, 100, (50, 40, 0), furniture=({**PANE, "glass": True},)).scan()
    wall = world(200, 100, (50, 40, 0), furniture=(PANE,)).scan()
    sonar = world(200, 100, (50, 40, 0), furniture=({**PANE, "glass": True},), model="sonar").scan()
    assert at(glass.ranges_in, glass.angles_deg, 0.0) == pytest.approx(150.0)
    assert at(wall.ranges_in, wall.angles_deg, 0.0) == pytest.approx(50.0)
    assert at(sonar.ranges_in, sonar.angles_deg, 0.0) == pytest.approx(50.0)


def test_the_swept_sonar_reads_the_nearest_echo_in_its_cone() -> None:
    """Room 100 x 60, robot at (40, 30) facing +x; beams every 15 deg, 30 deg wide.
    Beam 0 and beam 15 both hold the far wall's normal (60 away) in their cone; beam 30
    (cone 15-45) is nearest along its 45 deg edge, to the wall y = 60: 30 / sin 45;
    beam 45 (cone 30-60) along its 60 deg edge: 30 / sin 60."""
    scan = world(100, 60, (40, 30, 0), model="sonar").scan()
    assert scan.angles_deg == tuple(-180.0 + 15.0 * k for k in range(24))
    assert (scan.range_min_in, scan.range_max_in) == (12.0, 127.0)
    assert at(scan.ranges_in, scan.angles_deg, 0.0) == pytest.approx(60.0)
    assert at(scan.ranges_in, scan.angles_deg, 15.0) == pytest.approx(60.0)
    assert at(scan.ranges_in, scan.angles_deg, 30.0) == pytest.approx(30 / math.sin(math.radians(45)))
    assert at(scan.ranges_in, scan.angles_deg, 45.0) == pytest.approx(30 / math.sin(math.radians(60)))
    assert at(scan.ranges_in, scan.angles_deg, 90.0) == pytest.approx(30.0)


def test_nearer_than_the_sensor_measures_is_no_echo() -> None:
    scan = world(100, 60, (40, 10, 0), model="sonar").scan()  # the wall y = 0 is 10 in to the right
    assert at(scan.ranges_in, scan.angles_deg, -90.0) == math.inf


def test_a_drifting_base_scans_from_the_truth_and_stamps_what_its_encoders_say() -> None:
    sim = world(200, 100, (50, 40, 0))
    sim.drift = Drift(5.0, -3.0)  # true minus reported
    scan = sim.scan()
    assert scan.pose == Pose(45.0, 43.0, 0.0) == sim.state().pose
    assert at(scan.ranges_in, scan.angles_deg, 0.0) == pytest.approx(150.0)  # from the true (50, 40)


def test_a_scan_takes_the_scanners_time_and_moves_nothing() -> None:
    sim = world(100, 60, (40, 30, 0), model="sonar")
    before = sim.state()
    scan = sim.scan()
    assert scan.clock_s == before.clock_s + 90.0 == sim.state().clock_s
    assert sim.state().pose == before.pose


def test_the_simulator_scans_with_the_profiles_scanner_or_else_a_lidar() -> None:
    assert scanner_of(PROFILE) == scanner("lidar")  # hero2000.toml: model = "lidar"
    bare = dataclasses.replace(PROFILE, scanner=None)
    assert scanner_of(bare) == scanner("lidar")
    assert beam_angles(scanner("sonar"))[:3] == (-180.0, -165.0, -150.0)


def test_every_shipped_world_is_scanned() -> None:
    """``csl driver sim`` serves scans on every world: the lab's start sees its walls."""
    hero = SimulatedHero("s", world="lab", noise=CLEAN)
    scan = hero.scan().result()
    assert at(scan.ranges_in, scan.angles_deg, 0.0) == pytest.approx(210.0)  # lab.json: (30, 30), the wall x = 240
    assert at(scan.ranges_in, scan.angles_deg, 90.0) == pytest.approx(131.0)  # the cabinet's front at y = 161


# -- the profile's [scanner] table ------------------------------------------------------

def _profile(scanner_table: dict[str, object]) -> dict[str, object]:
    import tomllib

    from robot_profile import DEFAULT_PROFILE

    data = tomllib.loads(DEFAULT_PROFILE.read_text(encoding="utf-8"))
    return {**data, "scanner": scanner_table}


def test_a_profile_chooses_the_model_and_overrides_its_values() -> None:
    read = profile_from_dict(_profile({"model": "sonar", "beams": 36, "time_s": 60}), "p.toml")
    assert read.scanner == scanner("sonar", beams=36, time_s=60.0)
    assert read.scanner.step_deg == 10.0


@pytest.mark.parametrize("table, message", [
    ({"model": "radar"}, "p.toml: [scanner]: 'model' must be one of lidar, sonar, got 'radar'"),
    ({"model": "lidar", "beams": 0}, "p.toml: [scanner]: 'beams' must be a whole number from 1 to 3600, got 0"),
    ({"model": "lidar", "range_in": [5, 5]},
     "p.toml: [scanner]: 'range_in' must be [low, high] with 0 <= low < high, got [5, 5]"),
    ({"model": "lidar", "specular_deg": 95}, "p.toml: [scanner]: 'specular_deg' must be at most 90, got 95"),
    ({"model": "lidar", "fov_deg": 270}, "p.toml: [scanner]: unknown key 'fov_deg' (allowed: beam_deg, beams, "
                                         "height_in, model, range_in, specular_deg, through_glass, time_s)"),
    ({"model": "lidar", "through_glass": "yes"}, "p.toml: [scanner]: 'through_glass' must be true or false"),
])
def test_a_bad_scanner_table_fails_in_one_line(table: dict[str, object], message: str) -> None:
    with pytest.raises(ValueError) as info:
        profile_from_dict(_profile(table), "p.toml")
    assert str(info.value) == message


def test_a_glass_field_that_is_not_a_flag_fails_in_one_line() -> None:
    data = {"room": {"width_in": 100, "depth_in": 100}, "robot": {"x_in": 20, "y_in": 20},
            "furniture": [{**PANE, "x_in": 50, "depth_in": 10, "glass": "yes"}]}
    with pytest.raises(ValueError) as info:
        parse_world(data, "w.json", profile_and_catalogue()[1])
    assert str(info.value) == "w.json: furniture[0]: field 'glass' must be true or false, got 'yes'"


# -- noise ------------------------------------------------------------------------------

def within_binomial(hits: int, n: int, p: float) -> bool:
    """Within 4 standard deviations of n p (the draws are seeded: fixed either way)."""
    return abs(hits - n * p) <= 4.0 * math.sqrt(n * p * (1.0 - p)) + 1e-9


@pytest.mark.parametrize("preset", list(NOISE_PRESETS))
def test_range_noise_and_dropouts_follow_each_preset(preset: str) -> None:
    """A square room 200 x 200, robot at its centre: every beam meets a wall square to
    within 45 deg (no grazing), 100 / cos of its angle away. Over 20 scans the share of
    beams lost is the preset's dropout rate, and the relative errors of the rest have
    mean 0 and sigma ``scan_range_frac``."""
    noise = NoiseConfig.preset(preset)
    sim = world(200, 200, (100, 100, 0), noise=noise, seed=7)
    exact = world(200, 200, (100, 100, 0)).scan().ranges_in
    lost, errors = 0, []
    for _ in range(20):
        for got, true in zip(sim.scan().ranges_in, exact, strict=True):
            if math.isinf(got):
                lost += 1
            else:
                errors.append((got - true) / true)
    n = 20 * 360
    assert within_binomial(lost, n, noise.scan_dropout_p)
    spread = np.asarray(errors)
    if noise.scan_range_frac == 0:
        assert np.all(spread == 0)
    else:
        assert abs(spread.mean()) < 4 * noise.scan_range_frac / math.sqrt(len(spread))
        assert spread.std() == pytest.approx(noise.scan_range_frac, rel=0.05)


@pytest.mark.parametrize("preset", ["clean", "paper", "harsh"])
def test_grazing_beams_are_lost_at_the_specular_rate(preset: str) -> None:
    """A corridor 400 x 40, robot in its middle facing along it. The beams 6 to 9 deg off
    its axis meet a side wall (20 / sin a before the end wall's 200 / cos a: tan a > 0.1)
    81 to 84 deg off its normal, beyond the lidar's specular angle (80); every other beam
    meets a wall within 80 deg of square (up to 5 deg off the axis, the end wall). Only
    the grazing ones are lost, at ``scan_specular_p`` (dropouts off here)."""
    noise = dataclasses.replace(NoiseConfig.preset(preset), scan_dropout_p=0.0)
    sim = world(400, 40, (200, 20, 0), noise=noise, seed=3)
    angles = sim.scan().angles_deg
    grazing = [i for i, a in enumerate(angles) if 6 <= abs(a) <= 9 or 171 <= abs(a) <= 174]
    square = [i for i, a in enumerate(angles) if i not in grazing and abs(a) not in (10, 170)]  # 10: on the edge
    lost_grazing = lost_square = 0
    for _ in range(30):
        ranges = sim.scan().ranges_in
        lost_grazing += sum(math.isinf(ranges[i]) for i in grazing)
        lost_square += sum(math.isinf(ranges[i]) for i in square)
    assert lost_square == 0
    assert within_binomial(lost_grazing, 30 * len(grazing), noise.scan_specular_p)


def test_a_mirrored_sonar_beam_keeps_the_echoes_met_square_on() -> None:
    """Every sub-ray of the beam at 45 meets the wall y = 60 more than 15 deg off its
    normal: under certain specular loss the beam hears nothing; the beam at 90 meets it
    square on and still reads 30."""
    noise = dataclasses.replace(CLEAN, scan_specular_p=1.0)
    scan = world(100, 60, (40, 30, 0), model="sonar", noise=noise).scan()
    assert at(scan.ranges_in, scan.angles_deg, 45.0) == math.inf
    assert at(scan.ranges_in, scan.angles_deg, 90.0) == pytest.approx(30.0)


def test_scans_do_not_change_any_other_draw_of_a_seeded_run() -> None:
    """The scan's noise is its own stream: an episode with scans between its verbs moves,
    senses and ends exactly as one without them, under the noisiest preset."""
    def run(scanning: bool) -> tuple[object, ...]:
        hero = SimulatedHero("r", world="lab", seed=5, noise=NoiseConfig.preset("harsh"))
        seen = []
        for goal in (Pose(60.0, 45.0, 0.0), Pose(100.0, 45.0, 0.0)):
            if scanning:
                hero.scan().result()
            seen.append(hero.move([goal], face=(120.0, 45.0)).result().pose)
            seen.append(hero.sense("H-Sweep-5°").result().values)
        return (*seen, hero.world.rng.random(), hero.world.drift)

    assert run(False)[:-2] == run(True)[:-2]  # the clock differs by the scans' time, nothing else
    assert run(False)[-2:] == run(True)[-2:]


def test_the_scan_stream_is_seeded_from_the_world_seed() -> None:
    assert scan_rng(4).random() == scan_rng(4).random() != scan_rng(5).random()
    first = world(200, 200, (100, 100, 0), noise=NoiseConfig.preset("paper"), seed=4)
    again = world(200, 200, (100, 100, 0), noise=NoiseConfig.preset("paper"), seed=4)
    one = first.scan().ranges_in
    assert one == again.scan().ranges_in
    assert first.scan().ranges_in != one  # the stream goes on
    first.load(first.spec, 4)  # a reset restarts it
    assert first.scan().ranges_in == one
