"""What a robot backend must do, and the hardware backend a vendor fills in.

driver.py owns everything protocol-shaped (zenoh keys, JSON, busy, state
publications, liveliness); a backend only moves, senses, grasps and takes pictures.
Every method is called by one verb at a time except ``state()``, which the 5 Hz
publisher calls from its own thread while a verb runs: keep it quick and thread-safe.

Units: inches, degrees counter-clockwise from world +x, seconds of robot time
(docs/conventions.md). Refuse what the robot cannot do with ``RobotError(code, ...)``
using the protocol's codes (docs/driver-protocol.md, "Error codes").
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Protocol

import numpy as np

BAD_REQUEST = "bad_request"
UNKNOWN_PROCEDURE = "unknown_procedure"
OUT_OF_RANGE = "out_of_range"
NO_TARGET = "no_target"
BUSY = "busy"
INTERNAL = "internal"
UNKNOWN_VERB = "unknown_verb"

RANGE_TOLERANCE_IN = 1.5  # a procedure runs when lo - 1.5 <= distance <= hi + 1.5


class RobotError(Exception):
    """A verb the robot refuses: a protocol error code and one line for people."""

    def __init__(self, code: str, message: str) -> None:
        super().__init__(f"{code}: {message}")
        self.code = code
        self.message = message


@dataclass(frozen=True)
class Pose:
    x_in: float
    y_in: float
    heading_deg: float


@dataclass(frozen=True)
class RobotState:
    pose: Pose  # the driver's own estimate (odometry)
    clock_s: float  # robot time since the last reset
    battery: float  # charge left, 0..1


@dataclass(frozen=True)
class MoveResult:
    pose: Pose  # where the base stopped
    duration_s: float
    collided: bool  # stopped early on contact
    centred: bool  # sonar centring found an object at the face point


@dataclass(frozen=True)
class SenseResult:
    procedure: str
    values: dict[str, float | None]  # feature name -> value, None when the sonar dropped out
    duration_s: float
    distance_in: float  # sonar to object surface when applied


@dataclass(frozen=True)
class GraspResult:
    procedure: str
    success: bool  # the finger infrared sensor sees the object between the fingers
    duration_s: float


@dataclass(frozen=True)
class Image:
    """An overhead image already in the protocol's grey bands and mapping: row 0 at the
    room's high-y edge, pixel (row, col)'s centre at
    ``(origin_x_in + (col + 0.5) * s, origin_y_in - (row + 0.5) * s)``."""

    pixels: np.ndarray  # H x W uint8
    inches_per_pixel: float
    origin_x_in: float
    origin_y_in: float
    clock_s: float
    meta: dict = field(default_factory=dict)


class Robot(Protocol):
    """The backend driver.py serves: the toy one (toy_robot.py) or the hardware one."""

    def state(self) -> RobotState: ...

    def move(self, waypoints: list[Pose], face: tuple[float, float] | None) -> MoveResult: ...

    def sense(self, procedure: str) -> SenseResult: ...

    def grasp(self, procedure: str) -> GraspResult: ...

    def release(self) -> RobotState: ...

    def camera(self) -> Image: ...

    def reset(self, world: str | None, seed: int | None) -> RobotState: ...


class HardwareRobot:
    """The real robot. Every method is a stub to replace with calls to your hardware;
    until then each verb answers ``internal`` naming the stub, and ``csl driver check``
    shows which are left. Keep the signatures and the units; docs/vendor-guide.md says
    what each must deliver."""

    def __init__(self) -> None:
        # VENDOR: open your controller here (serial port, CAN bus, vendor SDK), home the
        # base if it can, and start odometry.
        pass

    def state(self) -> RobotState:
        # VENDOR: return the latest odometry pose, the robot time since the last reset
        # and the battery charge (0..1). Called at 5 Hz from another thread: no blocking I/O.
        raise NotImplementedError("VENDOR: state() is not implemented")

    def move(self, waypoints: list[Pose], face: tuple[float, float] | None) -> MoveResult:
        # VENDOR: drive through each waypoint (the last is the goal), stop early on a
        # bumper contact (collided=True, pose where it stopped); with `face`, turn to
        # that world point and centre the sonar on the object there (centred=True when
        # one was found). Block until the base has stopped.
        raise NotImplementedError("VENDOR: move() is not implemented")

    def sense(self, procedure: str) -> SenseResult:
        # VENDOR: run the sensing procedure named in your knowledge profile. Measure
        # the distance d to the first surface straight ahead of the sonar: none ->
        # RobotError(NO_TARGET); outside [lo - 1.5, hi + 1.5] of its range_in ->
        # RobotError(OUT_OF_RANGE); an unknown name -> RobotError(UNKNOWN_PROCEDURE).
        # Return every feature the procedure yields (None where the sonar dropped out).
        raise NotImplementedError("VENDOR: sense() is not implemented")

    def grasp(self, procedure: str) -> GraspResult:
        # VENDOR: as sense() for the range and the codes; refuse with BAD_REQUEST while
        # the hand already holds something. success = the finger sensor sees the object.
        raise NotImplementedError("VENDOR: grasp() is not implemented")

    def release(self) -> RobotState:
        # VENDOR: put a held object away (nothing to do with an empty hand).
        raise NotImplementedError("VENDOR: release() is not implemented")

    def camera(self) -> Image:
        # VENDOR: grab the overhead camera frame, undistort it (or send camera_matrix
        # and fisheye), flip it so row 0 is the room's high-y edge, and segment it into
        # the grey bands (floor 30, furniture 110, base 170, heading marker 250,
        # objects 220): overhead.py has the bands and the pixel mapping.
        raise NotImplementedError("VENDOR: camera() is not implemented")

    def reset(self, world: str | None, seed: int | None) -> RobotState:
        # VENDOR: reset the robot clock to 0 and re-home if the robot can; a `world`
        # you cannot restore -> RobotError(BAD_REQUEST). `seed` can be ignored.
        raise NotImplementedError("VENDOR: reset() is not implemented")
