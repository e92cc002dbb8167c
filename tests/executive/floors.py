"""One experiment floor played in the simulator with the library the experiment
trains: the shared set-up of the whole-episode tests that compare two settings of the
executive on the same floor.

Training in the simulator is the dearest set-up of the suite's episode tests, and every
one of them trains the same way, so it happens once per test process (per pytest-xdist
worker): :func:`sim_training` is cached, and every test module that needs the trained
library or the training itself takes it from here."""

from __future__ import annotations

from functools import cache
from pathlib import Path

from behaviours.services import Params
from executive.executive import Executive
from experiments.floor import play
from experiments.worlds import write_floor
from executive.sim_training import SimTraining, train_in_simulator
from hero_driver.interface import OUT_OF_RANGE
from hero_driver.sim.noise import NoiseConfig
from hero_driver.sim_driver import SimulatedHero
from learner.description import ObjectDescription
from learner.service.local import LocalLearner
from robot_profile import load_profile


@cache
def sim_training() -> SimTraining:
    """`csl train --sim` on the shipped profile (seed 0, no noise), as the experiment's
    training study runs it; once per test process. Read it, never change it."""
    profile = load_profile()
    return train_in_simulator(profile.knowledge(), profile)


@cache
def trained() -> tuple[ObjectDescription, ...]:
    """The library `csl experiment paper` trains in the simulator."""
    return tuple(sim_training().result.descriptions)


def play_floor(folder: Path, floor_seed: int, noise: NoiseConfig,
               params: Params) -> tuple[list[dict[str, object]], list[bool]]:
    """The unseen test objects laid out as the experiment's floor ``floor_seed``, played
    to the end in ``folder`` (made here): the episode's events and, per record, whether
    its object was handled right."""
    folder.mkdir()
    world = write_floor(folder, "test", floor_seed)
    hero = SimulatedHero("r1", world=world, seed=floor_seed, noise=noise)
    learner = LocalLearner(folder / "library.sqlite", seed_library=list(trained()))
    executive = Executive(hero, learner, params=params)
    played = play(hero, executive, closing=(learner,))
    return list(played.events), [bool(r.correct) for _, r in played.rows()]


def refused_for_range(events: list[dict[str, object]]) -> list[int]:
    """The index of every event that is a refusal for range."""
    return [i for i, e in enumerate(events) if e["event"] == "driver_error" and e.get("code") == OUT_OF_RANGE]
