"""Study: low battery — success and cost against the battery's start level and against
its drain rate, with the low-battery guard on and off and the dock-detour pricing on and
off.

Beyond the paper: CSL "can not handle ... low battery". Each floor of unseen test
objects gets a charging dock by the west wall and a start level L; the robot works
until the floor is done. Two sweeps: the start level at the documented drain rates,
and the disturbance rate, a multiplier on those rates (the world file's
``battery_drain``: docs/simulator.md, Battery), from a fixed start level. Three
settings on the same floors and seeds:

- ``guard off``: no threshold; the robot runs flat, the driver refuses every later
  verb with ``battery_empty``, and the object in hand and all the rest fail;
- ``guard``: below the threshold the robot docks, charges and resumes (behaviours.battery);
- ``guard + pricing``: the same, with the dock detour priced into the learner's moves
  (executive.battery_cost).

Measured per level and setting: the success rate, robot minutes per object, dock trips,
objects resumed with their measurements kept after a charge, flat-battery failures,
and descriptions saved from attempts the battery cut short (a ``battery_empty`` refusal
while the object was in hand), which must be 0 in every setting: a cut-short attempt
is a failure, and the paper learns only from a grasp that held.

Run: ``csl experiment battery [--quick] [--seeds N] [--jobs J]``.
"""

from __future__ import annotations

import json
from collections.abc import Mapping, Sequence
from dataclasses import dataclass, field
from pathlib import Path

from behaviours.services import Params
from experiments.floor import play_floor
from experiments.config import ExperimentConfig
from experiments.study import Study
from experiments.table import ResultRow, StudyResult, mean, num, percent
from experiments.worlds import random_floor

TITLE = "Low battery: success and cost vs the start level and the drain rate, guard and detour pricing on and off"
THRESHOLD = Params().battery_low
DOCK = {"x_in": 15.0, "y_in": 90.0, "heading_deg": 180.0}  # by the west wall, clear of the first column
QUICK_LEVELS = (0.03, 0.21)
FULL_LEVELS = (0.02, 0.1, 0.205, 0.21, 0.22, 0.24)
DRAIN_LEVEL = 0.5  # the drain sweep's start level: 0.3 of a charge above the threshold
QUICK_DRAINS = (1.0, 8.0)
FULL_DRAINS = (1.0, 2.0, 4.0, 8.0, 16.0)
SETTINGS = ("guard off", "guard", "guard + pricing")

def params_for(setting: str) -> Params:
    """The executive's settings for one of :data:`SETTINGS`."""
    if setting not in SETTINGS:
        raise ValueError(f"unknown battery setting {setting!r}; expected one of {', '.join(SETTINGS)}")
    return Params(battery_low=0.0 if setting == "guard off" else THRESHOLD,
                  price_detours=setting == "guard + pricing")


def write_docked_floor(folder: Path, seed: int, level: float, drain: float = 1.0) -> Path:
    """The experiment floor of unseen objects for ``seed`` with a dock, a start level
    and a multiplier on the drain rates."""
    world = random_floor("test", seed)
    world.update(dock=DOCK, battery=level, battery_drain=drain, name=f"test-{seed}-battery-{level:g}-x{drain:g}")
    path = folder / f"test-{seed}-battery.json"
    path.write_text(json.dumps(world), encoding="utf-8")
    return path


@dataclass(frozen=True)
class BatteryJob:
    """One floor (``seed``) from start level ``level``, its drain rates times ``drain``,
    under one setting."""

    level: float
    setting: str
    seed: int
    drain: float = 1.0
    study: str = field(default="battery", compare=False)

    def run(self) -> list[ObjectRow]:
        return run_job(self)


@dataclass(frozen=True)
class ObjectRow:
    """One object of one episode."""

    level: float
    setting: str
    seed: int
    object: str
    outcome: str
    correct: bool
    robot_s: float
    charges: int  # dock visits while this object was in hand
    resumed: bool  # charged mid-object and went on with what it had measured
    flat: bool  # failed with the battery flat
    drain: float = 1.0
    saved_cut_short: bool = False  # a description saved though the battery cut the attempt short


def run_job(job: BatteryJob) -> list[ObjectRow]:
    """Run one floor here (in a worker process) and report it object by object."""
    played = play_floor(lambda folder: write_docked_floor(folder, job.seed, job.level, job.drain), job.seed,
                        params_for(job.setting))
    events = played.events
    charges = [e.get("object") for e in events if e["event"] == "charge"]
    flat = {e.get("object") for e in events if e["event"] == "driver_error" and e.get("code") == "battery_empty"}
    cut_short = learned_after_flat(events)
    out = []
    for record, row in played.rows(judged_now=False):
        n = charges.count(record.index)
        out.append(ObjectRow(job.level, job.setting, job.seed, row.object, row.outcome, bool(row.correct),
                             round(row.robot_s, 1), n, n > 0 and row.outcome != "failed",
                             record.index in flat and row.outcome == "failed", job.drain,
                             record.index in cut_short))
    return out


def learned_after_flat(events: Sequence[Mapping[str, object]]) -> set[object]:
    """The objects whose description was saved after a ``battery_empty`` refusal while
    they were in hand: attempts the battery cut short. A refusal after the object was
    learned (the last verb finished on the reserve, then the drive to the dock was
    refused) does not count: the grasp that held came first."""
    refused: set[object] = set()
    saved: set[object] = set()
    for e in events:
        if e["event"] == "driver_error" and e.get("code") == "battery_empty":
            refused.add(e.get("object"))
        elif e["event"] == "learn" and e.get("id") is not None and e.get("object") in refused:
            saved.add(e.get("object"))
    return saved


def plan(levels: Sequence[float], seeds: Sequence[int], drains: Sequence[float] = ()) -> list[BatteryJob]:
    """Every start level at the documented rates, then every drain multiplier from
    :data:`DRAIN_LEVEL`, each under every setting on every floor."""
    points = [(level, 1.0) for level in levels] + [(DRAIN_LEVEL, drain) for drain in drains]
    return [BatteryJob(level, s, seed, drain) for level, drain in points for s in SETTINGS for seed in seeds]


@dataclass(frozen=True)
class Cell:
    """One level and setting, over its seeds."""

    success: float
    minutes: float  # robot minutes per object, charging included
    charges: int
    resumed: int
    flat: int
    objects: int
    saved_cut_short: int = 0


def cell(found: Sequence[ObjectRow]) -> Cell:
    return Cell(mean(float(r.correct) for r in found), mean(r.robot_s for r in found) / 60.0,
                sum(r.charges for r in found), sum(r.resumed for r in found), sum(r.flat for r in found), len(found),
                sum(r.saved_cut_short for r in found))


def describe(c: Cell) -> str:
    """One table cell: success, robot minutes per object, dock trips, resumed, flat."""
    return f"{percent(c.success)}, {num(c.minutes)} min, {c.charges} dock, {c.resumed} resumed, {c.flat} flat"


def pooled(results: Mapping[BatteryJob, Sequence[ObjectRow]], level: float, drain: float, setting: str) -> Cell:
    """The cell of one sweep point and setting, over its floors."""
    return cell([row for job, found in results.items()
                 if (job.level, job.drain, job.setting) == (level, drain, setting) for row in found])


def summarise(results: Mapping[BatteryJob, Sequence[ObjectRow]], levels: Sequence[float],
              drains: Sequence[float] = ()) -> StudyResult:
    cells = {(level, s): pooled(results, level, 1.0, s) for level in levels for s in SETTINGS}
    drained = {(drain, s): pooled(results, DRAIN_LEVEL, drain, s) for drain in drains for s in SETTINGS}
    table = tuple((f"{level:g}", *(describe(cells[(level, s)]) for s in SETTINGS)) for level in levels)
    drain_table = tuple((f"x{drain:g}", *(describe(drained[(drain, s)]) for s in SETTINGS)) for drain in drains)
    every = [*cells.items(), *drained.items()]
    low = min(levels)
    flat_on = sum(c.flat for (_, s), c in every if s != "guard off")
    guard = [cells[(level, "guard")] for level in levels]
    priced = [cells[(level, "guard + pricing")] for level in levels]
    result_rows = (
        ResultRow("flat-battery failures with the guard on (must be 0)", "-", str(flat_on)),
        ResultRow(f"success from level {low:g}: guard off / guard / guard + pricing", "not handled",
                  " / ".join(percent(cells[(low, s)].success) for s in SETTINGS)),
        ResultRow("robot min per object over all levels: guard / guard + pricing", "-",
                  f"{num(mean(c.minutes for c in guard))} / {num(mean(c.minutes for c in priced))}"),
        ResultRow("dock trips over all levels: guard / guard + pricing", "-",
                  f"{sum(c.charges for c in guard)} / {sum(c.charges for c in priced)}"),
        ResultRow("descriptions saved from attempts the battery cut short: guard off / guard / guard + pricing "
                  "(must be 0)", "-",
                  " / ".join(str(sum(c.saved_cut_short for (_, s), c in every if s == setting))
                             for setting in SETTINGS)),
        *(ResultRow(f"success at drain x{drain:g} from {DRAIN_LEVEL:g}: guard off / guard / guard + pricing", "-",
                    " / ".join(percent(drained[(drain, s)].success) for s in SETTINGS)) for drain in drains[-1:]),
    )
    notes = (f"Each cell: success, robot minutes per object (charging included), dock trips, objects resumed "
             f"after a charge with their measurements kept, flat-battery failures. Threshold {THRESHOLD:g}; "
             f"the dock at ({DOCK['x_in']:g}, {DOCK['y_in']:g}). The second table: from level {DRAIN_LEVEL:g}, "
             f"every drain rate times the multiplier (world file `battery_drain`).",)
    details = ((("start level", *SETTINGS), table),)
    if drains:
        details += (((f"drain (from {DRAIN_LEVEL:g})", *SETTINGS), drain_table),)
    return StudyResult(TITLE, result_rows, notes, details=details)


def sweep(config: ExperimentConfig) -> tuple[tuple[float, ...], tuple[float, ...]]:
    """The start levels and drain multipliers of a run of this size."""
    return (QUICK_LEVELS, QUICK_DRAINS) if config.quick else (FULL_LEVELS, FULL_DRAINS)


STUDY = Study("battery", lambda config: plan(sweep(config)[0], config.seed_list, sweep(config)[1]),
              lambda context, results: summarise(results, *sweep(context.config)), floors=(1, 4))
"""Every level and every drain multiplier under every setting (``csl experiment battery``)."""
