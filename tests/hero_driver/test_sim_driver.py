"""SimulatedHero as a Driver: settled futures, errors as DriverError, reset, close,
ground truth, and whole episodes repeatable per seed."""

from __future__ import annotations

import dataclasses
import hashlib

import pytest

from hero_driver.interface import (
    BAD_REQUEST, NO_TARGET, UNAVAILABLE, UNKNOWN_PROCEDURE, DriverError, Driver, Pose,
)
from hero_driver.sim.noise import NoiseConfig
from hero_driver.sim.probe import approach_pose
from hero_driver.sim.world import ObjectTruth
from hero_driver.sim_driver import SimulatedHero


def test_is_a_driver_with_settled_futures() -> None:
    hero = SimulatedHero(noise=NoiseConfig.off())
    assert isinstance(hero, Driver) and hero.robot == "r1"
    for future in (hero.camera(), hero.sense("H-Sweep-1°"), hero.grasp("Front-Wrap"), hero.release(),
                   hero.move([Pose(30.0, 40.0, 90.0)])):
        assert future.done()
    assert isinstance(hero.sense("Sniff").exception(), DriverError)
    assert hero.sense("Sniff").exception().code == UNKNOWN_PROCEDURE
    assert hero.grasp("Front-Wrap").exception().code == NO_TARGET


def test_truth_reports_every_object() -> None:
    hero = SimulatedHero(world="lab", noise=NoiseConfig.off())
    truth = hero.truth()
    assert [t.index for t in truth] == list(range(len(truth)))
    first = truth[0]
    assert isinstance(first, ObjectTruth) and first.entry_id == "closed-box-2x2x2/upright"
    assert (first.x_in, first.y_in, first.held, first.binned) == (70.0, 60.0, False, False)
    with pytest.raises(dataclasses.FrozenInstanceError):
        first.x_in = 0.0  # type: ignore[misc]


def test_reset_restores_the_world_and_close_makes_it_unavailable() -> None:
    hero = SimulatedHero(noise=NoiseConfig.off())
    before = hero.truth()
    hero.move([Pose(30.0, 80.0, 0.0)], face=(60.0, 115.0)).result()
    assert hero.state().clock_s > 0
    state = hero.reset().result()
    assert state.clock_s == 0 and state.pose == Pose(30.0, 30.0, 0.0) and hero.truth() == before
    hero.reset(world="training").result()
    assert len(hero.truth()) == 14
    assert hero.reset(world="no-such-world").exception().code == BAD_REQUEST
    hero.close()
    assert hero.camera().exception().code == UNAVAILABLE
    with pytest.raises(DriverError):
        hero.state()


def _episode(seed: int) -> list[object]:
    """A scripted lab episode with default noise: every observable result."""
    hero = SimulatedHero(seed=seed)
    trace: list[object] = [hashlib.sha1(hero.camera().result().pixels.tobytes()).hexdigest()]
    for index in (1, 3):
        target = hero.truth()[index]
        for d, procs in ((24.0, ("H-Sweep-1°", "V-Sweep-5°")), (6.0, ("H-Scan-0.3", "D-Scan-0.3"))):
            move = hero.move([approach_pose(hero.world, index, d, 180.0)], face=(target.x_in, target.y_in))
            trace.append(move.result())
            for p in procs:
                future = hero.sense(p)
                trace.append(future.exception() and str(future.exception()) or future.result())
        grasp = hero.grasp("Top-Pinch")
        trace.append(grasp.exception() and str(grasp.exception()) or grasp.result())
        trace.append(hero.last_side_effect)
        hero.release()
    trace.append(hero.truth())
    trace.append(hashlib.sha1(hero.camera().result().pixels.tobytes()).hexdigest())
    return trace


def test_whole_episodes_repeat_per_seed() -> None:
    assert _episode(11) == _episode(11)
    assert _episode(11) != _episode(12)


def test_world_noise_is_overridden_by_the_constructor() -> None:
    exact = SimulatedHero(noise=NoiseConfig.off())
    assert exact.world.noise == NoiseConfig.off()
    assert SimulatedHero().world.noise == NoiseConfig()
