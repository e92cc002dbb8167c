"""Collision-free paths for the base on the vision map, planned with OMPL.

The base is a disc and the map is inflated by its radius, so planning is for a point
in R² (the heading only matters at the ends, where it becomes turning time).

The map stays the same while the robot drives about (the robot is not an obstacle),
and the learner asks for many paths on it, so the default planner is a roadmap: OMPL's
PRM grows it once per map (:mod:`planner.roadmap`), and each query connects start and
goal to it and searches it in a few milliseconds, taking the shorter way round
obstacles, which a single RRT-Connect tree leaves to chance. When the roadmap cannot
connect a query (a narrow passage it missed), RRT-Connect is restarted within the time
limit and the shortest of its paths kept. Informed RRT* with a path-length objective
is used on request. Every path is shortened by OMPL's simplifier (the shorter of raw
and simplified is kept), checked exactly against the grid, and cut into waypoints for
the driver.

OMPL's seed sequence is restarted (:data:`PLANNER_SEED`) before every sampling run,
the roadmap is grown single-threaded to a fixed size and searched deterministically,
so the same question on the same map gets the same path, whatever the process planned
before (OMPL offers no per-planner seed in Python).
"""

from __future__ import annotations

import math
import time
from collections.abc import Callable
from dataclasses import dataclass
from typing import Any

import cv2
import numpy as np
from ompl import base as ob
from ompl import geometric as og
from ompl import util as ou

from planner.cache import LruCache
from planner.geometry import Pose, angle_between
from planner.roadmap import Roadmap
from planner.vision_map import VisionMap

PLANNER_SEED = 1991
ou.setLogLevel(ou.LOG_WARN)
ou.RNG.setSeed(PLANNER_SEED)


def _reseed(run: int = 0) -> None:
    """Restart OMPL's seed sequence (at a seed per ``run``), so that the random numbers
    of the OMPL objects made next do not depend on what the process planned before.
    OMPL does restart it, but complains at error level that sampling already began;
    that complaint is silenced here."""
    ou.setLogLevel(ou.LOG_NONE)
    ou.RNG.setSeed(PLANNER_SEED + run)
    ou.setLogLevel(ou.LOG_WARN)

# Why a plan has no path; the learner prices every one of them as an infinite move.
OK = "ok"
START_OUTSIDE = "start outside the map"
START_BLOCKED = "start in an obstacle"
GOAL_OUTSIDE = "goal outside the map"
GOAL_BLOCKED = "goal in an obstacle"
UNREACHABLE = "goal unreachable from start"
TIMEOUT = "no path found within the time limit"

# Planner names as reported in PlanResult.planner.
STRAIGHT = "straight line"
ROADMAP = "PRM"
TREE = "RRTConnect"
OPTIMAL = "InformedRRTstar"

# Sampling planners stay near the grid's resolution: motions are checked every half
# cell (see VisionMap.free_strict for why that suffices).
CHECK_STEP_CELLS = 0.5
# Around the start and the goal the one-cell safety margin of ``free_strict`` is waived
# (within this many cells), so that poses right at the edge of the free space can still
# be left and reached; the exact segment check afterwards keeps the guarantee.
ENDPOINT_MARGIN_CELLS = 2
# Roadmap size, grown on the first query that needs it: ~0.15 s on the default lab,
# after which roadmap routes are within a few per cent of the grid's shortest paths.
ROADMAP_MILESTONES = 400
# Growth stops at the milestone count, so the roadmap (and every path on it) is the same
# however busy the machine is; this many seconds is only a safety net for a map with
# too little free space to hold that many milestones.
ROADMAP_MAX_S = 10.0
# A start this close to free space (but in the inflated margin) is left by the shortest
# way out first: vision, odometry and the margin's own half-pixel rounding each put a
# robot that stopped at the edge of free space an inch or so inside it. Deeper than
# this the base would overlap an obstacle, and the start is reported as blocked.
ESCAPE_LIMIT_IN = 4.0
# A path this close to the straight-line distance cannot be beaten by restarting.
GOOD_ENOUGH = 1.02

Polyline = list[tuple[float, float]]


@dataclass(frozen=True)
class PlanResult:
    """A path for the driver, or why there is none.

    ``path`` holds the waypoints (world poses, the start excluded, the goal last with
    the goal heading; the others face along the path). ``length_in`` and
    ``turning_deg`` (start heading to path, along it, to goal heading) are what a move
    costs; both are ``inf`` when there is no path. ``escape_in`` is the length of a
    first segment that leaves the inflated margin the start stood in (0 normally);
    everything after it keeps clear of inflated obstacles.
    """

    path: tuple[Pose, ...] | None
    reason: str
    length_in: float
    turning_deg: float
    planner: str
    escape_in: float = 0.0

    @property
    def found(self) -> bool:
        """True when there is a path."""
        return self.path is not None

    @property
    def corners(self) -> tuple[tuple[float, float], ...]:
        """Waypoint positions only."""
        return () if self.path is None else tuple((p.x_in, p.y_in) for p in self.path)

    @staticmethod
    def none(reason: str, planner: str) -> PlanResult:
        """The no-path result (infinite cost) for ``reason``."""
        return PlanResult(None, reason, math.inf, math.inf, planner)


class PathPlanner:
    """Plans on one vision map; keeps its roadmap and recent plans between queries.

    The OMPL objects live inside this object (not at module level) and the validity
    callback holds no reference back to it, so they are released cleanly.
    """

    def __init__(self, vision_map: VisionMap, *, time_limit_s: float = 0.25,
                 optimise_time_s: float = 0.5, spacing_in: float = 6.0, restarts: int = 3,
                 roadmap_milestones: int = ROADMAP_MILESTONES, cache_size: int = 256,
                 roadmap: Roadmap | None = None) -> None:
        if restarts < 1 or roadmap_milestones < 1:
            raise ValueError(f"restarts and roadmap_milestones must be at least 1, got {restarts} and "
                             f"{roadmap_milestones}")
        self.map = vision_map
        self.restarts = restarts
        self.roadmap_milestones = roadmap_milestones
        self.time_limit_s = time_limit_s
        self.optimise_time_s = optimise_time_s
        self.spacing_in = spacing_in
        self._plans: LruCache[PlanResult] = LruCache(cache_size)
        _, self._components = cv2.connectedComponents(vision_map.free.astype(np.uint8), connectivity=8)

        x_min, x_max, y_min, y_max = vision_map.bounds
        self._space = ob.RealVectorStateSpace(2)
        bounds = ob.RealVectorBounds(2)
        bounds.setLow(0, x_min)
        bounds.setHigh(0, x_max)
        bounds.setLow(1, y_min)
        bounds.setHigh(1, y_max)
        self._space.setBounds(bounds)
        self._strict_cells = _cells(vision_map.free_strict)
        self._valid_holder: list[bytes] = [self._strict_cells]
        self._roadmap: Roadmap | None = roadmap  # one still valid on this map, or grown on demand
        self._tree_setup = self._new_setup()

    @property
    def roadmap(self) -> Roadmap | None:
        """The roadmap grown (or inherited) so far, for a map that only loses obstacles."""
        return self._roadmap

    def _new_setup(self) -> og.SimpleSetup:
        setup = og.SimpleSetup(self._space)
        setup.setStateValidityChecker(_validity_checker(self.map, self._valid_holder))
        step_in = CHECK_STEP_CELLS * self.map.image.inches_per_pixel
        setup.getSpaceInformation().setStateValidityCheckingResolution(step_in / self._space.getMaximumExtent())
        return setup

    def plan(self, start: Pose, goal: Pose, *, optimise: bool = False,
             time_limit_s: float | None = None, spacing_in: float | None = None) -> PlanResult:
        """A path from ``start`` to ``goal`` (poses of the base centre), or why not.

        Raises ValueError for a NaN/infinite pose or a non-positive spacing or time;
        every geometric failure is a :class:`PlanResult` without a path.
        """
        start.require_finite("start")
        goal.require_finite("goal")
        spacing = self.spacing_in if spacing_in is None else spacing_in
        limit = (self.optimise_time_s if optimise else self.time_limit_s) if time_limit_s is None else time_limit_s
        if not (spacing > 0 and limit > 0):
            raise ValueError(f"spacing_in and time_limit_s must be positive, got {spacing} and {limit}")
        key = (_rounded(start), _rounded(goal), optimise, spacing)
        return self._plans.get_or_make(key, lambda: self._plan(start, goal, optimise, limit, spacing))

    def _plan(self, start: Pose, goal: Pose, optimise: bool, limit: float, spacing: float) -> PlanResult:
        name = OPTIMAL if optimise else ROADMAP
        start_cell = self.map.cell_of(start.x_in, start.y_in)
        goal_cell = self.map.cell_of(goal.x_in, goal.y_in)
        if start_cell is None:
            return PlanResult.none(START_OUTSIDE, name)
        if goal_cell is None:
            return PlanResult.none(GOAL_OUTSIDE, name)
        if not self.map.free[goal_cell]:
            return PlanResult.none(GOAL_BLOCKED, name)
        origin = (start.x_in, start.y_in)
        a = self.map.nearest_free(*origin, ESCAPE_LIMIT_IN)
        if a is None:
            return PlanResult.none(START_BLOCKED, name)
        escape = [origin] if a != origin else []
        escape_in = math.dist(origin, a)
        start_cell = self.map.cell_of(*a)
        if self._components[start_cell] != self._components[goal_cell]:
            return PlanResult.none(UNREACHABLE, name)

        b = (goal.x_in, goal.y_in)
        if self.map.segment_is_free(a, b):
            return _result(escape + [a, b], start, goal, spacing, STRAIGHT, escape_in)
        if self._roadmap is None and not optimise:
            self._valid_holder[0] = self._strict_cells  # no query's endpoint exemptions
            _reseed()
            self._roadmap = Roadmap.grow(self._new_setup(), self.roadmap_milestones, ROADMAP_MAX_S)
        self._exempt_endpoints([start_cell, goal_cell])
        deadline = time.perf_counter() + limit
        if optimise:
            found = self._tree(a, b, limit, optimise=True, run=1), OPTIMAL
        else:
            found = self._roadmap_route(a, b), ROADMAP
            if found[0] is None:
                found = self._restarted_trees(a, b, deadline), TREE
        polyline, name = found
        if polyline is None:
            return PlanResult.none(TIMEOUT, name)
        return _result(escape + polyline, start, goal, spacing, name, escape_in)

    def _exempt_endpoints(self, cells: list[tuple[int, int]]) -> None:
        """Validity for this query: ``free_strict``, relaxed to ``free`` near the ends."""
        valid = self.map.free_strict.copy()
        m = ENDPOINT_MARGIN_CELLS
        for row, col in cells:
            window = (slice(max(row - m, 0), row + m + 1), slice(max(col - m, 0), col + m + 1))
            valid[window] |= self.map.free[window]
        self._valid_holder[0] = _cells(valid)

    def _roadmap_route(self, a: tuple[float, float], b: tuple[float, float]) -> Polyline | None:
        """The roadmap's shortest route, with needless vertices removed, or None."""
        route = self._roadmap.route(a, b, self.map.segment_is_free)
        if route is None:
            return None
        si = self._tree_setup.getSpaceInformation()
        path = og.PathGeometric(si, self._ompl_states(*route))
        return self._finish(path, thorough=False)

    def _restarted_trees(self, a: tuple[float, float], b: tuple[float, float], deadline: float) -> Polyline | None:
        """The shortest of up to ``restarts`` RRT-Connect paths found before ``deadline``.

        A single tree's way round obstacles is chance and simplification never changes
        it, so restarts are the way to a short path; they stop early once a path is
        within ``GOOD_ENOUGH`` of the straight-line distance.
        """
        floor = math.dist(a, b) * GOOD_ENOUGH
        best: Polyline | None = None
        for run in range(1, self.restarts + 1):
            remaining = deadline - time.perf_counter()
            if remaining <= 0:
                break
            polyline = self._tree(a, b, remaining, optimise=False, run=run)
            if polyline is not None and (best is None or _polyline_length(polyline) < _polyline_length(best)):
                best = polyline
            if best is not None and _polyline_length(best) <= floor:
                break
        return best

    def _tree(self, a: tuple[float, float], b: tuple[float, float], limit: float, optimise: bool,
              run: int) -> Polyline | None:
        setup = self._tree_setup
        setup.clear()
        _reseed(run)
        setup.setStartAndGoalStates(*self._ompl_states(a, b))
        si = setup.getSpaceInformation()
        if optimise:
            setup.setOptimizationObjective(ob.PathLengthOptimizationObjective(si))
            setup.setPlanner(og.InformedRRTstar(si))
        else:
            setup.setPlanner(og.RRTConnect(si))
        setup.solve(limit)
        if not setup.haveExactSolutionPath():
            return None
        return self._finish(og.PathGeometric(setup.getSolutionPath()), thorough=True)

    def _ompl_states(self, *points: tuple[float, float]) -> list:
        states = []
        for x, y in points:
            state = self._space.allocState()
            state[0], state[1] = x, y
            states.append(state)
        return states

    def _finish(self, raw: og.PathGeometric, thorough: bool) -> Polyline | None:
        """The shorter of the raw and simplified path that passes the exact grid check,
        or None (conceivable only within the endpoint margin).

        A roadmap route already takes a short way and only needs its needless vertices
        removed (0.5 ms); a tree's zig-zag gets OMPL's full simplification (~5 ms).
        """
        simplified = og.PathGeometric(raw)
        _reseed()
        simplifier = og.PathSimplifier(self._tree_setup.getSpaceInformation())
        if thorough:
            simplifier.simplifyMax(simplified)
        else:
            simplifier.reduceVertices(simplified)
        for polyline in sorted((_polyline_of(p) for p in (raw, simplified)), key=_polyline_length):
            if all(self.map.segment_is_free(p, q) for p, q in zip(polyline, polyline[1:])):
                return polyline
        return None


def _cells(grid: np.ndarray) -> bytes:
    """A boolean grid as the validity checker reads it: one byte per cell, row-major."""
    return np.ascontiguousarray(grid, dtype=bool).tobytes()


def _validity_checker(vision_map: VisionMap, holder: list[bytes]) -> Callable[[Any], bool]:
    """A state is valid when its cell is set in ``holder[0]`` (:func:`_cells`; a closure,
    not a method, so that OMPL's reference to it does not keep the planner alive).

    OMPL calls it from C++ for every state it checks, ~180,000 times to grow a roadmap
    on the lab's map: indexing a byte string with plain comparisons for the clamping
    costs about half of indexing the numpy grid with ``min``, for the same answers.
    """
    image = vision_map.image
    x0, y1, inv = image.origin_x_in, image.origin_y_in, 1.0 / image.inches_per_pixel
    cols = vision_map.free.shape[1]
    last_row, last_col = vision_map.free.shape[0] - 1, cols - 1

    def is_valid(state: Any) -> bool:
        col = int((state[0] - x0) * inv)
        row = int((y1 - state[1]) * inv)
        if col > last_col:
            col = last_col
        if row > last_row:
            row = last_row
        return holder[0][row * cols + col] == 1

    return is_valid


def _polyline_of(path: og.PathGeometric) -> Polyline:
    return [(float(s[0]), float(s[1])) for s in path.getStates()]


def _polyline_length(polyline: Polyline) -> float:
    return sum(math.dist(p, q) for p, q in zip(polyline, polyline[1:]))


def _rounded(pose: Pose) -> tuple[float, float, float]:
    """Cache key: poses closer than a tenth of an inch and degree plan alike."""
    return round(pose.x_in, 1), round(pose.y_in, 1), round(pose.heading_deg % 360.0, 1)


def _result(polyline: Polyline, start: Pose, goal: Pose, spacing: float, name: str,
            escape_in: float) -> PlanResult:
    """Waypoints every ``spacing`` inches at most, the path's length and turning."""
    waypoints: list[Pose] = []
    headings = [start.heading_deg]
    for p, q in zip(polyline, polyline[1:]):
        length = math.dist(p, q)
        if length < 1e-9:
            continue
        direction = math.degrees(math.atan2(q[1] - p[1], q[0] - p[0]))
        headings.append(direction)
        pieces = max(1, math.ceil(length / spacing - 1e-9))
        for k in range(1, pieces + 1):
            f = k / pieces
            waypoints.append(Pose(p[0] + f * (q[0] - p[0]), p[1] + f * (q[1] - p[1]), direction))
    headings.append(goal.heading_deg)
    goal_pose = Pose(goal.x_in, goal.y_in, goal.heading_deg)
    if waypoints:
        waypoints[-1] = goal_pose
    else:
        waypoints.append(goal_pose)
    turning = sum(angle_between(h, k) for h, k in zip(headings, headings[1:]))
    return PlanResult(tuple(waypoints), OK, _polyline_length(polyline), turning, name, escape_in)
