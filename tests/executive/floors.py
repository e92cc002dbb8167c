"""One experiment floor played in the simulator with the library the experiment
trains: the shared set-up of the whole-episode tests that compare two settings of the
executive on the same floor."""

from __future__ import annotations

from functools import cache
from pathlib import Path

from behaviours.services import Params
from executive.executive import Executive
from experiments.floor import play
from experiments.study_training import run_training
from experiments.worlds import write_floor
from hero_driver.interface import OUT_OF_RANGE
from hero_driver.sim.noise import NoiseConfig
from hero_driver.sim_driver import SimulatedHero
from learner.description import ObjectDescription
from learner.service.local import LocalLearner
from robot_profile import load_profile


@cache
def trained() -> tuple[ObjectDescription, ...]:
    """The library `csl experiment paper` trains in the simulator (once per test run)."""
    return tuple(run_training(load_profile()).descriptions)


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
