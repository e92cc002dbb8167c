"""Scripted episodes: one object (or two) in a bare room, a seeded simulator with sonar
noise but exact odometry, the shipped example library. Seeds were chosen so that each
control strategy of docs/method.md §5 shows up; the tests assert that it did."""

from __future__ import annotations

import tempfile
from collections.abc import Sequence
from dataclasses import dataclass
from pathlib import Path

from behaviours.services import Params
from executive.defaults import EXAMPLE_LIBRARY
from executive.executive import EpisodeResult, Executive
from hero_driver.sim.noise import NoiseConfig
from hero_driver.sim.probe import probe
from hero_driver.sim.worldfile import Placement, WorldSpec
from hero_driver.sim_driver import SimulatedHero
from learner.criteria import Criterion
from learner.description import ObjectDescription, Observation
from learner.library import read_library_json
from learner.position import Position
from learner.service.local import LocalLearner

NOISE = NoiseConfig(odometry_frac=0.0, odometry_heading_deg=0.0, pixel_sigma=0.0)
NOISY_SONAR = NoiseConfig(outlier_p=0.3, odometry_frac=0.0, odometry_heading_deg=0.0, pixel_sigma=0.0)
DEAF_SONAR = NoiseConfig(dropout_p=1.0, odometry_frac=0.0, odometry_heading_deg=0.0, pixel_sigma=0.0)


def world(*objects: tuple[str, float, float, float]) -> WorldSpec:
    return WorldSpec("scenario", "<scenario>", 200.0, 140.0, (), (30.0, 30.0, 0.0),
                     tuple(Placement(e, x, y, yaw) for e, x, y, yaw in objects), None)


def one(entry: str) -> WorldSpec:
    return world((entry, 110.0, 80.0, 20.0))


@dataclass
class Scenario:
    result: EpisodeResult
    executive: Executive
    learner: LocalLearner


def run(spec: WorldSpec, seed: int, *, params: Params = Params(), library: Sequence[ObjectDescription] | None = None,
        store: Path | None = None, noise: NoiseConfig = NOISE, max_ticks: int | None = None,
        criterion: Criterion | None = None) -> Scenario:
    """One episode; ``store`` keeps the library between episodes (learning); ``criterion``
    None is the executive's default."""
    path = store or Path(tempfile.mkdtemp()) / "library.sqlite"
    learner = LocalLearner(path, seed_library=list(library) if library is not None else read_library_json(EXAMPLE_LIBRARY))
    executive = Executive(SimulatedHero("r1", world=spec, seed=seed, noise=noise), learner, params=params,
                          criterion=criterion)
    result = executive.run(trace=True, max_ticks=max_ticks)
    executive.shutdown()
    return Scenario(result, executive, learner)


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


def transcript(scenario: Scenario) -> str:
    """The tick-by-tick trace and the episode's events, without anything that varies
    between runs (wall time; move durations, which depend on the sampled path)."""
    lines = ["# ticks: every behaviour ticked this tick, with its status (S/F/R)", *scenario.result.trace,
             "# events"]
    for e in scenario.executive.log.events:
        shown = {k: v for k, v in e.items() if k not in ("tick", "event", "behaviour")
                 and not (e["event"] == "move" and k in ("seconds", "path"))}
        lines.append(f"{e['tick']:4d} {e['event']}: " + ", ".join(f"{k}={v}" for k, v in shown.items()))
    return "\n".join(lines) + "\n"
