"""Move costs: what it costs the robot to go from one position to another.

The learner prices every candidate test from where the robot stands *now*, so the
estimator is pluggable: the knowledge file's simple model by default, the planner's
map-based heuristic once an executive provides one (any object with ``move_cost``).
"""

from __future__ import annotations

import math
from typing import Protocol, runtime_checkable

from learner.knowledge import MoveModel
from learner.position import Position


@runtime_checkable
class MoveCostEstimator(Protocol):
    """Seconds to move the sensor from ``start`` to ``goal`` (both concrete); ``inf``: no path."""

    def move_cost(self, start: Position, goal: Position) -> float: ...


class ModelMoveCost:
    """The knowledge file's model: straight-line travel, the turns, a fixed overhead.

    Positions are polar around the object's centre. The robot faces the object at both
    ends, so it turns towards the goal, drives, and turns back to face the object.
    """

    def __init__(self, model: MoveModel) -> None:
        self.model = model

    def move_cost(self, start: Position, goal: Position) -> float:
        if start.distance_in is None or goal.distance_in is None:
            raise ValueError(f"move cost needs concrete positions, got {start} -> {goal}")
        sx, sy = _point(start)
        gx, gy = _point(goal)
        length = math.hypot(gx - sx, gy - sy)
        if length < 1e-9:
            return 0.0
        face_start = (start.orientation_deg or 0.0) + 180.0
        face_goal = (goal.orientation_deg or 0.0) + 180.0
        travel = math.degrees(math.atan2(gy - sy, gx - sx))
        turning = abs(_wrap(travel - face_start)) + abs(_wrap(face_goal - travel))
        m = self.model
        return m.overhead_s + m.seconds_per_inch * length + m.seconds_per_degree * turning


def _point(p: Position) -> tuple[float, float]:
    theta = math.radians(p.orientation_deg or 0.0)
    d = p.distance_in or 0.0
    return d * math.cos(theta), d * math.sin(theta)


def _wrap(deg: float) -> float:
    return (deg + 180.0) % 360.0 - 180.0
