"""Onboard episodes: the robot without a ceiling camera, measured against the simulator's truth.

Each episode is the whole executive (``Executive(..., perception="onboard")``) on the
in-process simulator: the exploration branch maps the home from the robot's own scans,
then every candidate found is handled by CSL as in the lab. Measured per episode:

- objects present; found: true objects with an object record whose first region's
  centroid lies within :data:`FOUND_WITHIN_IN` of the object's centre (the record is
  matched to the truth nearest it, ``reporting.report.match_truth``, as every report of
  the project does); handled right: found objects whose record the report judges
  correct (``reporting.report.rows``); false: records matching no object (nearer than
  the tolerance to none) or a second record of an object already found;
- robot time: exploration (the ``mapped`` event's seconds), the objects' (moving,
  sensing, grasping of every record), and minutes per object two ways: the objects'
  time per object found, and everything (exploration included) per object present;
- the map: the built occupancy grid, resampled to the truth's cells, against
  ``hero_driver.sim.truth_map`` at the start (objects included): IoU of occupied cells
  as they are and the surface IoU, the same code as ``bench/bench_mapping_sim.py``;
- localisation: each scan's corrected pose (``executive.perception.poses``) against the
  simulator's true pose when the scan was taken (keyed by the scan's clock): final,
  median and largest error over the episode (inches), and the raw odometry's largest.

Beside them the ceiling-camera lab (world ``lab``, ``perception="ceiling"``, the same
library, params, preset and seeds) gives the baseline's minutes per object, and the
table shows the onboard minutes per object as a multiple of it.

Issue 35's goals, checked for each home under ``paper`` (one line each; a missed one
exits non-zero): found >= 95 % of present, handled right >= 95 % of found, robot time
per object present (exploration included) <= 1.5x the lab's, surface IoU >= 0.9.

``--explore-only`` stops each onboard episode when the home is mapped (no objects
handled, no lab baseline, no object goals): map and localisation only, much faster.

    python bench/bench_onboard.py [--homes apartment,apartment-2] [--presets paper]
                                  [--seeds 2] [--jobs 1] [--explore-only] [--leg-in 60]
"""

from __future__ import annotations

import argparse
import dataclasses
import math
import statistics
import sys
import tempfile
import time
from collections.abc import Sequence
from concurrent.futures import Future, ProcessPoolExecutor
from dataclasses import dataclass
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT))
sys.path.insert(0, str(ROOT / "bench"))

from bench_mapping_sim import map_accuracy, report_goals  # noqa: E402

from behaviours.services import Params  # noqa: E402
from executive.defaults import EXAMPLE_LIBRARY  # noqa: E402
from executive.executive import Executive  # noqa: E402
from experiments.floor import Played, play  # noqa: E402
from hero_driver.interface import RangeScan  # noqa: E402
from hero_driver.sim.noise import NOISE_PRESETS  # noqa: E402
from hero_driver.sim.truth_map import TruthMap, truth_map  # noqa: E402
from hero_driver.sim_driver import SimulatedHero  # noqa: E402
from learner.library.format import read_library_json  # noqa: E402
from learner.service.local import LocalLearner  # noqa: E402
from mapping import OccupancyGrid  # noqa: E402
from reporting.report import match_truth  # noqa: E402

FOUND_WITHIN_IN = 12.0  # a record's first region centred this near an object's centre found it
TRUTH_CELL_IN = 2.0  # the truth map's resolution: the built grid is resampled to it
GOAL_FOUND, GOAL_RIGHT, GOAL_TIME_RATIO, GOAL_SURFACE_IOU = 0.95, 0.95, 1.5, 0.9
LAB = "lab"


@dataclass(frozen=True)
class Measured:
    """One episode against the truth (times in robot seconds, distances in inches)."""

    world: str
    preset: str
    seed: int
    present: int
    found: int
    right: int
    false: int
    explore_s: float
    objects_s: float
    iou: float
    surface_iou: float
    loc_final_in: float
    loc_median_in: float
    loc_max_in: float
    odometry_max_in: float
    wall_s: float

    @property
    def minutes_per_found(self) -> float:
        """The objects' robot time per object found (the lab's: per object handled)."""
        return self.objects_s / 60.0 / max(self.found, 1)

    @property
    def minutes_per_present(self) -> float:
        """All the robot's time, exploring included, spread over the objects present."""
        return (self.explore_s + self.objects_s) / 60.0 / max(self.present, 1)


class TruthAtScans(SimulatedHero):
    """The simulator, noting its true pose at every scan (by the scan's clock): the
    ground truth the corrected poses are measured against."""

    def __init__(self, *args, **kwargs) -> None:  # noqa: ANN002, ANN003
        super().__init__(*args, **kwargs)
        self.true_at: dict[float, tuple[float, float]] = {}

    def scan(self) -> Future[RangeScan]:
        future = super().scan()
        if future.exception() is None:
            pose = self._live().pose
            self.true_at[future.result().clock_s] = (pose.x_in, pose.y_in)
        return future


class _Mapped(Exception):
    """Raised from the tick hook to end an ``--explore-only`` episode."""


def found_and_right(played: Played) -> tuple[int, int, int]:
    """(objects found, found and handled right, false records): a record finds the true
    object nearest its first region when within :data:`FOUND_WITHIN_IN`; an object is
    handled right when its first record is judged correct."""
    truths = played.truths()
    judged: dict[int, bool] = {}
    false = 0
    for record, row in played.rows():
        truth = match_truth(record, truths)
        x, y = (record.first_region or record.region).centroid
        if truth is None or math.hypot(truth.x_in - x, truth.y_in - y) > FOUND_WITHIN_IN:
            false += 1
        elif id(truth) in judged:
            false += 1  # a second record of one object
        else:
            judged[id(truth)] = bool(row.correct)
    return len(judged), sum(judged.values()), false


def on_truth_cells(mask: np.ndarray, grid: OccupancyGrid, truth: TruthMap) -> np.ndarray:
    """The grid's ``mask`` (its cells, row 0 at the high-y edge) on the truth's cells (row
    0 at the low-y edge): a truth cell is set when any grid cell centred in it is."""
    rows, cols = np.nonzero(mask)
    x_min, _, _, y_max = grid.bounds
    step = grid.inches_per_cell
    x, y = x_min + (cols + 0.5) * step, y_max - (rows + 0.5) * step
    r = np.floor((y - truth.y0_in) / truth.resolution_in).astype(int)
    c = np.floor((x - truth.x0_in) / truth.resolution_in).astype(int)
    inside = (r >= 0) & (r < truth.occupied.shape[0]) & (c >= 0) & (c < truth.occupied.shape[1])
    out = np.zeros(truth.occupied.shape, dtype=bool)
    out[r[inside], c[inside]] = True
    return out


def episode(world: str, preset: str, seed: int, params: Params, explore_only: bool = False,
            leg_in: float | None = None) -> Measured:
    """One episode: onboard in a home, with the ceiling camera in the lab."""
    onboard = world != LAB
    hero = TruthAtScans("bench", world=world, seed=seed, noise=NOISE_PRESETS[preset])
    sim = hero._live()
    spec, catalogue, start = sim.spec, sim.catalogue, sim.pose
    learner = LocalLearner(Path(tempfile.mkdtemp()) / "library.sqlite",
                           seed_library=read_library_json(EXAMPLE_LIBRARY))
    ex = Executive(hero, learner, params=params, perception="onboard" if onboard else "ceiling")
    if leg_in is not None and ex.perception is not None:  # a probe of the legs' length
        ex.perception.settings = dataclasses.replace(ex.perception.settings, leg_in=leg_in)
    began = time.perf_counter()
    if explore_only:
        def stop_when_mapped(tick: int, root: object) -> None:
            if any(e["event"] == "mapped" for e in ex.log.events[-3:]):
                raise _Mapped
        ex.on_tick = stop_when_mapped
        try:
            ex.run()
        except _Mapped:
            pass
        finally:
            ex.shutdown()
            learner.close()
        present, found, right, false, objects_s = len(hero.truth()), 0, 0, 0, 0.0
        events = ex.log.events
        hero.close()
    else:
        played = play(hero, ex, closing=(learner,))
        present = len(played.start)
        found, right, false = found_and_right(played)
        objects_s = sum(row.robot_s for _, row in played.rows())
        events = played.events
        if not onboard:  # the lab: every object is seen by the camera; found = handled
            found = len(played.rows())
    wall = time.perf_counter() - began
    mapped = [e for e in events if e["event"] == "mapped"]
    explore_s = float(mapped[0]["seconds"]) if mapped else 0.0
    iou = surface = math.nan
    errors, odometry = [math.nan], [math.nan]
    if onboard:
        perception = ex.perception
        truth = truth_map(spec, catalogue, TRUTH_CELL_IN, objects=True)
        footprint = truth_map(spec, catalogue, TRUTH_CELL_IN, layer="footprint", objects=True)
        grid = perception.grid
        iou, surface, _ = map_accuracy(on_truth_cells(grid.occupied, grid, truth),
                                       on_truth_cells(grid.free, grid, truth), truth, footprint,
                                       (start.x_in, start.y_in))
        pairs = [(hero.true_at[clock], reported, corrected) for clock, reported, corrected in perception.poses
                 if clock in hero.true_at]
        errors = [math.hypot(t[0] - c.x_in, t[1] - c.y_in) for t, _, c in pairs] or [math.nan]
        odometry = [math.hypot(t[0] - r.x_in, t[1] - r.y_in) for t, r, _ in pairs] or [math.nan]
    return Measured(world, preset, seed, present, found, right, false, explore_s, objects_s, iou, surface,
                    errors[-1], statistics.median(errors), max(errors), max(odometry), wall)


def spread(values: Sequence[float], fmt: str) -> str:
    """The median, with the range over seeds when they differ."""
    values = [v for v in values if not math.isnan(v)]
    if not values:
        return "-"
    med = format(statistics.median(values), fmt)
    lo, hi = format(min(values), fmt), format(max(values), fmt)
    return med if lo == hi else f"{med} ({lo}-{hi})"


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--homes", default="apartment,apartment-2")
    parser.add_argument("--presets", default="paper", help="noise presets, comma-separated (default paper)")
    parser.add_argument("--seeds", type=int, default=2, help="seeds 0..N-1 (default 2)")
    parser.add_argument("--jobs", type=int, default=1, help="episodes run at once, each in a process (default 1)")
    parser.add_argument("--explore-only", action="store_true",
                        help="end each onboard episode when the home is mapped: map and localisation only")
    parser.add_argument("--leg-in", type=float, default=None,
                        help="override OnboardSettings.leg_in for the run (a probe; default: as shipped)")
    args = parser.parse_args(argv)
    presets = args.presets.split(",")
    unknown = [p for p in presets if p not in NOISE_PRESETS]
    if unknown or args.seeds < 1 or args.jobs < 1:
        print(f"bench_onboard: bad arguments: presets {unknown or 'ok'} (valid: {', '.join(NOISE_PRESETS)}), "
              f"--seeds {args.seeds} and --jobs {args.jobs} must be >= 1", file=sys.stderr)
        return 2
    params = Params()
    homes = args.homes.split(",")
    worlds = homes + ([] if args.explore_only else [LAB])
    runs = [(w, p, s) for w in worlds for p in presets for s in range(args.seeds)]
    with ProcessPoolExecutor(args.jobs) as pool:
        futures = {run: pool.submit(episode, *run, params, args.explore_only, args.leg_in) for run in runs}
        done = {run: f.result() for run, f in futures.items()}

    def group(world: str, preset: str) -> list[Measured]:
        return [done[(world, preset, s)] for s in range(args.seeds)]

    print("| world | preset | seeds | present | found | right | false | explore min | object min / found | "
          "min / present (all) | x lab | IoU | surface IoU | loc final in | loc median in | loc max in | "
          "odometry max in | wall s |")
    print("|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|")
    goals: list[tuple[bool, str]] = []
    for world in worlds:
        for preset in presets:
            ms = group(world, preset)
            lab = None if world == LAB or args.explore_only else statistics.median(
                m.minutes_per_found for m in group(LAB, preset))
            ratio = [m.minutes_per_present / lab for m in ms] if lab else []
            print(f"| {world} | {preset} | {len(ms)} | {spread([m.present for m in ms], 'g')} | "
                  f"{spread([m.found for m in ms], 'g')} | {spread([m.right for m in ms], 'g')} | "
                  f"{spread([m.false for m in ms], 'g')} | {spread([m.explore_s / 60 for m in ms], '.1f')} | "
                  f"{spread([m.minutes_per_found for m in ms], '.2f')} | "
                  f"{spread([m.minutes_per_present for m in ms], '.2f')} | {spread(ratio, '.2f')} | "
                  f"{spread([m.iou for m in ms], '.2f')} | {spread([m.surface_iou for m in ms], '.2f')} | "
                  f"{spread([m.loc_final_in for m in ms], '.1f')} | {spread([m.loc_median_in for m in ms], '.1f')} | "
                  f"{spread([m.loc_max_in for m in ms], '.1f')} | {spread([m.odometry_max_in for m in ms], '.1f')} | "
                  f"{spread([m.wall_s for m in ms], '.0f')} |", flush=True)
            if world == LAB or preset != "paper":
                continue
            surface = statistics.median(m.surface_iou for m in ms)
            goals.append((surface >= GOAL_SURFACE_IOU,
                          f"{world} paper: surface IoU {surface:.3f} (at least {GOAL_SURFACE_IOU})"))
            if args.explore_only:
                continue
            found = sum(m.found for m in ms) / max(sum(m.present for m in ms), 1)
            right = sum(m.right for m in ms) / max(sum(m.found for m in ms), 1)
            goals.append((found >= GOAL_FOUND,
                          f"{world} paper: found {found:.0%} of present (at least {GOAL_FOUND:.0%})"))
            goals.append((right >= GOAL_RIGHT, f"{world} paper: handled right {right:.0%} of found "
                                               f"(at least {GOAL_RIGHT:.0%})"))
            times = statistics.median(ratio) if ratio else math.inf
            goals.append((times <= GOAL_TIME_RATIO, f"{world} paper: robot time per object present {times:.2f}x the "
                                                    f"ceiling-camera lab's (at most {GOAL_TIME_RATIO}x)"))
    return report_goals(goals)


if __name__ == "__main__":
    raise SystemExit(main())
