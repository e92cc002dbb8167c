"""Clutter in the simulator (docs/simulator.md "Clutter"): the shipped close-together
world, the seeded neighbour generator, and a neighbour in the beam contaminating the
sonar's readings."""

from __future__ import annotations

import json
import math

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from experiments.worlds import random_floor
from hero_driver.sim.clutter import Clutter, cluttered, footprint_gap, pairs_of
from hero_driver.sim.noise import NoiseConfig
from hero_driver.sim.probe import approach_pose
from hero_driver.sim.catalogue import profile_and_catalogue
from hero_driver.sim.world import SimWorld
from hero_driver.sim.worldfile import WORLDS_DIR, footprint_polygon, load_world, parse_world

CATALOGUE = profile_and_catalogue()[1]
BASE_WIDTH_IN = 18.0  # twice the HERO's 9 in base radius
MAGAZINE = "magazine-box-9x4x7/upright"  # 9 x 4 in: its +x face 4 in wide, 4.5 in from its centre
SMALL_BOX = "closed-box-2x2x2/upright"


def gap(world: dict, i: int, j: int) -> float:
    def poly(o: dict) -> np.ndarray:
        return np.asarray(footprint_polygon(CATALOGUE[o["id"]].footprint, o["x_in"], o["y_in"], o["yaw_deg"]))
    return footprint_gap(poly(world["objects"][i]), poly(world["objects"][j]))


def test_the_shipped_clutter_world_has_a_pair_and_a_trio_within_a_base_width() -> None:
    world = json.loads((WORLDS_DIR / "clutter.json").read_text(encoding="utf-8"))
    load_world("clutter", CATALOGUE)  # the loader's checks: nothing overlaps, all inside
    assert pairs_of(world, CATALOGUE, 3.0) == [(0, 1), (2, 3), (2, 4)]
    assert pairs_of(world, CATALOGUE, BASE_WIDTH_IN) == [(0, 1), (2, 3), (2, 4), (3, 4)]  # the big box alone
    # by hand: tumbler r 1.85 at x 70, bottle r 1.35 at x 75.2: 5.2 - 3.2 = 2.0 in;
    # magazine y 108..112, small box y 114..116: 2.0 in; upside-down tumbler x 137.5 - 1.85 - 134.5 = 1.15 in
    assert gap(world, 0, 1) == pytest.approx(2.0, abs=0.01)
    assert gap(world, 2, 3) == pytest.approx(2.0, abs=1e-9)
    assert gap(world, 2, 4) == pytest.approx(1.15, abs=0.01)


def test_no_clutter_leaves_the_floor_as_it_was() -> None:
    floor = random_floor("test", 1)
    assert cluttered(floor, CATALOGUE, Clutter(0.0, 2.0), 1)["objects"] == floor["objects"]


@pytest.mark.slow
@settings(max_examples=15, deadline=None)
@given(seed=st.integers(0, 10_000), gap_in=st.floats(0.5, 12.0))
def test_full_clutter_pairs_objects_at_the_asked_gap_and_still_loads(seed: int, gap_in: float) -> None:
    floor = random_floor("test", seed)
    assert pairs_of(floor, CATALOGUE, BASE_WIDTH_IN) == []  # the experiment's floors are apart
    close = cluttered(floor, CATALOGUE, Clutter(1.0, gap_in), seed)
    parse_world(close, "<cluttered>", CATALOGUE)  # nothing overlaps, nothing outside the room
    pairs = pairs_of(close, CATALOGUE, gap_in + 0.01)
    assert pairs, "at least one pair placed"
    assert all(gap(close, i, j) == pytest.approx(gap_in, abs=0.01) for i, j in pairs)
    assert len({k for pair in pairs for k in pair}) == 2 * len(pairs)  # pairs, not heaps
    assert close == cluttered(floor, CATALOGUE, Clutter(1.0, gap_in), seed)  # seeded


def test_bad_clutter_settings_are_refused() -> None:
    with pytest.raises(ValueError, match="rate"):
        Clutter(1.5, 2.0)
    with pytest.raises(ValueError, match="gap_in"):
        Clutter(0.5, 0.0)


def reading(*neighbour: float, procedure: str = "H-Sweep-1°") -> tuple[float, dict[str, float]]:
    """The magazine box at (100, 100), yaw 0, sensed from (24, 0): the sonar at
    x = 100 + 4.5 + 24 = 128.5, y = 100; a 2 in box at ``neighbour`` if given."""
    objects = [{"id": MAGAZINE, "x_in": 100.0, "y_in": 100.0, "yaw_deg": 0.0}]
    if neighbour:
        objects.append({"id": SMALL_BOX, "x_in": neighbour[0], "y_in": neighbour[1], "yaw_deg": 0.0})
    world = parse_world({"name": "beam", "room": {"width_in": 200, "depth_in": 200},
                         "robot": {"x_in": 10, "y_in": 10, "heading_deg": 0}, "objects": objects}, "beam", CATALOGUE)
    sim = SimWorld(world, 0, noise=NoiseConfig.off())
    sim.pose = approach_pose(sim, 0, 24.0, 0.0)
    result = sim.sense(procedure)
    return result.distance_in, result.values


def test_a_neighbour_in_the_beam_contaminates_the_reading() -> None:
    clear = reading()
    assert clear[0] == pytest.approx(24.0) and clear[1]["Width-Degree-1°"] == 9.0  # 2 atan(2/24) = 9.5°
    # a 2 in box 4 in beside the beam (y 105..107): the reading is the object's own
    assert reading(110.5, 106.0) == clear
    # partly in the fan of rays to the face (y 101..103 at x 109.5..111.5; the ray to the
    # face's corner (104.5, 102) passes y 101.5 there): rays lost, the heading ray clear
    partly = reading(110.5, 102.0)
    assert partly[0] == pytest.approx(24.0) and partly[1]["Width-Degree-1°"] < 9.0
    # squarely in the way: the neighbour is measured instead, 128.5 - 113 = 15.5 in away;
    # its height 2 in below the 4 in sonar: -atan(4/15.5) .. atan(-2/17.5) -> 8 one-degree steps
    squarely = reading(112.0, 100.0, procedure="V-Sweep-1°")
    assert squarely[0] == pytest.approx(15.5)
    assert reading(procedure="V-Sweep-1°")[1]["Height-Degree-1°"] == 17.0
    assert squarely[1]["Height-Degree-1°"] == 8.0 == math.floor(math.degrees(math.atan(4 / 15.5))) - \
        math.ceil(math.degrees(math.atan(2 / 17.5))) + 1
