"""Study: without a ceiling camera — whole onboard episodes in the simulated homes,
measured against the simulator's truth, beside the ceiling-camera lab.

The paper's closing step: the robot maps a home it has never seen from its
own range scans, finds the objects in it, and handles each by CSL as in the lab. Each
job is one whole episode (``Executive(..., perception="onboard")``) in a home under one
noise preset and seed, measured by :mod:`experiments.onboard_truth`: objects present,
found, handled right of those found, false records, the exploration's robot time, the
robot time per object present (exploration included), the map's surface IoU, and the
localisation error over every scan beside the raw odometry's. Beside each preset and
seed the ceiling-camera lab (world ``lab``, ``perception="ceiling"``, the same library,
params, preset and seed) is the baseline the robot time is a multiple of: the question
is what leaving the ceiling camera behind costs. Every episode starts from the shipped
example library (``executive.defaults.EXAMPLE_LIBRARY``, as ``csl demo`` does), not
from the run's training, so the homes' objects meet the library they would out of the
box.

Then the goals under ``paper``, per home, each met or not (never left out): at
least 95 % of the objects present found, at least 95 % of those handled right, robot
time per object present at most 1.5x the lab's, surface IoU at least 0.9.

Run: ``csl experiment onboard [--quick] [--seeds N] [--jobs J] [--out DIR]`` (the page:
:mod:`experiments.onboard_page`); ``bench/bench_onboard.py`` plays the same jobs for
their wall time, and can stop each when the home is mapped.
"""

from __future__ import annotations

import dataclasses
import math
import tempfile
import time
from collections.abc import Mapping, Sequence
from dataclasses import dataclass, field
from pathlib import Path

from executive.defaults import EXAMPLE_LIBRARY
from executive.executive import CEILING, ONBOARD, Executive
from experiments.conditions import noise_config
from experiments.config import ExperimentConfig
from experiments.floor import play
from experiments.onboard_truth import (Found, Localisation, MapAccuracy, TruthAtScans,
                                       found_and_right, localisation, map_accuracy)
from experiments.study import RESULTS_DIR, Study
from experiments.table import ResultRow, StudyResult, mean, num, percent
from experiments.worker import installed_profile
from hero_driver.sim.catalogue import CatalogueEntry
from hero_driver.sim.truth_map import truth_map
from hero_driver.sim.worldfile import WorldSpec
from learner.library.format import read_library_json
from learner.service.local import LocalLearner
from mapping import OccupancyGrid
from reporting.built_map import plot_built_map
from reporting.plots import legs
from reporting.report import FOUND_WITHIN_IN

TITLE = "Without a ceiling camera: onboard episodes in the simulated homes against the ceiling-camera lab"
HOMES = ("apartment", "apartment-2")
PRESETS = ("clean", "paper", "harsh")
QUICK_HOMES, QUICK_PRESETS = HOMES[:1], ("paper",)
LAB = "lab"
GOAL_PRESET = "paper"
GOAL_FOUND, GOAL_RIGHT, GOAL_TIME_RATIO, GOAL_SURFACE_IOU = 0.95, 0.95, 1.5, 0.9
TRUTH_CELL_IN = 2.0  # the truth map's resolution: the built grid is resampled to it
MAP_PNG = "onboard-map.png"  # the one episode drawn, beside the page under results/


@dataclass(frozen=True)
class OnboardJob:
    """One episode: a home onboard (or the lab with the ceiling camera) under noise
    ``preset`` on simulator seed ``seed``. ``map_png``: draw the map it built there.
    ``explore_only`` and ``leg_in`` are the bench's probes (stop when the home is
    mapped; another ``OnboardSettings.leg_in``); the study uses neither."""

    world: str
    preset: str
    seed: int
    map_png: Path | None = None
    explore_only: bool = False
    leg_in: float | None = None
    study: str = field(default="onboard", compare=False)

    def run(self) -> Episode:
        return run_job(self)


@dataclass(frozen=True)
class Episode:
    """One episode against the truth (robot seconds, inches). ``found`` is None when no
    object was handled (an explore-only probe); ``map`` and ``located`` are None in the
    lab (no map is built there)."""

    world: str
    preset: str
    seed: int
    present: int
    found: Found | None
    explore_s: float
    objects_s: float
    map: MapAccuracy | None
    located: Localisation | None
    wall_s: float
    drawn: str | None = None  # the map PNG's file name, when this episode drew one

    @property
    def minutes_per_object(self) -> float:
        """All the robot's time, exploring included, spread over the objects present:
        what a home costs per object, whether the robot found it or not."""
        return (self.explore_s + self.objects_s) / 60.0 / max(self.present, 1)


class _Mapped(Exception):
    """Raised from the tick hook to end an explore-only episode."""


def run_job(job: OnboardJob) -> Episode:
    """Play one episode here (in a worker process, given the run's robot profile) and
    measure it against the simulator's truth."""
    onboard = job.world != LAB
    profile = installed_profile()
    hero = TruthAtScans("experiment", world=job.world, seed=job.seed, profile=profile,
                        noise=noise_config(job.preset))
    sim = hero.world
    spec, catalogue, start = sim.spec, sim.catalogue, sim.pose
    with tempfile.TemporaryDirectory(prefix="csl-onboard-") as tmp:
        learner = LocalLearner(Path(tmp) / "library.sqlite", seed_library=read_library_json(EXAMPLE_LIBRARY))
        executive = Executive(hero, learner, profile=profile, perception=ONBOARD if onboard else CEILING)
        perception = executive.perception
        if job.leg_in is not None and perception is not None:
            perception.settings = dataclasses.replace(perception.settings, leg_in=job.leg_in)
        began = time.perf_counter()
        if job.explore_only:
            present, found, judged, objects_s = len(hero.truth()), None, [], 0.0
            events = explore_until_mapped(executive, learner)
            truths = []
            hero.close()
        else:
            played = play(hero, executive, closing=(learner,))
            truths, judged, events = played.truths(), played.rows(), played.events
            present, found = len(played.start), found_and_right(judged, truths)
            objects_s = sum(row.robot_s for _, row in judged)
        wall_s = time.perf_counter() - began
    mapped = [e for e in events if e["event"] == "mapped"]
    explore_s = float(mapped[0]["seconds"]) if mapped else 0.0
    accuracy = located = drawn = None
    if onboard and perception is not None and perception.grid is not None:
        grid = perception.grid
        accuracy = built_map_accuracy(grid, spec, catalogue, (start.x_in, start.y_in))
        located = localisation(perception.poses, hero.true_at)
        if job.map_png is not None:
            plot_built_map(job.map_png, grid, truth_map(spec, catalogue, grid.inches_per_cell),
                           route=[(c.x_in, c.y_in) for _, _, c in perception.poses], moves=legs(events, None),
                           records=[record for record, _ in judged], labels=[row.object for _, row in judged],
                           present=truths,
                           title=f"{job.world} under {job.preset}, seed {job.seed}: the map the robot built")
            drawn = job.map_png.name
    return Episode(job.world, job.preset, job.seed, present, found, explore_s, objects_s, accuracy, located,
                   wall_s, drawn)


def built_map_accuracy(grid: OccupancyGrid, spec: WorldSpec, catalogue: Mapping[str, CatalogueEntry],
                       start: tuple[float, float]) -> MapAccuracy:
    """The built ``grid`` against the home's true map with its objects, at
    :data:`TRUTH_CELL_IN` (``experiments.onboard_truth.map_accuracy``)."""
    return map_accuracy(grid, truth_map(spec, catalogue, TRUTH_CELL_IN, objects=True),
                        truth_map(spec, catalogue, TRUTH_CELL_IN, layer="footprint", objects=True), start)


def explore_until_mapped(executive: Executive, learner: LocalLearner) -> list[dict]:
    """Run ``executive`` until the exploration ends (its ``mapped`` event), then shut
    it down and close ``learner``; the events so far (``bench/bench_exploration.py``
    runs its episodes this way too)."""
    read = 0  # the events the hook has looked at: a tick may log several after ``mapped``

    def stop_when_mapped(tick: int, root: object) -> None:
        nonlocal read
        events = executive.log.events
        fresh, read = events[read:], len(events)
        if any(e["event"] == "mapped" for e in fresh):
            raise _Mapped
    executive.on_tick = stop_when_mapped
    try:
        executive.run()
    except _Mapped:
        pass
    finally:
        executive.shutdown()
        learner.close()
    return list(executive.log.events)


def plan(homes: Sequence[str], presets: Sequence[str], seeds: Sequence[int],
         map_png: Path | None = None) -> list[OnboardJob]:
    """Every home under every preset on every seed, then the lab under every preset on
    every seed; the first home under :data:`GOAL_PRESET` (or the first preset) on the
    first seed draws its map to ``map_png``."""
    drawn = (homes[0], GOAL_PRESET if GOAL_PRESET in presets else presets[0], seeds[0])
    return ([OnboardJob(h, p, s, map_png if (h, p, s) == drawn else None) for h in homes for p in presets
             for s in seeds] + [OnboardJob(LAB, p, s) for p in presets for s in seeds])


@dataclass(frozen=True)
class Pooled:
    """One home under one preset over its seeds, with the lab's episodes on the same
    preset and seeds: what one row of the table says."""

    home: str
    preset: str
    episodes: tuple[Episode, ...]
    lab: tuple[Episode, ...]

    @property
    def seeds(self) -> tuple[int, ...]:
        return tuple(e.seed for e in self.episodes)

    @property
    def found_counts(self) -> list[Found]:
        """The episodes' counts of objects found (none from an explore-only probe)."""
        return [e.found for e in self.episodes if e.found is not None]

    @property
    def found_of_present(self) -> tuple[int, int]:
        """Objects found and present, summed over the seeds (of the episodes that handled objects)."""
        return (sum(f.found for f in self.found_counts),
                sum(e.present for e in self.episodes if e.found is not None))

    @property
    def right_of_found(self) -> tuple[int, int]:
        """Objects handled right and found, summed over the seeds."""
        return sum(f.right for f in self.found_counts), sum(f.found for f in self.found_counts)

    @property
    def found_share(self) -> float:
        return share(*self.found_of_present)

    @property
    def right_share(self) -> float:
        return share(*self.right_of_found)

    @property
    def minutes(self) -> float:
        return mean(e.minutes_per_object for e in self.episodes)

    @property
    def lab_minutes(self) -> float:
        return mean(e.minutes_per_object for e in self.lab)

    @property
    def time_ratio(self) -> float:
        """The mean robot minutes per object present against the lab's mean."""
        lab = self.lab_minutes
        return self.minutes / lab if lab > 0 else math.nan

    @property
    def surface_iou(self) -> float:
        return mean(e.map.surface_iou for e in self.episodes if e.map is not None)


def share(part: int, whole: int) -> float:
    """``part`` of ``whole``; NaN (shown ``-``) of nothing."""
    return part / whole if whole else math.nan


def share_cell(part: int, whole: int) -> str:
    """``part`` of ``whole`` as a cell: the share and the counts it is of (``95% (19/20)``),
    so a share just under a goal does not read as one on it."""
    return f"{percent(share(part, whole))} ({part}/{whole})" if whole else "-"


def pooled(results: Mapping[OnboardJob, Episode], homes: Sequence[str], presets: Sequence[str]) -> list[Pooled]:
    """Every home under every preset, in that order, over the seeds it ran on."""
    by_world: dict[tuple[str, str], list[Episode]] = {}
    for job, episode in results.items():
        by_world.setdefault((job.world, job.preset), []).append(episode)
    return [Pooled(h, p, tuple(by_world.get((h, p), ())), tuple(by_world.get((LAB, p), ())))
            for h in homes for p in presets]


HEADERS = ("home", "preset", "seeds", "episodes", "present", "found", "right of found", "false records",
           "exploration min", "robot min / object present", "x lab (lab min / object)", "surface IoU",
           "localisation median in", "localisation max in", "odometry max in")


def table_row(row: Pooled) -> tuple[str, ...]:
    """One row of the table: means over the seeds, shares pooled, the largest errors
    the largest of any episode; a row of one seed says it is a smoke value."""
    episodes = row.episodes
    found = row.found_counts
    located = [e.located for e in episodes if e.located is not None]
    seeds = ", ".join(map(str, row.seeds)) + (" (1 seed: a smoke value, not a result)" if len(episodes) == 1 else "")
    return (row.home, row.preset, seeds, str(len(episodes)), _g(mean(e.present for e in episodes)),
            share_cell(*row.found_of_present), share_cell(*row.right_of_found), _g(mean(f.false for f in found)),
            num(mean(e.explore_s / 60.0 for e in episodes)), num(row.minutes, 2),
            f"{num(row.time_ratio, 2)} ({num(row.lab_minutes, 2)})", num(row.surface_iou, 2),
            num(mean(loc.median_in for loc in located)), num(max((loc.corrected.max_in for loc in located),
                                                                 default=math.nan)),
            num(max((loc.odometry.max_in for loc in located), default=math.nan)))


def _g(value: float) -> str:
    """A mean of counts: as it is (14, 0.5), ``-`` for none."""
    return f"{value:.3g}" if math.isfinite(value) else "-"


@dataclass(frozen=True)
class Goal:
    """One of the goals for one home under :data:`GOAL_PRESET`."""

    home: str
    what: str
    shown: str  # the measured value as the table shows it
    target: str
    met: bool
    seeds: int

    @property
    def text(self) -> str:
        """What was measured against what was asked, without the verdict."""
        smoke = ", 1 seed: a smoke value" if self.seeds == 1 else ""
        return f"{self.home} under {GOAL_PRESET}: {self.what} {self.shown} ({self.target}{smoke})"

    @property
    def line(self) -> str:
        """The goal as the command prints it, one line, met or missed."""
        return f"goal {'met' if self.met else 'MISSED'}: {self.text}"


def goals(rows: Sequence[Pooled], *, objects: bool = True) -> list[Goal]:
    """Issue 35's goals for every home under :data:`GOAL_PRESET`, from the rows the table
    shows: the map's, and with ``objects`` the three on the objects (a probe that stops
    when the home is mapped handles none); a value not measured (NaN) does not meet its
    goal."""
    out = []
    for row in rows:
        if row.preset != GOAL_PRESET:
            continue
        n = len(row.episodes)
        if objects:
            out += [Goal(row.home, "objects found of present", share_cell(*row.found_of_present),
                         f"at least {GOAL_FOUND:.0%}", row.found_share >= GOAL_FOUND, n),
                    Goal(row.home, "handled right of found", share_cell(*row.right_of_found),
                         f"at least {GOAL_RIGHT:.0%}", row.right_share >= GOAL_RIGHT, n),
                    Goal(row.home, "robot time per object present", f"{num(row.time_ratio, 2)}x the lab's",
                         f"at most {GOAL_TIME_RATIO:g}x", row.time_ratio <= GOAL_TIME_RATIO, n)]
        out.append(Goal(row.home, "surface IoU", num(row.surface_iou, 2), f"at least {GOAL_SURFACE_IOU:g}",
                        row.surface_iou >= GOAL_SURFACE_IOU, n))
    return out


NOTES = (
    "Each row: one home under one noise preset, the means over its seeds (each seed its own noise draws and "
    "odometry drift; the homes' objects stand where their world files put them). Found and right are pooled "
    "over the seeds: objects found of all present, handled right of all found; a record is an object found "
    f"when it was first seen within {FOUND_WITHIN_IN:g} in of the object it is matched to, false when it matches "
    "none or is a second record of one. Robot minutes per object present include the exploration; 'x lab' "
    "divides them by the ceiling-camera lab's (world `lab`, the same library, preset and seeds), whose own figure "
    "is in brackets. Surface IoU: the map's occupied cells against the true ones a robot can see, each matched "
    f"within one {TRUTH_CELL_IN:g} in cell. Localisation: each scan's corrected pose against the simulator's true "
    "pose at that scan, the mean of the episodes' medians and the largest error of any; odometry: the pose the "
    "scan was stamped with, its largest error.",
)


def summarise(results: Mapping[OnboardJob, Episode], homes: Sequence[str], presets: Sequence[str]) -> StudyResult:
    """The goals under :data:`GOAL_PRESET` as the result's rows (the paper has no figure:
    its robot needed the ceiling camera), the table (one row per home and preset) and the
    map drawn."""
    rows = pooled(results, homes, presets)
    goal_rows = tuple(ResultRow(f"{g.home} under {GOAL_PRESET}: {g.what} (goal: {g.target})", "-",
                                f"{g.shown}: {'met' if g.met else 'NOT met'}"
                                + (" (1 seed: a smoke value)" if g.seeds == 1 else "")) for g in goals(rows))
    drawn = tuple(e.drawn for e in results.values() if e.drawn is not None)
    return StudyResult(TITLE, goal_rows, NOTES, drawn, details=((HEADERS, tuple(table_row(r) for r in rows)),))


def sweep(config: ExperimentConfig) -> tuple[tuple[str, ...], tuple[str, ...]]:
    """The homes and presets of a run of this size."""
    return (QUICK_HOMES, QUICK_PRESETS) if config.quick else (HOMES, PRESETS)


STUDY = Study("onboard",
              lambda config: plan(*sweep(config), config.seed_list, config.out / RESULTS_DIR / MAP_PNG),
              lambda context, results: summarise(results, *sweep(context.config)),
              floors=(1, 2))
"""Every home under every preset with the lab beside it (``csl experiment onboard``)."""
