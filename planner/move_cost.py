"""The move-cost heuristic: seconds of robot time to reach a pose (docs/method.md §3, C(F)).

A move costs overhead-camera processing, driving, turning in place and sonar centring:

    seconds = vision_s + length / speed_in_per_s + turning / turn_deg_per_s + centring_s

Two modes price the same formula. *Exact* plans the path with OMPL and prices its
length and turning. *Estimate* answers from a grid distance field rooted at the
robot's cell (computed once per map and start cell, then a lookup per candidate), so
that the learner can price dozens of candidate positions for the cost of one
Dijkstra. Turning is the straight line's (to the goal's bearing, then to the goal
heading) when the way is clear; for a detour it is read off the grid's shortest path,
traced back through the field and simplified to a few legs. A pose the base cannot
reach costs ``inf``, which the learner reads as "never go there".
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import cv2
import numpy as np

from planner.cache import LruCache
from planner.geometry import Pose, angle_between
from planner.grid_search import GRID_TO_EUCLIDEAN, GridGraph, descend
from planner.paths import (
    ESCAPE_LIMIT_IN, GOAL_BLOCKED, GOAL_OUTSIDE, OK, START_BLOCKED, START_OUTSIDE, UNREACHABLE, PlanResult,
)
from planner.vision_map import VisionMap
from robot_profile import RobotMotion

# A goal this close to the start (inches, degrees) needs no move at all.
ARRIVED_IN = 0.5
ARRIVED_DEG = 2.0
# A grid distance beyond this multiple of the straight line (plus a cell) is a detour:
# its turns are read off the grid's shortest path, simplified to legs at this
# tolerance (cells), instead of the straight line's two turns.
DETOUR_RATIO = 1.02
DETOUR_SIMPLIFY_CELLS = 3.0


@dataclass(frozen=True)
class MoveCost:
    """The price of one move and what it is made of (``inf`` seconds: impossible)."""

    seconds: float
    length_in: float
    turning_deg: float
    exact: bool
    reason: str
    detour_s: float = 0.0  # of ``seconds``: a dock detour the executive priced in (executive.battery_cost)

    @property
    def possible(self) -> bool:
        """True when the goal can be reached."""
        return math.isfinite(self.seconds)


def move_seconds(model: RobotMotion, length_in: float, turning_deg: float) -> float:
    """The heuristic's formula for a move of this length and total turning."""
    if not (math.isfinite(length_in) and math.isfinite(turning_deg)):
        return math.inf
    return model.vision_s + length_in / model.speed_in_per_s + turning_deg / model.turn_deg_per_s + model.centring_s


def arrived(start: Pose, goal: Pose) -> bool:
    """True when the robot already stands at the goal pose."""
    return (math.hypot(goal.x_in - start.x_in, goal.y_in - start.y_in) <= ARRIVED_IN
            and angle_between(start.heading_deg, goal.heading_deg) <= ARRIVED_DEG)


def price_plan(model: RobotMotion, plan: PlanResult) -> MoveCost:
    """Exact mode: the cost of driving a planned path."""
    if not plan.found:
        return MoveCost(math.inf, math.inf, math.inf, True, plan.reason)
    return MoveCost(move_seconds(model, plan.length_in, plan.turning_deg), plan.length_in,
                    plan.turning_deg, True, OK)


# The estimate mode searches a grid this many times coarser than the camera's.
FIELD_COARSENING = 2
# Distance fields an estimator keeps (one per start block): the exact rule prices moves
# from every position its search explores, tens per object on one map, and comes back
# to them. The fields of the coarse grid alone are kept, so these take about the memory
# eight fields did with their copies on the map's own grid.
FIELDS_KEPT = 32
# How far a start's first distance field reaches (inches): past the longest move between
# two positions around one object that the learner usually prices. A goal beyond it
# costs a second, whole field from that start.
FIELD_REACH_IN = 100.0


class CostEstimator:
    """Estimate mode on one vision map: distance fields cached per start block."""

    def __init__(self, vision_map: VisionMap, model: RobotMotion, cache_size: int = FIELDS_KEPT) -> None:
        self.map = vision_map
        self.model = model
        self._fields: LruCache[np.ndarray] = LruCache(cache_size)
        self._graph: GridGraph | None = None  # built on the first field: a map may never be priced

    @property
    def fields_computed(self) -> int:
        """How many distance fields were computed (each costs one Dijkstra)."""
        return self._fields.misses

    def _field(self, cell: tuple[int, int], goal_cell: tuple[int, int]) -> np.ndarray:
        """The distances (inches, any-angle corrected) from a free cell's block to the
        blocks of the coarse grid the search runs on: at least as far as ``goal_cell``'s
        (``inf`` there: the goal cannot be reached).

        Pricing needs inches, not the camera's 0.8 in cells: the map is coarsened
        :data:`FIELD_COARSENING` times (a block is free when any of its cells is;
        inflated obstacles are far thicker than a block, so no wall opens) and the
        search runs over a quarter of the cells. Every cell of a block starts the same
        search, so fields are kept per block: the learner prices from many positions a
        few inches apart. A free cell's distance is its block's (:meth:`estimate`
        prices free goals only), so no field on the map's own grid is made. A start's
        first search stops at :data:`FIELD_REACH_IN`, where the learner's moves around
        one object end; a goal beyond it, or none reachable, gets the whole search (the
        distances within the reach are the same to the last bit, ``GridGraph.distances_from``).
        """
        k = FIELD_COARSENING
        if self._graph is None:
            rows, cols = self.map.free.shape
            padded = np.zeros((-(-rows // k) * k, -(-cols // k) * k), dtype=bool)
            padded[:rows, :cols] = self.map.free
            self._graph = GridGraph(padded.reshape(padded.shape[0] // k, k, padded.shape[1] // k, k).any(axis=(1, 3)))
        graph, block, goal_block = self._graph, (cell[0] // k, cell[1] // k), (goal_cell[0] // k, goal_cell[1] // k)
        scale = k * self.map.image.inches_per_pixel * GRID_TO_EUCLIDEAN
        near = self._fields.get_or_make((block, False),
                                        lambda: graph.distances_from(block, FIELD_REACH_IN / scale) * scale)
        if math.isfinite(near[goal_block]):
            return near
        return self._fields.get_or_make((block, True), lambda: graph.distances_from(block) * scale)

    def estimate(self, start: Pose, goal: Pose) -> MoveCost:
        """The estimated cost of moving from ``start`` to ``goal``.

        A start in the inflated margin is left by the shortest way out first, as the
        planner does (``paths.ESCAPE_LIMIT_IN``).
        """
        start.require_finite("start")
        goal.require_finite("goal")
        if arrived(start, goal):
            return MoveCost(0.0, 0.0, 0.0, False, OK)
        goal_cell = self.map.cell_of(goal.x_in, goal.y_in)
        exit_point = self.map.nearest_free(start.x_in, start.y_in, ESCAPE_LIMIT_IN)
        reason = (START_OUTSIDE if not self.map.contains(start.x_in, start.y_in)
                  else GOAL_OUTSIDE if goal_cell is None
                  else GOAL_BLOCKED if not self.map.free[goal_cell]
                  else START_BLOCKED if exit_point is None else None)
        if reason is not None:
            return MoveCost(math.inf, math.inf, math.inf, False, reason)
        escape = math.hypot(exit_point[0] - start.x_in, exit_point[1] - start.y_in)
        coarse = self._field(self.map.cell_of(*exit_point), goal_cell)
        k = FIELD_COARSENING
        length = float(coarse[goal_cell[0] // k, goal_cell[1] // k]) + escape
        if not math.isfinite(length):
            return MoveCost(math.inf, math.inf, math.inf, False, UNREACHABLE)
        # The field measures cell to cell; the straight line is a floor on the length.
        straight = math.hypot(goal.x_in - start.x_in, goal.y_in - start.y_in)
        if length <= straight * DETOUR_RATIO + self.map.image.inches_per_pixel:
            length = max(length, straight)
            turning = _turning(start, goal, [(start.x_in, start.y_in), (goal.x_in, goal.y_in)])
        else:
            turning = _turning(start, goal, self._detour(coarse, start, goal, goal_cell))
        return MoveCost(move_seconds(self.model, length, turning), length, turning, False, OK)

    def _detour(self, coarse: np.ndarray, start: Pose, goal: Pose, goal_cell: tuple[int, int]
                ) -> list[tuple[float, float]]:
        """The grid's shortest path as a few straight legs (for its turns), descended on
        the coarse field it was searched on."""
        k = FIELD_COARSENING
        cells = np.array([(col, row) for row, col in descend(coarse, (goal_cell[0] // k, goal_cell[1] // k))],
                         np.float32)
        corners = cv2.approxPolyDP(cells.reshape(-1, 1, 2), DETOUR_SIMPLIFY_CELLS / k, False).reshape(-1, 2)
        centres = corners * k + (k - 1) / 2.0
        points = [tuple(p) for p in self.map.image.to_world(centres[:, 1], centres[:, 0])]
        return [(start.x_in, start.y_in)] + points[1:-1] + [(goal.x_in, goal.y_in)]


def _turning(start: Pose, goal: Pose, polyline: list[tuple[float, float]]) -> float:
    """Turn onto each leg in place, then to the goal heading (legs under half an inch,
    like a move that is all turning, add no turn of their own)."""
    headings = [start.heading_deg]
    for (ax, ay), (bx, by) in zip(polyline, polyline[1:]):
        if math.hypot(bx - ax, by - ay) > ARRIVED_IN:
            headings.append(math.degrees(math.atan2(by - ay, bx - ax)))
    headings.append(goal.heading_deg)
    return sum(angle_between(a, b) for a, b in zip(headings, headings[1:]))
