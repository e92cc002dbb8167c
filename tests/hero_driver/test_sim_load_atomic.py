"""``SimWorld.load`` keeps nothing of a load that fails part-way: it used to keep the
new spec and seed before the rest was built, so one bad reset left the world half
loaded and every later reset of "the current world" failed the same way."""

from __future__ import annotations

import dataclasses

import pytest

from hero_driver.interface import Pose
from hero_driver.sim.world import SimWorld

SEED = 3


def _state(sim: SimWorld) -> tuple[object, ...]:
    """What a reset replaces, by value or identity (the physics, battery and
    disturber are built afresh by every load)."""
    return (sim.spec, sim.seed, id(sim.physics), sim.rng.bit_generator.state, sim.pose, sim.clock_s,
            id(sim.battery), sim.battery.level, id(sim.disturber), sim.noise, sim.drift, sim.contacts)


@pytest.fixture
def moved() -> SimWorld:
    """The lab world (robot starting at 30, 30) after one move: not at its start any more."""
    sim = SimWorld("lab", seed=SEED)
    sim.move([Pose(40.0, 30.0, 0.0)], None)
    assert sim.clock_s > 0.0
    return sim


def _fresh_reset_works(sim: SimWorld) -> None:
    """A reset of the current world now gives what a new world with its seed gives."""
    sim.load(sim.spec, sim.seed)
    fresh = SimWorld("lab", seed=SEED)
    assert sim.seed == SEED
    assert sim.clock_s == 0.0
    assert sim.pose == fresh.pose == Pose(30.0, 30.0, 0.0)  # hero_driver/worlds/lab.json
    assert sim.truth() == fresh.truth()
    assert sim.rng.random(4).tolist() == fresh.rng.random(4).tolist()


def test_a_spec_whose_battery_cannot_be_built_leaves_the_world_as_it_was(moved: SimWorld) -> None:
    before = _state(moved)
    bad = dataclasses.replace(moved.spec, battery=1.5)
    with pytest.raises(ValueError, match=r"^battery level must be in \[0, 1\], got 1\.5$"):
        moved.load(bad, SEED + 1)
    assert _state(moved) == before
    _fresh_reset_works(moved)


def test_a_seed_numpy_refuses_leaves_the_world_as_it_was(moved: SimWorld) -> None:
    before = _state(moved)
    with pytest.raises(ValueError):
        moved.load(moved.spec, -1)
    assert _state(moved) == before
    _fresh_reset_works(moved)


def test_a_start_overlapping_furniture_leaves_the_world_as_it_was(moved: SimWorld) -> None:
    before = _state(moved)
    blocked = dataclasses.replace(moved.spec, robot=(0.0, 0.0, 0.0))  # the base half through two walls
    with pytest.raises(ValueError, match=r"robot: base at \(0, 0\) overlaps a wall, furniture or object$"):
        moved.load(blocked, SEED)
    assert _state(moved) == before
    _fresh_reset_works(moved)
