"""The driver interface: what the executive may ask of a robot, simulated or real.

The executive holds a :class:`Driver` and nothing else of the robot. Two
implementations exist: the in-process simulator (``hero_driver.sim_driver``) and the
zenoh client (``hero_driver.zenoh_link.client``), which talks to any driver process
that serves the protocol in ``docs/driver-protocol.md``.

Every verb that takes robot time returns a :class:`concurrent.futures.Future` so that
behaviours can start the work in ``initialise`` and watch it in ``update`` without
blocking the tick. The in-process simulator returns futures that are already done
(keeping tick-by-tick traces deterministic); the zenoh client returns futures that
complete when the reply arrives. A failed call completes its future with a
:class:`DriverError`.

Units: inches, degrees (counter-clockwise from world +x), seconds of robot time.
Geometry conventions shared with the planner are in ``docs/conventions.md``.
"""

from __future__ import annotations

from collections.abc import Callable, Mapping, Sequence
from concurrent.futures import Future
from dataclasses import dataclass
from typing import Protocol, runtime_checkable

from camera_model.image import CameraImage

PROTOCOL_VERSION = 1

# Error codes a driver may answer with (docs/driver-protocol.md lists when).
BAD_REQUEST = "bad_request"  # malformed JSON, missing or mistyped field, wrong version
UNKNOWN_VERB = "unknown_verb"
UNKNOWN_PROCEDURE = "unknown_procedure"
OUT_OF_RANGE = "out_of_range"  # procedure refused: object not within its distance range
NO_TARGET = "no_target"  # nothing in front of the sonar to sense or grasp
BUSY = "busy"  # another verb is still executing
UNAVAILABLE = "unavailable"  # the driver is gone (client side) or not ready
TIMEOUT = "timeout"  # no reply within the client's deadline, or the driver cancelled a verb past its bound
INTERNAL = "internal"  # the driver failed; it keeps serving
BATTERY_EMPTY = "battery_empty"  # the battery feature: flat, nothing moves until it charges
NO_CAMERA = "no_camera"  # camera: the robot's world has no ceiling camera (a home; onboard perception only)
ERROR_CODES = frozenset(
    {BAD_REQUEST, UNKNOWN_VERB, UNKNOWN_PROCEDURE, OUT_OF_RANGE, NO_TARGET, BUSY,
     UNAVAILABLE, TIMEOUT, INTERNAL, BATTERY_EMPTY, NO_CAMERA}
)


class DriverError(Exception):
    """A verb the driver refused or could not carry out, with a protocol error code."""

    def __init__(self, code: str, message: str) -> None:
        super().__init__(f"{code}: {message}")
        self.code = code
        self.message = message


@dataclass(frozen=True)
class Pose:
    """The robot base's centre and heading in the world frame."""

    x_in: float
    y_in: float
    heading_deg: float


@dataclass(frozen=True)
class RobotState:
    """What the driver publishes on ``hero/<robot>/state``."""

    pose: Pose
    clock_s: float  # robot time spent since the last reset
    battery: float  # 0..1


@dataclass(frozen=True)
class Obstacle:
    """A moving obstacle (a person, a cart) that stopped a move: where it stood when the
    base stopped, and how far its outline reaches from there (the ``blocked_moves``
    feature, docs/driver-protocol.md "Moving obstacles")."""

    x_in: float
    y_in: float
    radius_in: float


@dataclass(frozen=True)
class MoveResult:
    """End of a move: where the base stopped and what the move cost.

    ``collided`` is true when the base stopped early on contact; ``pose`` is then where
    it stopped. ``centred`` is true when sonar centring found an object to face.
    ``blocked`` (the ``blocked_moves`` feature) is the moving obstacle the base stopped
    short of, ``pose`` then where it stopped; None when nothing was in the way.
    """

    pose: Pose
    duration_s: float
    collided: bool
    centred: bool
    blocked: Obstacle | None = None


@dataclass(frozen=True)
class SenseResult:
    """Feature values yielded by one sensing procedure (None: the sonar dropped out)."""

    procedure: str
    values: Mapping[str, float | None]
    duration_s: float
    distance_in: float  # sonar-to-object distance the procedure was applied at


@dataclass(frozen=True)
class GraspResult:
    """The finger infrared sensor's verdict: something is between the fingers."""

    procedure: str
    success: bool
    duration_s: float


@dataclass(frozen=True)
class RangeScan:
    """One planar range scan (the ``scan`` feature, docs/driver-protocol.md "Scans"):
    what the robot's own range sensor saw around it, for a robot with no ceiling camera.

    ``angles_deg`` are beam directions in the robot's frame, counter-clockwise from its
    heading (degrees, as every angle of the protocol), strictly increasing within
    [-180, 180); ``ranges_in[i]`` is how far from the base centre the beam at
    ``angles_deg[i]`` met something, within [``range_min_in``, ``range_max_in``], or
    ``inf`` when no echo came back within them. ``pose`` is where the driver says the
    robot stood (its reported pose, the frame of ``state().pose``: a drifting base's scan
    is taken at the truth and stamped with what its encoders say), ``clock_s`` the robot
    clock when the scan was taken, as the state publications carry it.
    """

    pose: Pose
    clock_s: float
    angles_deg: tuple[float, ...]
    ranges_in: tuple[float, ...]
    range_min_in: float
    range_max_in: float


@dataclass(frozen=True)
class Hello:
    """What a driver process serves: the protocol versions it speaks and the optional
    features it offers (the ``hello`` verb's answer, docs/driver-protocol.md).

    The driver node answers it, not the robot: versions and features are properties
    of the protocol a process serves, so in-process drivers have no ``hello``.
    """

    versions: tuple[int, ...]
    features: tuple[str, ...] = ()


@runtime_checkable
class Driver(Protocol):
    """A robot the executive can drive: the simulated HERO or a hardware driver."""

    robot: str

    def state(self) -> RobotState:
        """The latest known state (cheap; no robot time)."""
        ...

    def move(self, waypoints: Sequence[Pose], face: tuple[float, float] | None = None) -> Future[MoveResult]:
        """Follow ``waypoints`` (world poses; the last is the goal), then turn to
        ``face`` (a world point, usually the object's centroid) and centre on the
        object there with the sonar."""
        ...

    def sense(self, procedure: str) -> Future[SenseResult]:
        """Apply a sensing procedure to the object in front of the sonar."""
        ...

    def grasp(self, procedure: str) -> Future[GraspResult]:
        """Apply a grasping procedure to the object in front of the hand. A successful
        grasp lifts the object off the floor; ``release`` puts it down and away."""
        ...

    def release(self) -> Future[RobotState]:
        """Put a held object away (into the robot's bin); no-op when the hand is empty."""
        ...

    def camera(self) -> Future[CameraImage]:
        """Take an overhead image."""
        ...

    def reset(self, world: str | None = None, seed: int | None = None) -> Future[RobotState]:
        """Restore a world (a world-file name or path; None: the current one) and seed."""
        ...

    def close(self) -> None:
        """Release the driver's resources; further calls fail with ``unavailable``."""
        ...


@runtime_checkable
class Charger(Protocol):
    """A driver with the optional ``battery`` feature: it names its charging dock and
    can charge there. A driver without it still works; the executive's low-battery
    guard is then off."""

    def dock(self) -> Pose | None:
        """Where the base charges, in the frame of ``state().pose`` (None: no dock here)."""
        ...

    def charge(self) -> Future[RobotState]:
        """With the base at the dock, charge until full and answer the new state;
        ``out_of_range`` anywhere else."""
        ...


@runtime_checkable
class BlockedMoves(Protocol):
    """A driver with the optional ``blocked_moves`` feature: a move stops short of a
    moving obstacle that comes within its safety distance ahead and answers it in
    ``MoveResult.blocked``; the robot can wait in place for one to pass. A driver
    without it still works; the executive's blocked-move branch is then off."""

    def safety_in(self) -> float | None:
        """How near ahead a moving obstacle stops a move (None: the feature is off here)."""
        ...

    def wait(self, seconds: float) -> Future[RobotState]:
        """Stand still for ``seconds`` of robot time and answer the state after it."""
        ...


@runtime_checkable
class Scanner(Protocol):
    """A driver with the optional ``scan`` feature: a planar range sensor on the robot
    (a 2-D lidar, or the wrist sonar swept in place), for finding its way and the
    objects without the ceiling camera. A driver without it still works; nothing that
    needs scans is then offered."""

    def scan(self) -> Future[RangeScan]:
        """Take one planar range scan where the robot stands (it does not move) and
        answer it with the pose it was taken from."""
        ...


# -- the verb table ------------------------------------------------------------------------


@dataclass(frozen=True)
class DriverVerb:
    """One method a driver offers, as every driver decorator needs to know it
    (:class:`hero_driver.decorator.DriverDecorator`): busy-retry, the camera's frame and
    recording each read this row instead of listing the verbs by hand.

    ``args`` names the method's arguments in order; ``poses_in`` those that carry world
    positions (a :class:`Pose`, an ``(x, y)`` point, or a sequence of them) and
    ``poses_out`` the result's fields that do (``""``: the result itself is one).
    ``robot_time``: the verb takes the robot's time and answers with a future that may
    fail as ``busy`` (every one of them is a zenoh verb, ``hero_driver.zenoh_link.verbs``);
    else it is answered at once from what the driver knows (``state``, ``dock``), or is
    the driver's own housekeeping (``close``). ``feature`` is the optional feature that
    brings it (None: the :class:`Driver` protocol's own).
    """

    name: str
    result: type | None
    args: tuple[str, ...] = ()
    poses_in: tuple[str, ...] = ()
    poses_out: tuple[str, ...] = ()
    robot_time: bool = True
    feature: str | None = None


DRIVER_VERBS: tuple[DriverVerb, ...] = (
    DriverVerb("state", RobotState, poses_out=("pose",), robot_time=False),
    DriverVerb("move", MoveResult, ("waypoints", "face"), poses_in=("waypoints", "face"),
               poses_out=("pose", "blocked")),
    DriverVerb("sense", SenseResult, ("procedure",)),
    DriverVerb("grasp", GraspResult, ("procedure",)),
    DriverVerb("release", RobotState, poses_out=("pose",)),
    DriverVerb("camera", CameraImage),
    DriverVerb("reset", RobotState, ("world", "seed"), poses_out=("pose",)),
    DriverVerb("close", None, robot_time=False),
    DriverVerb("dock", Pose, poses_out=("",), robot_time=False, feature="battery"),
    DriverVerb("charge", RobotState, poses_out=("pose",), feature="battery"),
    DriverVerb("safety_in", float, robot_time=False, feature="blocked_moves"),
    DriverVerb("wait", RobotState, ("seconds",), poses_out=("pose",), feature="blocked_moves"),
    DriverVerb("scan", RangeScan, poses_out=("pose",), feature="scan"),
)
"""Every method of :class:`Driver`, :class:`Charger`, :class:`BlockedMoves` and :class:`Scanner`, one row
each (``tests/hero_driver/test_driver_verbs.py`` holds the protocols to it)."""

VERB_BY_NAME: dict[str, DriverVerb] = {verb.name: verb for verb in DRIVER_VERBS}
PROTOCOLS: Mapping[str | None, type] = {None: Driver, "battery": Charger, "blocked_moves": BlockedMoves,
                                         "scan": Scanner}
"""The protocol that declares a row's method, by the row's ``feature``."""


def protocol_method(verb: DriverVerb) -> Callable[..., object]:
    """The protocol's declaration of ``verb``: its signature and its docstring."""
    return getattr(PROTOCOLS[verb.feature], verb.name)
