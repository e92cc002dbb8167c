"""The robot facts the planner needs, read from the knowledge profile's ``[robot]`` table.

The planner may not import ``hero_driver``, so it reads the same TOML file itself: the
profile is the one place where the simulator and the planner agree on the base's size,
where the sonar sits and how fast the base drives and turns.
"""

from __future__ import annotations

import tomllib
from dataclasses import dataclass
from pathlib import Path


@dataclass(frozen=True)
class RobotGeometry:
    """Where the robot's body and sonar are, relative to its pose (docs/conventions.md).

    ``base_radius_in`` inflates the vision map; ``sensor_offset_in`` places the base
    behind the sonar when converting a learner position into a pose.
    """

    base_radius_in: float
    sensor_offset_in: float
    sensor_height_in: float = 0.0

    def __post_init__(self) -> None:
        if not self.base_radius_in > 0 or not self.sensor_offset_in >= 0:
            raise ValueError(
                f"robot geometry needs base_radius_in > 0 and sensor_offset_in >= 0, got "
                f"{self.base_radius_in} and {self.sensor_offset_in}"
            )


@dataclass(frozen=True)
class MoveModel:
    """How long the base takes to move: the terms of the move-cost heuristic.

    A move costs ``vision_s`` (overhead image processing before it), driving at
    ``speed_in_per_s``, turning in place at ``turn_deg_per_s`` and ``centring_s`` (sonar
    centring on the object at the end).
    """

    speed_in_per_s: float
    turn_deg_per_s: float
    vision_s: float
    centring_s: float

    def __post_init__(self) -> None:
        if not self.speed_in_per_s > 0 or not self.turn_deg_per_s > 0:
            raise ValueError(
                f"move model needs positive speeds, got {self.speed_in_per_s} in/s and "
                f"{self.turn_deg_per_s} deg/s"
            )
        if self.vision_s < 0 or self.centring_s < 0:
            raise ValueError(
                f"move model needs non-negative overheads, got vision_s={self.vision_s} and "
                f"centring_s={self.centring_s}"
            )


@dataclass(frozen=True)
class RobotProfile:
    """The ``[robot]`` table split into body geometry and move timing."""

    geometry: RobotGeometry
    move: MoveModel


def load_robot_profile(path: str | Path) -> RobotProfile:
    """Read the ``[robot]`` table of a knowledge profile (e.g. ``hero2000.toml``)."""
    with open(path, "rb") as handle:
        document = tomllib.load(handle)
    table = document.get("robot")
    if not isinstance(table, dict):
        raise ValueError(f"{path}: no [robot] table")
    try:
        geometry = RobotGeometry(
            base_radius_in=float(table["base_radius_in"]),
            sensor_offset_in=float(table["sensor_offset_in"]),
            sensor_height_in=float(table.get("sensor_height_in", 0.0)),
        )
        move = MoveModel(
            speed_in_per_s=float(table["speed_in_per_s"]),
            turn_deg_per_s=float(table["turn_deg_per_s"]),
            vision_s=float(table["vision_s"]),
            centring_s=float(table["centring_s"]),
        )
    except KeyError as missing:
        raise ValueError(f"{path}: [robot] lacks {missing.args[0]}") from None
    return RobotProfile(geometry=geometry, move=move)
