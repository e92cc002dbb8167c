"""The suite's scripted episodes on the installed testing API (:mod:`csl_testing`):
the noise settings and the paper's tumbler story the snapshot tests share, and the
old ``run(world, seed)`` shape that tests not yet written on ``csl_testing`` still use."""

from __future__ import annotations

import dataclasses
from dataclasses import dataclass
from types import SimpleNamespace

from behaviours.services import Params
from csl_testing import STEADY_NOISE, Scenario, ScenarioResult
from hero_driver.sim.noise import NoiseConfig
from hero_driver.sim.probe import probe
from hero_driver.sim.worldfile import Placement
from learner.description import ObjectDescription, Observation
from learner.position import Position

NOISE = STEADY_NOISE
NOISY_SONAR = dataclasses.replace(STEADY_NOISE, outlier_p=0.3)
DEAF_SONAR = dataclasses.replace(STEADY_NOISE, dropout_p=1.0)


def one(entry: str) -> tuple[Placement, ...]:
    """The objects of a one-object episode: ``entry`` in the middle of the bare room."""
    return (Placement(entry, 110.0, 80.0, 20.0),)


@dataclass(frozen=True)
class Played:
    """A result in the old helper's shape: ``.result`` and ``.executive.log.events``."""

    result: ScenarioResult

    @property
    def executive(self) -> SimpleNamespace:
        return SimpleNamespace(log=SimpleNamespace(events=list(self.result.events)))


def run(objects: tuple[Placement, ...], seed: int, *, params: Params = Params(), noise: NoiseConfig = NOISE,
        max_ticks: int | None = None) -> Played:
    """One episode of ``objects`` in the bare room (for tests written before csl_testing)."""
    return Played(Scenario(objects=objects, seed=seed, params=params, noise=noise, max_ticks=max_ticks).run())


def recorded(entry: str, grasp: str) -> ObjectDescription:
    """A description as a team would record it by hand: both scans at 6 in."""
    values = {**probe(entry, "D-Scan-0.3", 6.0, 0.0).values, **probe(entry, "H-Scan-0.3", 6.0, 0.0).values}
    return ObjectDescription(entry, grasp, Position(6.0, None), tuple(sorted(
        Observation(f, Position(6.0, None), float(v)) for f, v in values.items() if v is not None)))


def tumbler_story_library() -> list[ObjectDescription]:
    """The paper's situation: the robot knows the upright 20 oz tumbler (Top-Pinch, open
    top), a lying soda can (Top-Vert-Grip) and a closed box it must leave; it has never
    seen a tumbler upside down, which is as tall as the upright one."""
    return [recorded("tumbler-20oz/upright", "Top-Pinch"), recorded("soda-can-12oz/lying", "Top-Vert-Grip"),
            recorded("closed-box-11x9x12/upright", "No-Grab")]
