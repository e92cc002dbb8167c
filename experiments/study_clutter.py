"""Study: clutter — success, cost and contaminated readings against how close the
objects stand, with the beam check on and off.

Beyond the paper: CSL "assumes that objects are apart". Each floor of unseen test
objects is cluttered by the simulator's generator (:mod:`hero_driver.sim.clutter`):
every object paired with a neighbour ``gap`` inches away, edge to edge, as far as the
pairs fit; ``apart`` is the uncluttered floor. The same floors and seeds run with the
executive's ``BeamClear?`` check (``behaviours.clutter``) on and off.

Measured per gap and setting: the success rate (the right grasp, or No-Grab left),
robot minutes per object, and the sonar readings used that a neighbour contaminated:
ground truth from the simulator (:func:`hero_driver.sim.clutter.contaminated`: the
reading, noise off, differs from the object's alone from the same pose), counted for
every reading the executive took (each one is given to the learner); and the test
positions ``BeamClear?`` refused (``beam_blocked`` events).

Run: ``csl experiment clutter [--quick] [--seeds N] [--jobs J]``.
"""

from __future__ import annotations

import json
import math
from collections.abc import Mapping, Sequence
from concurrent.futures import Future
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

from py_trees.blackboard import Blackboard

from behaviours.services import Params, namespace
from experiments.floor import play_floor
from experiments.config import ExperimentConfig
from experiments.study import Study
from experiments.table import ResultRow, StudyResult, mean, num, percent
from experiments.worlds import random_floor
from hero_driver.interface import SenseResult
from hero_driver.sim.clutter import Clutter, cluttered, contaminated
from hero_driver.sim.catalogue import profile_and_catalogue
from hero_driver.sim_driver import SimulatedHero

TITLE = "Clutter: success, cost and contaminated readings vs the neighbour's gap, beam check on and off"
APART = math.inf  # the uncluttered floor
QUICK_GAPS = (APART, 2.0)
FULL_GAPS = (APART, 1.0, 2.0, 4.0, 8.0)

def gap_label(gap: float) -> str:
    return "apart" if math.isinf(gap) else f"{gap:g} in"


@dataclass(frozen=True)
class ClutterJob:
    """One floor (``seed``) cluttered at ``gap`` (APART: not at all), beam check on or off."""

    gap: float
    check: bool
    seed: int
    study: str = field(default="clutter", compare=False)

    def run(self) -> list[ObjectRow]:
        return run_job(self)


@dataclass(frozen=True)
class ObjectRow:
    """One object of one episode."""

    gap: float
    check: bool
    seed: int
    object: str
    outcome: str
    correct: bool
    robot_s: float
    readings: int
    contaminated: int  # readings used that a neighbour changed (ground truth)
    beam_blocked: int  # test positions refused because a neighbour was in the beam (``beam_blocked``)


class WatchedHero:
    """The simulated HERO, every sensing checked against ground truth first: whether a
    neighbour contaminates it, for the object the executive is working on (the true
    object nearest its record's current region). Everything else is the HERO's own."""

    def __init__(self, hero: SimulatedHero) -> None:
        self._hero = hero
        self.readings: dict[int, list[bool]] = {}  # sim object index -> contaminated, per reading

    def __getattr__(self, name: str) -> Any:
        return getattr(self._hero, name)

    def sense(self, procedure: str) -> Future[SenseResult]:
        record = Blackboard.get(f"{namespace(self._hero.robot)}/object")
        x, y = record.region.centroid
        target = min(self._hero.truth(), key=lambda t: math.hypot(t.x_in - x, t.y_in - y)).index
        self.readings.setdefault(target, []).append(contaminated(self._hero.world, procedure, target))
        return self._hero.sense(procedure)


def floor(folder: Path, gap: float, seed: int) -> Path:
    """The test objects' floor for ``seed``, cluttered at ``gap`` unless APART."""
    world = random_floor("test", seed)
    if not math.isinf(gap):
        world = cluttered(world, profile_and_catalogue()[1], Clutter(1.0, gap), seed)
    path = folder / f"clutter-{seed}.json"
    path.write_text(json.dumps(world), encoding="utf-8")
    return path


def run_job(job: ClutterJob) -> list[ObjectRow]:
    """Run one floor here (in a worker process) and report it object by object."""
    watched: WatchedHero | None = None

    def watch(hero: SimulatedHero) -> WatchedHero:
        nonlocal watched
        watched = WatchedHero(hero)
        return watched

    played = play_floor(lambda folder: floor(folder, job.gap, job.seed), job.seed, Params(beam_check=job.check),
                        watch=watch)  # type: ignore[arg-type]
    assert watched is not None
    blocked = [e["object"] for e in played.events if e["event"] == "beam_blocked"]
    start = played.start
    out = []
    for record, row in played.rows(judged_now=False):
        seen = (record.first_region or record.region).centroid
        index = min(start, key=lambda t: math.hypot(t.x_in - seen[0], t.y_in - seen[1])).index
        taken = watched.readings.get(index, [])
        out.append(ObjectRow(job.gap, job.check, job.seed, row.object, row.outcome, bool(row.correct),
                             round(row.robot_s, 1), len(taken), sum(taken), blocked.count(record.index)))
    return out


def plan(gaps: Sequence[float], seeds: Sequence[int]) -> list[ClutterJob]:
    return [ClutterJob(g, c, s) for g in gaps for c in (True, False) for s in seeds]


@dataclass(frozen=True)
class Cell:
    """One gap and setting, over its seeds."""

    success: float
    minutes: float  # robot minutes per object
    readings: int
    contaminated: int
    blocked: int  # beam_blocked refusals
    objects: int


def cell(found: Sequence[ObjectRow]) -> Cell:
    return Cell(mean(float(r.correct) for r in found), mean(r.robot_s for r in found) / 60.0,
                sum(r.readings for r in found), sum(r.contaminated for r in found),
                sum(r.beam_blocked for r in found), len(found))


def summarise(results: Mapping[ClutterJob, Sequence[ObjectRow]], gaps: Sequence[float]) -> StudyResult:
    cells = {(g, c): cell([row for job, found in results.items() if job.gap == g and job.check == c
                           for row in found]) for g in gaps for c in (True, False)}

    def text(c: Cell) -> str:
        return (f"{percent(c.success)}, {num(c.minutes)} min, {c.contaminated}/{c.readings} contaminated, "
                f"{c.blocked} beam blocked")

    table = tuple((gap_label(g), text(cells[(g, True)]), text(cells[(g, False)])) for g in gaps)
    closest = min(gaps)
    on = sum(c.contaminated for (_, check), c in cells.items() if check)
    off = sum(c.contaminated for (_, check), c in cells.items() if not check)
    result_rows = (
        ResultRow("contaminated readings used, beam check on / off", "objects apart",
                  f"{on} / {off}"),
        ResultRow(f"success at {gap_label(closest)}: check on / off", "objects apart",
                  f"{percent(cells[(closest, True)].success)} / {percent(cells[(closest, False)].success)}"),
        ResultRow(f"robot min per object at {gap_label(closest)}: check on / off", "-",
                  f"{num(cells[(closest, True)].minutes)} / {num(cells[(closest, False)].minutes)}"),
    )
    notes = ("Each cell: success (right grasp, or No-Grab left), robot minutes per object, sonar readings a "
             "neighbour contaminated (ground truth, noise off) / readings taken, test positions refused for a "
             "neighbour in the beam (`beam_blocked`).",)
    return StudyResult(TITLE, result_rows, notes, details=((("gap", "beam check on", "beam check off"), table),))



def gaps(config: ExperimentConfig) -> tuple[float, ...]:
    return QUICK_GAPS if config.quick else FULL_GAPS


STUDY = Study("clutter", lambda config: plan(gaps(config), config.seed_list),
              lambda context, results: summarise(results, gaps(context.config)), floors=(1, 4))
"""Every gap with the beam check on and off (``csl experiment clutter``)."""
