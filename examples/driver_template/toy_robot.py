"""A toy backend: a robot of the knowledge profile's size and speeds on an empty floor
with one box, all in memory.

It lets the template run, and pass ``csl driver check``, before any hardware is
wired: the geometry is honest (a disc base that stops on contact, a sonar ray cast
to the box, ranges with the 1.5 in tolerance, a camera image drawn in the grey bands)
but the box's features are computed from its size, not measured, by a model that
knows the HERO 2000's procedure names. Procedure times and ranges and the [robot]
constants come from the profile (knowledge.py), the same file whose fingerprint
``hello`` sends. Moves take real time (``time_scale`` real seconds per robot second),
as a real base does, so a second verb sent during one is refused ``busy``.
"""

from __future__ import annotations

import math
import threading
import time
from dataclasses import dataclass

import numpy as np

import overhead
from knowledge import Knowledge, Procedure
from robot import (
    BAD_REQUEST,
    NO_TARGET,
    OUT_OF_RANGE,
    RANGE_TOLERANCE_IN,
    UNKNOWN_PROCEDURE,
    GraspResult,
    Image,
    MoveResult,
    Pose,
    RobotError,
    RobotState,
    SenseResult,
)

ROOM_IN = (144.0, 120.0)  # floor, x by y, walls all round
WALL_IN = 2.0
INCHES_PER_PIXEL = 0.8
START = Pose(30.0, 60.0, 0.0)
STEP_S = 0.1  # robot seconds per motion step: odometry updates this often


@dataclass(frozen=True)
class Box:
    """The one object: a box of ``length`` along ``angle_deg`` and ``width`` across."""

    x_in: float = 100.0
    y_in: float = 60.0
    length_in: float = 6.0
    width_in: float = 10.0
    height_in: float = 8.0
    angle_deg: float = 0.0


LIFTS_THE_BOX = {"Front-Wrap", "Top-Hor-Grip"}  # the grasps that hold a 10 in wide box


def _wrap(deg: float) -> float:
    return deg % 360.0


def _turn(from_deg: float, to_deg: float) -> float:
    """The signed shortest turn, degrees."""
    return (to_deg - from_deg + 180.0) % 360.0 - 180.0


class ToyRobot:
    """The robot and its world; every verb is thread-safe against ``state()``."""

    def __init__(self, knowledge: Knowledge, time_scale: float = 0.1) -> None:
        self.knowledge = knowledge
        self.robot = knowledge.robot  # the [robot] constants: base size, sonar placement, speeds
        self.radius_in = self.robot["base_radius_in"]
        self.time_scale = time_scale
        self._lock = threading.Lock()
        self._pose = START
        self._clock_s = 0.0
        self._box: Box | None = Box()
        self._held: Box | None = None

    # ----------------------------------------------------------------- the world

    def _blocked(self, x: float, y: float) -> bool:
        """Would the base disc at (x, y) touch a wall or the box?"""
        w, h = ROOM_IN
        if not (WALL_IN + self.radius_in <= x <= w - WALL_IN - self.radius_in
                and WALL_IN + self.radius_in <= y <= h - WALL_IN - self.radius_in):
            return True
        box = self._box
        if box is None:
            return False
        a = math.radians(box.angle_deg)
        along = (x - box.x_in) * math.cos(a) + (y - box.y_in) * math.sin(a)
        across = -(x - box.x_in) * math.sin(a) + (y - box.y_in) * math.cos(a)
        dx = max(abs(along) - box.length_in / 2, 0.0)
        dy = max(abs(across) - box.width_in / 2, 0.0)
        return math.hypot(dx, dy) < self.radius_in

    def _sonar(self, pose: Pose) -> tuple[float, float]:
        h = math.radians(pose.heading_deg)
        offset = self.robot["sensor_offset_in"]
        return pose.x_in + offset * math.cos(h), pose.y_in + offset * math.sin(h)

    def _distance_ahead(self, pose: Pose) -> float | None:
        """Sonar to the box's surface straight ahead (slab test in the box frame), or None."""
        box = self._box
        if box is None:
            return None
        sx, sy = self._sonar(pose)
        a, h = math.radians(box.angle_deg), math.radians(pose.heading_deg)
        origin = ((sx - box.x_in) * math.cos(a) + (sy - box.y_in) * math.sin(a),
                  -(sx - box.x_in) * math.sin(a) + (sy - box.y_in) * math.cos(a))
        direction = (math.cos(h - a), math.sin(h - a))
        near, far = 0.0, math.inf
        for o, d, half in zip(origin, direction, (box.length_in / 2, box.width_in / 2)):
            if abs(d) < 1e-12:
                if abs(o) > half:
                    return None
                continue
            t1, t2 = sorted(((-half - o) / d, (half - o) / d))
            near, far = max(near, t1), min(far, t2)
        return near if near <= far else None

    def _in_range(self, procedure: Procedure, name: str) -> float:
        distance = self._distance_ahead(self._pose)
        if distance is None:
            raise RobotError(NO_TARGET, f"{name}: nothing in front of the sonar")
        lo, hi = procedure.range_in
        if not lo - RANGE_TOLERANCE_IN <= distance <= hi + RANGE_TOLERANCE_IN:
            raise RobotError(OUT_OF_RANGE, f"{name}: the object is {distance:.1f} in away, range is {lo:g}-{hi:g} in")
        return distance

    def _spend(self, seconds: float) -> None:
        """Robot time passes; a move also takes real time (the caller sleeps)."""
        self._clock_s += seconds

    # -------------------------------------------------------------------- verbs

    def state(self) -> RobotState:
        with self._lock:
            return RobotState(self._pose, self._clock_s, max(0.0, 1.0 - self._clock_s / 36000.0))

    def move(self, waypoints: list[Pose], face: tuple[float, float] | None) -> MoveResult:
        start = self._clock_s
        for goal in waypoints:
            here = self._pose
            length = math.hypot(goal.x_in - here.x_in, goal.y_in - here.y_in)
            if length > 1e-6:
                self._turn_to(math.degrees(math.atan2(goal.y_in - here.y_in, goal.x_in - here.x_in)))
                if not self._drive(goal.x_in, goal.y_in):
                    return MoveResult(self._pose, self._clock_s - start, True, False)
            self._turn_to(goal.heading_deg)
        centred = False
        if face is not None:
            here = self._pose
            self._turn_to(math.degrees(math.atan2(face[1] - here.y_in, face[0] - here.x_in)))
            distance = self._distance_ahead(self._pose)
            if distance is not None and math.dist(self._sonar(self._pose), face) <= distance + self.radius_in:
                centred = True
                self._step(self.robot["centring_s"], self._pose)
        return MoveResult(self._pose, self._clock_s - start, False, centred)

    def _step(self, seconds: float, pose: Pose) -> None:
        time.sleep(seconds * self.time_scale)
        with self._lock:
            self._pose = pose
            self._spend(seconds)

    def _turn_to(self, heading_deg: float) -> None:
        here = self._pose
        turn = _turn(here.heading_deg, heading_deg)
        steps = max(1, math.ceil(abs(turn) / self.robot["turn_deg_per_s"] / STEP_S))
        for i in range(1, steps + 1):
            self._step(abs(turn) / self.robot["turn_deg_per_s"] / steps,
                       Pose(here.x_in, here.y_in, _wrap(here.heading_deg + turn * i / steps)))

    def _drive(self, x: float, y: float) -> bool:
        """Straight to (x, y); False when the base touched something first."""
        here = self._pose
        length = math.hypot(x - here.x_in, y - here.y_in)
        steps = max(1, math.ceil(length / self.robot["speed_in_per_s"] / STEP_S))
        for i in range(1, steps + 1):
            nx = here.x_in + (x - here.x_in) * i / steps
            ny = here.y_in + (y - here.y_in) * i / steps
            if self._blocked(nx, ny):
                return False
            self._step(length / self.robot["speed_in_per_s"] / steps, Pose(nx, ny, here.heading_deg))
        return True

    def sense(self, procedure: str) -> SenseResult:
        spec = self.knowledge.sensing.get(procedure)
        if spec is None:
            raise RobotError(UNKNOWN_PROCEDURE, f"{procedure!r} is not a sensing procedure of this robot")
        d = self._in_range(spec, procedure)
        box = self._box
        assert box is not None  # _in_range found it
        values: dict[str, float | None]
        if procedure.startswith("H-Sweep"):
            values = {f"Width-Degree-{procedure[-2:]}": math.degrees(2 * math.atan2(box.width_in / 2, d))}
        elif procedure.startswith("V-Sweep"):
            sonar = self.robot["sensor_height_in"]
            values = {f"Height-Degree-{procedure[-2:]}": math.degrees(
                math.atan2(box.height_in - sonar, d) + math.atan2(sonar, d))}
        elif procedure == "S-Sweep-1°":
            values = {"Depth-Degree-1°": math.degrees(
                math.atan2(box.length_in, max(self.robot["raised_sensor_height_in"] - box.height_in, 1.0)))}
        elif procedure == "H-Scan-0.3":
            values = {"Width": box.width_in, "Front-Hole?": 0.0}
        else:
            values = {"Height": box.height_in, "Depth": box.length_in, "Top-Hole?": 0.0}
        with self._lock:
            self._spend(spec.time_s)
        return SenseResult(procedure, values, spec.time_s, d)

    def grasp(self, procedure: str) -> GraspResult:
        spec = self.knowledge.grasping.get(procedure)
        if spec is None:
            raise RobotError(UNKNOWN_PROCEDURE, f"{procedure!r} is not a grasping procedure of this robot")
        if self._held is not None:
            raise RobotError(BAD_REQUEST, f"{procedure}: the hand already holds an object")
        self._in_range(spec, procedure)
        lifted = procedure in LIFTS_THE_BOX
        with self._lock:
            self._spend(spec.time_s)
            if lifted:
                self._held, self._box = self._box, None
        return GraspResult(procedure, lifted, spec.time_s)

    def release(self) -> RobotState:
        with self._lock:
            self._held = None  # put away: off the floor until the next reset
        return self.state()

    def camera(self) -> Image:
        with self._lock:
            pose, box, clock = self._pose, self._box, self._clock_s
        width, height = (round(side / INCHES_PER_PIXEL) for side in ROOM_IN)
        x, y = overhead.pixel_centres(height, width, INCHES_PER_PIXEL, 0.0, ROOM_IN[1])
        pixels = np.full((height, width), overhead.FLOOR, np.uint8)
        inside = (x > WALL_IN) & (x < ROOM_IN[0] - WALL_IN) & (y > WALL_IN) & (y < ROOM_IN[1] - WALL_IN)
        pixels[~inside] = overhead.FURNITURE
        if box is not None:
            pixels[overhead.rectangle(x, y, box.x_in, box.y_in, box.length_in, box.width_in,
                                      box.angle_deg)] = overhead.OBJECT
        pixels[overhead.disc(x, y, pose.x_in, pose.y_in, self.radius_in)] = overhead.BASE
        h = math.radians(pose.heading_deg)
        ahead = 2 / 3 * self.radius_in
        pixels[overhead.disc(x, y, pose.x_in + ahead * math.cos(h), pose.y_in + ahead * math.sin(h),
                             self.radius_in / 4)] = overhead.MARKER
        return Image(pixels, INCHES_PER_PIXEL, 0.0, ROOM_IN[1], clock, {"backend": "toy"})

    def reset(self, world: str | None, seed: int | None) -> RobotState:
        if world is not None:
            raise RobotError(BAD_REQUEST, f"world: the toy robot has one world, cannot restore {world!r}")
        with self._lock:
            self._pose, self._clock_s, self._box, self._held = START, 0.0, Box(), None
        return self.state()
