"""One floor played to its end in the simulator: what every study's job does.

A study's job differs in its world, its settings and what it reads off the episode;
the play itself is the same everywhere: the simulated HERO on the floor's world file,
a learner store seeded with the trained library, the executive run to the end and
shut down, and the ground truth of every object before and after (a tumbler knocked
over and grasped as a lying one was handled right by what it is now). So it is
written once here, and a study module keeps only what is its own.
"""

from __future__ import annotations

import tempfile
from collections.abc import Callable, Mapping, Sequence
from dataclasses import dataclass
from pathlib import Path
from typing import Any

from behaviours.records import ObjectRecord
from behaviours.services import Params
from executive.executive import EpisodeResult, Executive
from experiments.conditions import EXECUTION_NOISE, noise_config
from experiments.worker import installed_library, installed_profile
from reporting.report import Row, Truth, rows
from hero_driver.interface import Driver
from hero_driver.sim.disturber import Happened
from hero_driver.sim.world import ObjectTruth
from hero_driver.sim_driver import SimulatedHero
from learner.service.local import LocalLearner


@dataclass(frozen=True)
class Played:
    """A floor after its episode: the executive's result and events, and the ground
    truth the simulator kept."""

    result: EpisodeResult
    events: Sequence[Mapping[str, Any]]
    start: Sequence[ObjectTruth]
    now: Sequence[ObjectTruth]
    disturbances: Sequence[Happened]
    contacts: int

    def truths(self, *, judged_now: bool = True) -> list[Truth]:
        """Every object named by what it was at the start and judged by its grasps now
        (``judged_now``) or at the start."""
        after = self.now if judged_now else self.start
        return [Truth(s.entry_id, tuple(g.procedure for g in n.grasps), s.x_in, s.y_in)
                for s, n in zip(self.start, after)]

    def rows(self, *, judged_now: bool = True) -> list[tuple[ObjectRecord, Row]]:
        """Each object the executive worked on, with its report row."""
        return list(zip(self.result.objects, rows(self.result.objects, self.truths(judged_now=judged_now))))


def play(hero: SimulatedHero, executive: Executive, *, closing: Sequence[LocalLearner] = ()) -> Played:
    """Run ``executive`` on ``hero``'s floor to its end, shut it and ``closing`` down,
    read the ground truth, and close ``hero``."""
    start = hero.truth()
    try:
        result = executive.run()
    finally:
        executive.shutdown()
        for learner in closing:
            learner.close()
    played = Played(result, executive.log.events, start, hero.truth(), hero.disturbances(), hero.contacts)
    hero.close()
    return played


def play_floor(world: Callable[[Path], Path], seed: int, params: Params, *,
               watch: Callable[[SimulatedHero], Driver] | None = None, **simulator: Any) -> Played:
    """Play the floor ``world`` writes into a scratch folder, under ``EXECUTION_NOISE``
    and simulator seed ``seed``, with the library and profile this worker was given
    (:func:`~experiments.worker.install_worker`) and the executive's ``params``.
    ``watch`` wraps the simulator in a driver that watches it (the clutter study's
    contamination check); ``simulator`` goes to :class:`SimulatedHero` (disturbances,
    movers)."""
    library, profile = installed_library(), installed_profile()
    with tempfile.TemporaryDirectory(prefix="csl-floor-") as tmp:
        folder = Path(tmp)
        hero = SimulatedHero("experiment", world=world(folder), seed=seed, profile=profile,
                             noise=noise_config(EXECUTION_NOISE), **simulator)
        learner = LocalLearner(folder / "library.sqlite", seed_library=list(library))
        executive = Executive(hero if watch is None else watch(hero), learner, profile=profile, params=params)
        return play(hero, executive, closing=(learner,))
