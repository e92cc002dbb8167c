"""A robot without a ceiling camera, measured against the simulator's truth: the objects
it found, the map it built, and how well it knew where it stood.

Only a simulator knows the truth, and three things read it the same way: the onboard
study (``csl experiment onboard``, :mod:`experiments.study_onboard`), its bench
(``bench/bench_onboard.py``, for speed) and the mapping bench
(``bench/bench_mapping_sim.py``, the mapping stack alone on a survey route). So each
measure is written once here:

- **found**: a record finds the true object nearest where it was first seen
  (``reporting.report.match_truth``, as every report of the project matches) when it
  was seen within ``reporting.report.FOUND_WITHIN_IN`` of it (``found_truth``); further
  away it found something that
  is not there, a *false* record, as is a second record of an object already found;
- **the map**: the built occupancy grid, resampled to the truth's cells, against
  ``hero_driver.sim.truth_map``: the IoU of occupied cells as they are (a robot never
  sees inside a wall or behind it, so a perfect one scores below 1) and the *surface*
  IoU, the true cells a robot can see against the built ones, which is what the
  onboard page's goal reads;
- **localisation**: each scan's corrected pose against where the simulator really had
  the robot when the scan was taken (:class:`TruthAtScans` notes it, keyed by the
  scan's clock), and the raw odometry's beside it.
"""

from __future__ import annotations

import statistics
from collections.abc import Mapping, Sequence
from concurrent.futures import Future
from dataclasses import dataclass
from typing import Any

import numpy as np
from scipy import ndimage

from behaviours.records import ObjectRecord
from hero_driver.interface import RangeScan
from hero_driver.sim.truth_map import TruthMap
from hero_driver.sim_driver import SimulatedHero
from mapping import LocalisationError, OccupancyGrid, localisation_error
from planner.geometry import Pose
from reporting.report import Row, Truth, found_truth

@dataclass(frozen=True)
class Found:
    """Objects found, found and handled right (the report's ``correct``), and false
    records (matching no object, or a second record of one)."""

    found: int
    right: int
    false: int


def found_and_right(judged: Sequence[tuple[ObjectRecord, Row]], truths: Sequence[Truth]) -> Found:
    """Count ``judged`` (each record with its report row) against the objects present:
    an object is handled right when its first record is judged correct, so a second
    try at an object already found cannot make up for the first."""
    right_by_object: dict[int, bool] = {}
    false = 0
    for record, row in judged:
        truth = found_truth(record, truths)
        if truth is None or id(truth) in right_by_object:
            false += 1
        else:
            right_by_object[id(truth)] = bool(row.correct)
    return Found(len(right_by_object), sum(right_by_object.values()), false)


def on_truth_cells(mask: np.ndarray, grid: OccupancyGrid, truth: TruthMap) -> np.ndarray:
    """The grid's ``mask`` (its cells, row 0 at the high-y edge) on the truth's cells
    (row 0 at the low-y edge): a truth cell is set when any grid cell centred in it is.
    The robot's grid has its own extent and resolution; the truth is compared cell by
    cell, so the built map comes to it."""
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


def surface_iou(built: np.ndarray, truth: np.ndarray, free: np.ndarray) -> float:
    """Visible true cells (occupied, beside a truly ``free`` one) against ``built``
    occupied cells, each matched when the other has an occupied cell within one cell: a
    wall drawn a cell off is still the wall, and what no robot could see is not asked of
    it. 1.0 when both are empty."""
    visible = truth & ndimage.binary_dilation(free)
    near_built = ndimage.binary_dilation(built, structure=np.ones((3, 3), bool))
    near_truth = ndimage.binary_dilation(visible, structure=np.ones((3, 3), bool))
    matched = (visible & near_built).sum() + (built & near_truth).sum()
    total = visible.sum() + built.sum()
    return float(matched / total) if total else 1.0


@dataclass(frozen=True)
class MapAccuracy:
    """A built map against the truth: IoU of occupied cells, surface IoU, and the share
    of the home's free floor the map knows to be free."""

    iou: float
    surface_iou: float
    coverage: float


def map_accuracy(grid: OccupancyGrid, truth: TruthMap, footprint: TruthMap, start: tuple[float, float]) -> MapAccuracy:
    """``grid`` against ``truth`` (the scan plane's map, objects included) on the truth's
    cells; the home's free floor is the floor free in both ``truth`` and ``footprint``
    (the furniture's outlines on the floor) that is reachable from ``start``: the rooms
    the robot could enter, not the inside of a cupboard."""
    built = on_truth_cells(grid.occupied, grid, truth)
    built_free = on_truth_cells(grid.free, grid, truth)
    truly_free = ~footprint.occupied & ~truth.occupied
    reachable = ndimage.label(truly_free)[0]
    home_free = reachable == reachable[truth.cell_of(*start)]
    inter, union = (built & truth.occupied).sum(), (built | truth.occupied).sum()
    coverage = float((built_free & home_free).sum() / home_free.sum())
    return MapAccuracy(float(inter / union) if union else 1.0, surface_iou(built, truth.occupied, home_free), coverage)


@dataclass(frozen=True)
class Localisation:
    """Each scan's corrected pose and the odometry's (the pose the scan was stamped with)
    against the truth at that scan, in the scans' order."""

    corrected: LocalisationError
    odometry: LocalisationError

    @property
    def median_in(self) -> float:
        return statistics.median(self.corrected.position_in)


def localisation(poses: Sequence[tuple[float, Pose, Pose]], true_at: Mapping[float, Pose]) -> Localisation | None:
    """``poses``: ``(clock, reported, corrected)`` of each scan (as
    ``executive.onboard.OnboardPerception.poses`` keeps them); ``true_at``: the true
    pose at each scan's clock. Scans with no truth are left out; None when none has."""
    known = [(clock, reported, corrected) for clock, reported, corrected in poses if clock in true_at]
    if not known:
        return None
    stamps = [clock for clock, _, _ in known]
    truths = [true_at[clock] for clock in stamps]
    return Localisation(localisation_error([c for _, _, c in known], truths, stamps),
                        localisation_error([r for _, r, _ in known], truths, stamps))


class TruthAtScans(SimulatedHero):
    """The simulator, noting its true pose at every scan (by the scan's clock): the
    truth the corrected poses are measured against, which no driver reply carries."""

    def __init__(self, *args: Any, **kwargs: Any) -> None:
        super().__init__(*args, **kwargs)
        self.true_at: dict[float, Pose] = {}

    def scan(self) -> Future[RangeScan]:
        future = super().scan()
        if future.exception() is None:
            pose = self.world.pose
            self.true_at[future.result().clock_s] = Pose(pose.x_in, pose.y_in, pose.heading_deg)
        return future
