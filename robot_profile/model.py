"""The robot profile as typed values: what one TOML file says about one robot.

Every field is validated by :mod:`robot_profile.reader` before these are built, so a
consumer never re-checks a profile; the two ``[robot]`` parts also check themselves,
because the planner's tests and tools build them by hand.

The procedures and the ``[move]`` model are the learner's own types
(:mod:`learner.knowledge`), which the reader builds directly: one definition, no
translation (the package docstring says why the learner owns them).

The ``[robot]`` keys are the fields of :class:`RobotGeometry` and :class:`RobotMotion`:
the reader reads each field as a non-negative number, or one greater than 0 when its
metadata is :data:`POSITIVE`, so a new constant is one field here and one line in the
profile file (docs/conventions.md, "Adding a robot constant").
"""

from __future__ import annotations

from dataclasses import dataclass, field, fields

from learner.knowledge import GraspingProcedure, Knowledge, MoveModel, SensingProcedure

POSITIVE = {"positive": True}  # field metadata: the reader refuses 0 (sizes, and what costs divide by)


def _check_constants(part: object, what: str) -> None:
    """A hand-built ``[robot]`` part holds to the reader's rule, read from the same
    metadata: each field > 0 when :data:`POSITIVE`, else >= 0."""
    wrong = []
    for f in fields(part):
        value, positive = getattr(part, f.name), f.metadata.get("positive", False)
        if not (value > 0 if positive else value >= 0):
            wrong.append(f"{f.name} {'> 0' if positive else '>= 0'} (got {value})")
    if wrong:
        raise ValueError(f"{what} needs {', '.join(wrong)}")


@dataclass(frozen=True)
class RobotGeometry:
    """Where the robot's body and sonar are, relative to its pose (docs/conventions.md).

    ``base_radius_in`` inflates the vision map and stops the simulated base;
    ``sensor_offset_in`` places the base behind the sonar.
    """

    base_radius_in: float = field(metadata=POSITIVE)
    sensor_offset_in: float
    sensor_height_in: float
    raised_sensor_height_in: float = field(metadata=POSITIVE)

    def __post_init__(self) -> None:
        _check_constants(self, "robot geometry")


@dataclass(frozen=True)
class RobotMotion:
    """How long the base takes to move: the terms of the planner's move-cost heuristic
    and of the simulator's clock.

    A move costs ``vision_s`` (overhead image processing before it), driving at
    ``speed_in_per_s``, turning in place at ``turn_deg_per_s`` and ``centring_s`` (sonar
    centring on the object at the end).
    """

    speed_in_per_s: float = field(metadata=POSITIVE)
    turn_deg_per_s: float = field(metadata=POSITIVE)
    vision_s: float
    centring_s: float

    def __post_init__(self) -> None:
        _check_constants(self, "move model")


@dataclass(frozen=True)
class Robot:
    """The ``[robot]`` table, split into body geometry and move timing."""

    geometry: RobotGeometry
    motion: RobotMotion


@dataclass(frozen=True)
class RobotProfile:
    """A whole profile file; ``source`` names it in messages."""

    robot: Robot
    move: MoveModel
    sensing: tuple[SensingProcedure, ...]
    grasping: tuple[GraspingProcedure, ...]
    source: str

    def sensing_procedure(self, name: str) -> SensingProcedure | None:
        """The sensing procedure called ``name``, or None: a driver refuses unknown names."""
        return next((p for p in self.sensing if p.name == name), None)

    def grasping_procedure(self, name: str) -> GraspingProcedure | None:
        """The grasping procedure called ``name``, or None."""
        return next((g for g in self.grasping if g.name == name), None)

    @property
    def grasp_names(self) -> tuple[str, ...]:
        return tuple(g.name for g in self.grasping)

    def knowledge(self) -> Knowledge:
        """The learner's part of the profile: its procedures and ``[move]`` model, already
        in the learner's own types, so nothing is translated; ``[robot]`` stays out."""
        return Knowledge(sensing=self.sensing, grasping=self.grasping, move=self.move, source=self.source)
