"""The world file's ``battery_drain``: one multiplier on the simulator's documented
drain rates (docs/simulator.md, Battery), the battery study's swept disturbance rate."""

from __future__ import annotations

import json
import math
from pathlib import Path

import pytest
from hypothesis import given
from hypothesis import strategies as st

from hero_driver.interface import Pose
from hero_driver.sim.battery import CHARGING_PER_S, Battery, Charge
from hero_driver.sim.noise import NoiseConfig
from hero_driver.sim.world import SimWorld

ROOM = {"width_in": 120, "depth_in": 100}
DOCK = {"x_in": 20, "y_in": 70, "heading_deg": 180}


def world(tmp_path: Path, **extra: object) -> SimWorld:
    data = {"name": "drain", "room": ROOM, "robot": {"x_in": 20, "y_in": 20, "heading_deg": 0},
            "objects": [{"id": "closed-box-10x10x10/upright", "x_in": 80, "y_in": 20}], **extra}
    path = tmp_path / "drain.json"
    path.write_text(json.dumps(data), encoding="utf-8")
    return SimWorld(path, seed=0, noise=NoiseConfig.preset("clean"))


@pytest.mark.parametrize("drain", [1, 2, 4, 8])
def test_a_45_s_move_drains_45_over_18000_times_the_multiplier(tmp_path: Path, drain: int) -> None:
    sim = world(tmp_path, battery=0.5, battery_drain=drain)
    # 20 in straight ahead at 0.5 in/s plus 5 s of vision: 45 s at 1/18000 a second
    assert sim.move([Pose(40.0, 20.0, 0.0)], None).duration_s == pytest.approx(45.0)
    assert sim.state().battery == pytest.approx(0.5 - 45.0 * drain / 18000.0)  # x8: 0.48


def test_the_multiplier_alone_meters_a_full_battery_and_charging_keeps_its_rate(tmp_path: Path) -> None:
    sim = world(tmp_path, battery_drain=4, dock=DOCK)
    sim.move([Pose(40.0, 20.0, 0.0)], None)
    assert sim.state().battery == pytest.approx(1.0 - 45.0 * 4 / 18000.0)  # 0.99
    battery = Battery(Charge(0.5, 8.0))
    assert battery.charge() == pytest.approx(0.5 / CHARGING_PER_S)  # 900 s, as at x1


@given(st.floats(0.0, 1.0), st.floats(0.0, 1e4), st.floats(1e-3, 1e-3 * 64), st.sampled_from([0.5, 2.0, 3.0]))
def test_the_drain_scales_linearly_until_empty(level: float, seconds: float, per_s: float, m: float) -> None:
    one, scaled = Battery(level), Battery(Charge(level, m))
    one.drain(seconds * m, per_s)  # m times as long at x1 is the same charge as x m
    scaled.drain(seconds, per_s)
    assert scaled.level == pytest.approx(one.level)
    assert scaled.level == pytest.approx(max(0.0, level - seconds * per_s * m))


@pytest.mark.parametrize("value, problem", [
    (0, "'battery_drain' must be a multiplier > 0 on the drain rates, got 0"),
    (-2, "'battery_drain' must be a number >= 0.0, got -2"),
    ("x2", "'battery_drain' must be a number >= 0.0, got 'x2'"),
    (True, "'battery_drain' must be a number >= 0.0, got True"),
    (math.nan, "'battery_drain' must be a number >= 0.0, got nan"),
])
def test_a_bad_multiplier_is_refused_naming_the_field(tmp_path: Path, value: object, problem: str) -> None:
    with pytest.raises(ValueError) as refused:
        world(tmp_path, battery_drain=value)
    assert problem in str(refused.value) and "\n" not in str(refused.value)


@pytest.mark.parametrize("drain", [0.0, -1.0, math.nan, math.inf])
def test_a_charge_refuses_a_multiplier_that_is_not_positive_and_finite(drain: float) -> None:
    with pytest.raises(ValueError, match="battery drain must be a number > 0"):
        Charge(0.5, drain)
