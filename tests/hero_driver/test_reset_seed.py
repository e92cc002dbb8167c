"""``reset`` with a negative seed: the simulated driver refuses it with ``bad_request``
naming the field, in process and over zenoh, and the refusal leaves the world as it
was (numpy's refusal used to come after the world had kept the bad seed, so every
later ``reset`` without a seed failed too)."""

from __future__ import annotations

import pytest
import zenoh
from hypothesis import given, settings
from hypothesis import strategies as st

from hero_driver.interface import BAD_REQUEST, DriverError, Pose
from hero_driver.sim_driver import SimulatedHero
from hero_driver.zenoh_link.client import ZenohDriver
from hero_driver.zenoh_link.node import DriverNode

REPLY_S = 10.0


def _refusal(hero: SimulatedHero | ZenohDriver, seed: int) -> DriverError:
    with pytest.raises(DriverError) as caught:
        hero.reset(None, seed).result(REPLY_S)
    return caught.value


@settings(max_examples=25, deadline=None)
@given(st.integers(max_value=-1))
def test_a_negative_seed_is_refused_naming_the_field(seed: int) -> None:
    hero = SimulatedHero("r1", seed=4)
    error = _refusal(hero, seed)
    assert (error.code, error.message) == (BAD_REQUEST, f"seed: expected a non-negative integer, got {seed}")


def test_the_refusal_leaves_the_world_and_its_seed_as_they_were() -> None:
    hero = SimulatedHero("r1", seed=4)
    start = hero.state().pose
    hero.move([Pose(start.x_in + 20, start.y_in, 0)]).result(REPLY_S)
    _refusal(hero, -1)
    assert hero.state().pose != start  # nothing was reloaded
    assert hero.reset().result(REPLY_S).pose == start  # a reset without a seed still works ...
    image = hero.camera().result(REPLY_S).pixels  # the camera's pixel noise comes from the seeded stream
    assert (image == SimulatedHero("r1", seed=4).camera().result(REPLY_S).pixels).all()  # ... with seed 4
    assert (image != SimulatedHero("r1", seed=5).camera().result(REPLY_S).pixels).any()


@pytest.mark.zenoh
def test_over_zenoh_the_client_gets_bad_request_naming_the_seed(server: zenoh.Session, endpoint: str) -> None:
    with DriverNode(SimulatedHero("r1"), server), ZenohDriver("r1", connect=[endpoint], discover_s=5.0) as client:
        assert client.wait_ready(5.0)
        error = _refusal(client, -7)
        assert (error.code, error.message) == (BAD_REQUEST, "seed: expected a non-negative integer, got -7")
        assert client.reset(None, 7).result(REPLY_S).clock_s == 0  # not busy, not poisoned
