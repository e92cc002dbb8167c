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

from collections.abc import Mapping
from dataclasses import dataclass, field, fields
from types import MappingProxyType

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


SCANNER_MODELS = ("lidar", "sonar")


@dataclass(frozen=True)
class ScannerSpec:
    """The ``[scanner]`` table: the robot's planar range sensor, which the simulator
    serves as the ``scan`` feature (docs/simulator.md, "Scans").

    ``model`` is ``lidar`` (a 2-D laser scanner over the base centre) or ``sonar`` (the
    wrist sonar swept in place by the base turning a full circle under it, the
    1991-faithful option); the rest defaults to the model's values
    (:data:`SCANNER_DEFAULTS`). ``beams`` directions spread evenly over a full turn;
    ranges within ``range_in`` (from the base centre); ``beam_deg`` is how wide one
    beam is (0: a thin ray; wider: the nearest echo within the cone); beyond
    ``specular_deg`` off a surface's normal the echo may be reflected away; objects
    lower than ``height_in`` lie under the scan plane; ``through_glass``: light passes
    glass, sound does not; ``time_s`` is the robot time one scan takes.
    """

    model: str
    beams: int
    range_in: tuple[float, float]
    beam_deg: float
    specular_deg: float
    height_in: float
    through_glass: bool
    time_s: float

    def __post_init__(self) -> None:
        lo, hi = self.range_in
        if (self.model not in SCANNER_MODELS or self.beams < 1 or not 0 <= lo < hi
                or not 0 <= self.beam_deg < 180 or not 0 <= self.specular_deg <= 90
                or self.height_in < 0 or self.time_s < 0):
            raise ValueError(f"scanner needs a model of {', '.join(SCANNER_MODELS)}, beams >= 1, "
                             f"0 <= range low < high, 0 <= beam_deg < 180, 0 <= specular_deg <= 90, "
                             f"height_in and time_s >= 0 (got {self})")

    @property
    def step_deg(self) -> float:
        """The angle between neighbouring beams."""
        return 360.0 / self.beams


SCANNER_DEFAULTS: Mapping[str, Mapping[str, object]] = MappingProxyType({
    # A hobby-grade 2-D lidar low on the base: a beam per degree, half an inch to 40 ft,
    # a thin ray that loses only near-grazing returns, one revolution in a fifth of a second.
    "lidar": {"beams": 360, "range_in": (0.5, 480.0), "beam_deg": 0.0, "specular_deg": 80.0,
              "height_in": 1.5, "through_glass": True, "time_s": 0.2},
    # The HERO's wrist sonar swept in place: a ping every 15 degrees, a beam about 30
    # degrees wide (the Polaroid-style transducer of docs/simulator.md's specular effect,
    # mirrored beyond half of it), heard from about a foot (its ringing and the base's
    # edge) to the sensing procedures' 127 in; the base turns a full circle at 5 deg/s.
    "sonar": {"beams": 24, "range_in": (12.0, 127.0), "beam_deg": 30.0, "specular_deg": 15.0,
              "height_in": 0.0, "through_glass": False, "time_s": 90.0},
})
"""Each model's values, which a profile's ``[scanner]`` table may override key by key."""


@dataclass(frozen=True)
class RobotProfile:
    """A whole profile file; ``source`` names it in messages."""

    robot: Robot
    move: MoveModel
    sensing: tuple[SensingProcedure, ...]
    grasping: tuple[GraspingProcedure, ...]
    source: str
    scanner: ScannerSpec | None = None  # the [scanner] table; None: the profile has none

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
