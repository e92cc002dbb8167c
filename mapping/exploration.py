"""Where to explore next, and when the home is mapped.

The next exploration goal is a frontier region (:mod:`mapping.frontiers`) and a pose to
look at it from. Only unknown space more than ``surface_in`` from every occupied cell
makes a frontier: the inside of a wall, of furniture or of a box, and the noise round a
surface, are unknown for good, and chasing them cost most of the exploration under
range noise (docs/mapping.md, "Exploration time"). Each region large enough to matter
(``min_frontier_in`` of frontier, counted in cells: a gap behind furniture or between
table legs is not worth a trip) gets a *viewing pose*: the known-free cell nearest the
frontier's middle (its cell nearest its centroid) that leaves the base ``clearance_in``
from every occupied and unknown cell and from every candidate not yet handled, lies
within ``view_range_in`` of the frontier's middle, and sees it (no occupied cell on the
line between), facing it; when the middle has none, the same for the frontier's cell
nearest the robot (:func:`targets`). So the goal never lies in unknown space, and
standing there the range finder looks straight into what is unknown.

The goal is the region whose viewing pose is cheapest to reach, weighted by its size:
``move_cost(pose) / size ** size_exponent`` (with the exponent 0.5 a frontier four times
larger is worth a trip twice as long). ``move_cost`` is any callable from a pose to
seconds — the planner's estimate in the executive, a straight-line time in the tests —
and ``inf`` for a pose it cannot reach. A viewing pose within ``arrived_in`` of the
robot is skipped: the robot is there already, and what it cannot see from there (beyond
the range, behind glass) it will not see by standing still.

The home is mapped when no frontier region of at least ``min_frontier_in`` (beside
unknown space beyond ``surface_in``) has a viewing pose the robot can reach. Pure
functions of their inputs; ties go to the frontiers' own order (largest first, then by
first cell), so the result is the same run to run.
"""

from __future__ import annotations

import math
from collections.abc import Callable, Sequence
from dataclasses import dataclass

import cv2
import numpy as np

from mapping.candidates import Candidate
from mapping.frontiers import Frontier, frontiers
from mapping.occupancy import OccupancyGrid
from planner.geometry import Pose

MoveCost = Callable[[Pose], float]


@dataclass(frozen=True)
class ExplorationSettings:
    """The rules' numbers (inches); docs/mapping.md says why."""

    min_frontier_in: float = 12.0  # frontier regions shorter than this are not worth a trip
    surface_in: float = 6.0  # unknown this near an occupied cell is a surface's inside or noise, not space
    clearance_in: float = 12.0  # viewing pose from occupied and unknown cells (base radius 9 in + 3 in)
    candidate_clearance_in: float = 12.0  # ... and from a candidate's outline (not on top of an object)
    view_range_in: float = 60.0  # viewing pose within this of the frontier's middle
    arrived_in: float = 6.0  # a viewing pose this close to the robot is where it already stands
    size_exponent: float = 0.5

    def __post_init__(self) -> None:
        for name in ("min_frontier_in", "surface_in", "clearance_in", "candidate_clearance_in", "view_range_in",
                     "arrived_in"):
            value = getattr(self, name)
            if not (math.isfinite(value) and value >= 0):
                raise ValueError(f"exploration setting {name} must be finite and not negative, got {value}")
        if not (math.isfinite(self.size_exponent) and self.size_exponent >= 0):
            raise ValueError(f"exploration setting size_exponent must be finite and not negative, "
                             f"got {self.size_exponent}")

    def min_cells(self, inches_per_cell: float) -> int:
        return max(1, math.ceil(self.min_frontier_in / inches_per_cell - 1e-9))


@dataclass(frozen=True)
class ExplorationGoal:
    """Where to go next: a viewing pose facing the frontier cell it looks at (``target``:
    the middle, or the cell nearest the robot), its cost (seconds) and score (cost over
    size to the exponent: lower is better)."""

    pose: Pose
    frontier: Frontier
    target_x_in: float
    target_y_in: float
    cost_s: float
    score: float


def frontier_middle(grid: OccupancyGrid, frontier: Frontier) -> tuple[int, int]:
    """The frontier's cell nearest its centroid (the centroid of a bent frontier may lie
    off it, in free or unknown space)."""
    cells = np.array(frontier.cells)
    centres = grid.grid.to_world(cells[:, 0], cells[:, 1])
    k = int(np.argmin(np.hypot(centres[:, 0] - frontier.centroid_x_in, centres[:, 1] - frontier.centroid_y_in)))
    return int(cells[k, 0]), int(cells[k, 1])


def standing_room(grid: OccupancyGrid, candidates: Sequence[Candidate] = (),
                  settings: ExplorationSettings = ExplorationSettings()) -> np.ndarray:
    """The cells a viewing pose may be in: free, ``clearance_in`` from any cell not known
    free (the grid's edge counts as not free) and ``candidate_clearance_in`` from every
    candidate's outline."""
    free = np.pad(grid.free, 1, constant_values=False).astype(np.uint8)
    distance_in = cv2.distanceTransform(free, cv2.DIST_L2, cv2.DIST_MASK_PRECISE)[1:-1, 1:-1] * grid.inches_per_cell
    room = grid.free & (distance_in >= settings.clearance_in)
    outline = np.array([p for c in candidates for p in c.outline]).reshape(-1, 2)
    rows, cols = (np.floor(v).astype(int) for v in grid.grid.to_cell(outline[:, 0], outline[:, 1]))
    height, width = grid.shape
    inside = (rows >= 0) & (rows < height) & (cols >= 0) & (cols < width)
    if inside.any():
        clear = np.ones(grid.shape, dtype=np.uint8)
        clear[rows[inside], cols[inside]] = 0
        # cell centre to the centre of an outline cell: the outline point may lie half a cell nearer
        to_object_in = cv2.distanceTransform(clear, cv2.DIST_L2, cv2.DIST_MASK_PRECISE) * grid.inches_per_cell
        room &= to_object_in >= settings.candidate_clearance_in + grid.inches_per_cell / math.sqrt(2)
    return room


def _sees(grid: OccupancyGrid, start: tuple[float, float], end: tuple[float, float],
          occupied: np.ndarray | None = None) -> bool:
    """No occupied cell on the segment between two world points (sampled at quarter cells);
    ``occupied``: the grid's, when the caller has it already."""
    steps = max(1, math.ceil(math.dist(start, end) / (0.25 * grid.inches_per_cell)))
    t = np.linspace(0.0, 1.0, steps + 1)
    xs, ys = start[0] + t * (end[0] - start[0]), start[1] + t * (end[1] - start[1])
    rows, cols = (np.floor(v).astype(int) for v in grid.grid.to_cell(xs, ys))
    height, width = grid.shape
    inside = (rows >= 0) & (rows < height) & (cols >= 0) & (cols < width)
    occupied = grid.occupied if occupied is None else occupied
    return not occupied[rows[inside], cols[inside]].any()


def viewing_pose(grid: OccupancyGrid, frontier: Frontier, room: np.ndarray,
                 settings: ExplorationSettings = ExplorationSettings(), *,
                 occupied: np.ndarray | None = None, target: tuple[int, int] | None = None) -> Pose | None:
    """The cell of ``room`` nearest the frontier's ``target`` cell (default: its middle),
    within ``view_range_in`` and seeing it, as a pose facing it; None when there is none.
    ``occupied``: the grid's, when the caller has it already (it is computed once per
    question, not per cell)."""
    middle = grid.grid.to_world(*(frontier_middle(grid, frontier) if target is None else target))[0]
    occupied = grid.occupied if occupied is None else occupied
    reach = math.ceil(settings.view_range_in / grid.inches_per_cell) + 1
    (row0, col0), = np.floor(np.array([grid.grid.to_cell(float(middle[0]), float(middle[1]))])).astype(int)
    r0, c0 = max(row0 - reach, 0), max(col0 - reach, 0)
    rows, cols = np.nonzero(room[r0:row0 + reach + 1, c0:col0 + reach + 1])  # the cells within range only
    rows, cols = rows + r0, cols + c0
    if len(rows) == 0:
        return None
    centres = grid.grid.to_world(rows, cols)
    distance = np.hypot(centres[:, 0] - middle[0], centres[:, 1] - middle[1])
    for k in np.lexsort((cols, rows, distance)):
        if distance[k] > settings.view_range_in:
            return None
        x, y = float(centres[k, 0]), float(centres[k, 1])
        if _sees(grid, (x, y), (float(middle[0]), float(middle[1])), occupied):
            return Pose(x, y, math.degrees(math.atan2(middle[1] - y, middle[0] - x)))
    return None


def targets(grid: OccupancyGrid, frontier: Frontier, robot: Pose) -> tuple[tuple[int, int], ...]:
    """The frontier's cells to look at, in turn: its middle, then its cell nearest the
    robot. A long frontier bent round a room seen only through its doorway has its
    middle deep in that room, where no viewing pose may see it; its end at the doorway
    can be looked at from this side."""
    middle = frontier_middle(grid, frontier)
    cells = np.array(frontier.cells)
    centres = grid.grid.to_world(cells[:, 0], cells[:, 1])
    k = int(np.argmin(np.hypot(centres[:, 0] - robot.x_in, centres[:, 1] - robot.y_in)))
    nearest = (int(cells[k, 0]), int(cells[k, 1]))
    return (middle,) if nearest == middle else (middle, nearest)


def exploration_goals(grid: OccupancyGrid, robot: Pose, candidates: Sequence[Candidate], move_cost: MoveCost,
                      settings: ExplorationSettings = ExplorationSettings()) -> list[ExplorationGoal]:
    """Every frontier region worth a trip with a reachable viewing pose, best first."""
    room = standing_room(grid, candidates, settings)
    occupied = grid.occupied
    goals = []
    for frontier in frontiers(grid, settings.min_cells(grid.inches_per_cell), settings.surface_in):
        for target in targets(grid, frontier, robot):
            pose = viewing_pose(grid, frontier, room, settings, occupied=occupied, target=target)
            if pose is not None:
                break
        if pose is None or math.dist((pose.x_in, pose.y_in), (robot.x_in, robot.y_in)) <= settings.arrived_in:
            continue
        cost = float(move_cost(pose))
        if not math.isfinite(cost):
            continue
        looked_at = grid.grid.to_world(*target)[0]
        goals.append(ExplorationGoal(pose, frontier, float(looked_at[0]), float(looked_at[1]), cost,
                                     cost / frontier.size ** settings.size_exponent))
    return sorted(goals, key=lambda g: g.score)  # stable: ties keep the frontiers' order


def next_goal(grid: OccupancyGrid, robot: Pose, candidates: Sequence[Candidate], move_cost: MoveCost,
              settings: ExplorationSettings = ExplorationSettings()) -> ExplorationGoal | None:
    """The next exploration goal; None when the home is mapped (:func:`is_mapped`)."""
    goals = exploration_goals(grid, robot, candidates, move_cost, settings)
    return goals[0] if goals else None


def is_mapped(grid: OccupancyGrid, robot: Pose, candidates: Sequence[Candidate], move_cost: MoveCost,
              settings: ExplorationSettings = ExplorationSettings()) -> bool:
    """No frontier region of at least ``min_frontier_in`` (beside unknown space beyond
    ``surface_in``) has a viewing pose the robot can reach."""
    return next_goal(grid, robot, candidates, move_cost, settings) is None
