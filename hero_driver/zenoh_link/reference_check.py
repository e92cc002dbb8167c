"""Conformance on a physical reference: what the robot senses and grasps, checked
against objects an operator placed on the floor.

A real robot cannot restore the simulated ``lab`` (the vendor guide tells it to
refuse), so there the suite's ``sense`` and ``grasp`` checks meet nothing in front of
the sonar and pass on ``no_target``: a sonar that reads centimetres, a finger sensor
stuck at "held" or a world model with objects' yaw the other way round would all pass.
Here the suite asks for named catalogue objects anywhere on the floor, finds them
with the camera (matched by footprint size and shape), drives to the shipped
library's training positions around them (:func:`planner.positions.pose_for_position`,
the executive's own conversion) and holds every value against the library's value
for that object and position within ERROR_FACTOR times the profile's expected error.
It senses one feature twice in a row from positions whose library values differ
widely (a stale or stuck reading repeats itself), grasps one object with its correct
grasp and looks that it left the floor, and tries a wrong grasp on another, which
must fail.

The robot only drives straight segments: away from the object it stands at, round
it on a ring that clears it, and straight in to the next position; every position is
checked against the objects the camera sees before the robot first moves, and every
segment before it is driven, so the operator is told to leave the rest of the floor
clear. Before each move the driver's dead reckoning is corrected by where the camera
sees the robot, as the executive corrects it. Each named check returns a detail or
raises :class:`~hero_driver.zenoh_link.checking.CheckFailed`.
"""

from __future__ import annotations

import json
import math
import time
from collections.abc import Callable, Sequence
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from hero_driver.interface import DriverError, GraspResult, MoveResult, Pose, SenseResult
from hero_driver.sim.catalogue import CatalogueEntry, load_catalogue
from hero_driver.zenoh_link.camera_check import CENTRE_TOLERANCE_IN
from hero_driver.zenoh_link.checking import CheckFailed, CheckResult, Probe, valid_states
from planner.geometry import Pose as PlannerPose
from planner.positions import beam_blockers, pose_for_position
from planner.segmentation import Camera
from planner.vision import Region, Scene, look
from robot_profile import RobotProfile

LIBRARY = Path(__file__).resolve().parents[1] / "profiles" / "hero2000-library.json"
"""The shipped library whose descriptions are the expected values."""
DEFAULT_OBJECTS = ("closed-box-11x9x12/upright", "soda-can-12oz/upright")
"""The reference asked for by default: a box whose values depend on the side the sonar
faces (it shows an object's yaw drawn the other way round) and a can that one grasp
lifts; both described by the shipped library, of clearly different sizes."""
REFERENCE_WORLD = "reference"  # hero_driver/worlds/reference.json: the default objects, for a simulator to restore
ERROR_FACTOR = 3.0  # a value passes within this many expected errors of the library's
READINGS = 3  # a value off its library value is read again, up to this many times; most must pass
DISTANCE_TOLERANCE_IN = 3.0  # the sense reply's distance_in vs the distance the camera puts the object at
AREA_RATIO = 2.0  # a region is an object's when its area is within this factor of the footprint's ...
ELONGATION_RATIO = 1.5  # ... and its elongation within this factor
STALE_SHARE = 0.5  # two readings from positions whose library values differ by D must differ by this share of D
STALE_ATTEMPTS = 2  # ... in one of this many tries of the pair
RING_MARGIN_IN = 3.0  # the ring the robot drives round an object clears it by this much
ARC_STEP_DEG = 30.0  # ... in straight chords of at most this angle
EDGE_MARGIN_IN = 3.0  # the base stays this far inside the floor the camera sees
LOCALISE_DEADBAND_IN = 0.5  # as the executive's (behaviours/localisation.py DEADBAND_IN)
SIDE_STEP_DEG = 30.0  # a side tried for a position of any orientation ("*"), turning from the floor's middle
NOT_CHECKED = "sensing and grasping NOT checked: run with --reference"
NOT_PLACED = "sensing and grasping NOT checked: the reference objects were not placed"


@dataclass(frozen=True)
class Expected:
    """One value of the library: ``feature`` from ``procedure`` at a training position
    (``orientation_deg`` None: any side), with the profile's expected error."""

    feature: str
    procedure: str
    distance_in: float
    orientation_deg: float | None
    value: float
    error: float
    unit: str

    @property
    def tolerance(self) -> float:
        return ERROR_FACTOR * self.error


@dataclass(frozen=True)
class ReferenceObject:
    """A catalogue object with its library description, as the check uses it."""

    id: str
    area_in2: float  # the catalogue footprint's
    elongation: float  # length over width (1 for a circle)
    expected: tuple[Expected, ...]
    grasp: str  # the library's grasp
    grasp_position: tuple[float, float | None]
    correct_grasps: frozenset[str]  # every grasp the catalogue says lifts it
    liftable: bool  # its grasp is one the finger sensor confirms

    def fits(self, region: Region) -> bool:
        """Whether the camera's ``region`` has this object's footprint size and shape."""
        area = region.area_in2 or 0.0
        elongation = region.elongation or 1.0
        return (self.area_in2 / AREA_RATIO <= area <= self.area_in2 * AREA_RATIO
                and self.elongation / ELONGATION_RATIO <= elongation <= self.elongation * ELONGATION_RATIO)


@dataclass(frozen=True)
class Reference:
    """What the reference checks are given: the objects, the robot's profile, whether
    ``--reference`` asked for them (``always``: run them even on a driver that restores
    ``lab``), how the operator is asked to place them (None: already placed, the
    ``--placed`` flag) and the camera's calibration (None: band images)."""

    objects: tuple[ReferenceObject, ...]
    profile: RobotProfile
    always: bool = True
    ask: Callable[[str], bool] | None = None
    camera: Camera | None = None


def reference_objects(ids: Sequence[str], profile: RobotProfile, library: Path = LIBRARY) -> tuple[ReferenceObject, ...]:
    """The reference objects named by ``ids``; ValueError in one line naming the id that
    is not in the catalogue or the library, or two that the camera cannot tell apart."""
    if len(set(ids)) != len(ids) or len(ids) < 2:
        raise ValueError(f"expected at least two different catalogue ids, got {','.join(ids) or 'none'}")
    catalogue = load_catalogue(profile.grasp_names, None)
    descriptions = _descriptions(library)
    objects = []
    for name in ids:
        if name not in catalogue:
            raise ValueError(f"{name}: not in the object catalogue (hero_driver/worlds/catalogue.json)")
        if name not in descriptions:
            known = ", ".join(sorted(i for i in descriptions if i in catalogue))
            raise ValueError(f"{name}: the library {library.name} has no description of it, so nothing to compare "
                             f"its values with (described: {known})")
        objects.append(_reference_object(catalogue[name], descriptions[name], profile, library))
    for i, a in enumerate(objects):
        for b in objects[i + 1:]:
            if _alike(a, b):
                raise ValueError(f"{a.id} and {b.id} cannot be told apart by the camera (footprints of "
                                 f"{a.area_in2:.1f} and {b.area_in2:.1f} sq in): choose objects of clearly different "
                                 "sizes")
    if not any(o.liftable for o in objects):
        raise ValueError(f"none of {', '.join(ids)} can be lifted (each one's grasp is one the finger sensor cannot "
                         "confirm): add one that can, such as soda-can-12oz/upright")
    return tuple(objects)


def _descriptions(library: Path) -> dict[str, dict]:
    try:
        document = json.loads(library.read_text(encoding="utf-8"))
        return {d["id"]: d for d in document["descriptions"]}
    except (OSError, ValueError, KeyError, TypeError) as exc:
        raise ValueError(f"{library}: cannot read the library's descriptions: {exc}") from None


def _reference_object(entry: CatalogueEntry, description: dict, profile: RobotProfile,
                      library: Path) -> ReferenceObject:
    by_feature = {f.name: (p, f) for p in profile.sensing for f in p.features}
    expected = []
    for item in description["features"]:
        if item["feature"] not in by_feature:
            raise ValueError(f"{library}: {entry.id}: feature {item['feature']} is not one of the profile's "
                             f"({profile.source})")
        procedure, spec = by_feature[item["feature"]]
        distance, side = item["position"]
        expected.append(Expected(spec.name, procedure.name, float(distance), None if side == "*" else float(side),
                                 float(item["value"]), spec.error, spec.unit))
    footprint = entry.footprint
    if footprint.shape == "circle":
        area, elongation = math.pi * footprint.radius_in ** 2, 1.0
    else:
        area, elongation = footprint.length_in * footprint.width_in, footprint.length_in / footprint.width_in
    grasp = profile.grasping_procedure(description["grasp"])
    distance, side = description["grasp_position"]
    return ReferenceObject(entry.id, area, elongation, tuple(expected), description["grasp"],
                           (float(distance), None if side == "*" else float(side)),
                           frozenset(rule.procedure for rule in entry.grasps),
                           grasp is not None and grasp.verifiable)


def _alike(a: ReferenceObject, b: ReferenceObject) -> bool:
    """Whether one region could fit both (each fits within a factor of its own footprint)."""
    area = max(a.area_in2, b.area_in2) / min(a.area_in2, b.area_in2)
    elongation = max(a.elongation, b.elongation) / min(a.elongation, b.elongation)
    return area < AREA_RATIO ** 2 and elongation < ELONGATION_RATIO ** 2


def prompt(reference: Reference) -> str:
    """What the operator is asked before the robot moves: what to place, where, and what
    the robot will then do."""
    plan = reference.objects
    senses = sum(len({(e.procedure, e.distance_in, e.orientation_deg) for e in o.expected}) for o in plan)
    lifted = next(o for o in plan if o.liftable)
    nearest = min(min(e.distance_in for e in o.expected) for o in plan)
    lines = [
        "reference check: place these objects anywhere on the floor the camera sees, each standing as named,",
        *(f"  - {o.id}" for o in plan),
        "at least 5 ft apart, 4 ft from the robot and 3 ft from walls and furniture; take everything else off "
        "the floor and keep people out of the room.",
        f"The robot will then drive straight lines around each object to the library's training positions "
        f"(as near as {nearest:g} in), apply about {senses + 2} sensing procedures, grasp {lifted.id} with {lifted.grasp} "
        "and put it in its bin, and try one wrong grasp on another object (which may nudge it).",
        "Press Enter when they are placed (type 'skip' to leave sensing and grasping NOT checked; Ctrl-C stops "
        "the suite).",
    ]
    return "\n".join(lines)


def reference_checks(probe: Probe, reference: Reference) -> list[CheckResult]:
    """Run the reference checks in order, each named; a check that needs an earlier one
    that failed says so. A driver that restores the shipped world REFERENCE_WORLD (a
    simulator) places the default objects itself; otherwise the operator is asked, and
    one who declines gets the one failing ``reference`` line."""
    try:
        restored = _restored(probe, reference)
    except CheckFailed as exc:  # the reset's reply: malformed, or none
        return [CheckResult("reference-objects", False, f"reset to world {REFERENCE_WORLD!r}: {exc}")]
    if not restored and reference.ask is not None and not reference.ask(prompt(reference)):
        return [CheckResult("reference", False, NOT_PLACED)]
    run = _Run(probe, reference)
    results = []
    for name, check in run.checks():
        try:
            results.append(CheckResult(name, True, check()))
        except CheckFailed as exc:
            results.append(CheckResult(name, False, str(exc)))
    return results


def _restored(probe: Probe, reference: Reference) -> bool:
    """Whether the driver restored REFERENCE_WORLD, which holds the default objects (a
    real robot refuses it ``bad_request``, as it refuses every simulated world)."""
    if tuple(o.id for o in reference.objects) != DEFAULT_OBJECTS:
        return False
    return not isinstance(probe.outcome("reset", {"world": REFERENCE_WORLD, "seed": None}), DriverError)


# ------------------------------------------------------------------- the plan


@dataclass(frozen=True)
class _Visit:
    """One training position of one object, on a side the camera fixed."""

    object: ReferenceObject
    distance_in: float
    orientation_deg: float  # from the region's reference axis
    expected: tuple[Expected, ...]

    def text(self) -> str:
        return f"{self.object.id} at ({self.distance_in:g} in, {self.orientation_deg:.0f} deg)"


def _circumradius(region: Region) -> float:
    return float(np.max(np.hypot(*(region.polygon_array() - np.asarray(region.centroid)).T)))


def _segment_gap(a: np.ndarray, b: np.ndarray, point: np.ndarray) -> float:
    ab = b - a
    t = 0.0 if not ab.any() else float(np.clip(np.dot(point - a, ab) / np.dot(ab, ab), 0.0, 1.0))
    return float(np.hypot(*(a + t * ab - point)))


def _bearing(origin: np.ndarray, point: np.ndarray) -> float:
    """The world direction (degrees) from ``origin`` to ``point``."""
    return math.degrees(math.atan2(point[1] - origin[1], point[0] - origin[0]))


def _arc(centre: np.ndarray, radius: float, start_deg: float, end_deg: float) -> list[np.ndarray]:
    """Points on a circle from ``start_deg`` to ``end_deg`` the short way round, both
    ends included, at most ARC_STEP_DEG apart: straight chords that clear what the
    circle clears by ``radius * (1 - cos(ARC_STEP_DEG / 2))`` less."""
    turn = (end_deg - start_deg + 180.0) % 360.0 - 180.0
    steps = max(1, math.ceil(abs(turn) / ARC_STEP_DEG))
    return [centre + radius * _unit(start_deg + turn * k / steps) for k in range(steps + 1)]


def _unit(deg: float) -> np.ndarray:
    return np.array([math.cos(math.radians(deg)), math.sin(math.radians(deg))])


class _Run:
    """The reference checks against one placement of the objects."""

    def __init__(self, probe: Probe, reference: Reference) -> None:
        self.probe = probe
        self.reference = reference
        self.geometry = reference.profile.robot.geometry
        self.regions: dict[str, Region] = {}
        self.scene: Scene | None = None
        self.visits: list[_Visit] = []
        self.sides: dict[str, float] = {}  # the side each object is approached from for "any side" positions
        self.at: tuple[str, float] | None = None  # the object the robot stands at, and its bearing from it
        self.pose: Pose | None = None  # as the driver reports it
        self.offset = np.zeros(2)  # the camera's robot position less the driver's (_localise)
        self.ready = False  # reference-objects passed: the objects are found and the plan fits the floor

    def checks(self) -> list[tuple[str, Callable[[], str]]]:
        return [
            ("reference-objects", self.objects),
            ("reference-sensing", self.sensing),
            ("reference-stale", self.stale),
            ("reference-grasp", self.grasp),
            ("reference-wrong-grasp", self.wrong_grasp),
        ]

    # -- finding the objects ------------------------------------------------------

    def objects(self) -> str:
        """Each object is the one region of its footprint's size and shape; then every
        position the robot will stand at is checked against the floor and the other
        objects before anything moves (and each straight drive before it is driven)."""
        scene = self._look()
        for obj in self.reference.objects:
            fitting = [r for r in scene.regions if obj.fits(r)]
            if not fitting:
                seen = ", ".join(f"{r.area_in2 or 0:.1f}" for r in scene.regions) or "none"
                raise CheckFailed(f"{obj.id}: no object of its footprint ({obj.area_in2:.1f} sq in, elongation "
                                  f"{obj.elongation:.2f}) seen; the camera sees objects of {seen} sq in")
            if len(fitting) > 1:
                where = ", ".join(f"({r.centroid[0]:.0f}, {r.centroid[1]:.0f})" for r in fitting)
                raise CheckFailed(f"{obj.id}: {len(fitting)} objects of its size at {where} cannot be told apart: "
                                  "leave only the reference objects on the floor")
            self.regions[obj.id] = fitting[0]
        self.scene = scene
        self.pose = self._published_pose()
        for obj in self.reference.objects:
            self.sides[obj.id] = self._free_side(obj)
            self.visits.extend(self._visits(obj))
        for visit in self.visits:
            self._check_stand(visit.object, visit.distance_in, visit.orientation_deg)
        self.ready = True
        return "; ".join(f"{o.id} seen at ({self.regions[o.id].centroid[0]:.1f}, {self.regions[o.id].centroid[1]:.1f})"
                         f" over {self.regions[o.id].area_in2 or 0:.1f} sq in" for o in self.reference.objects) + \
            f"; {len(self.visits)} training positions reachable"

    def _look(self) -> Scene:
        """What the executive's vision makes of a fresh image: by the grey bands, or
        through the camera's calibration."""
        image = self.probe.result("camera", {})
        camera = self.reference.camera
        if camera is not None:
            width, height = camera.calibration.image_size
            rows, cols = image.pixels.shape[:2]
            if (cols, rows) != (width, height):
                raise CheckFailed(f"the calibration is for {width}x{height} images, the driver's camera gives "
                                  f"{cols}x{rows} (a calibration of another camera?)")
        try:
            return look(image, camera)
        except ValueError as exc:
            raise CheckFailed(f"the camera's image cannot be read: {exc}") from None

    def _published_pose(self) -> Pose:
        """The pose of the next state publication: where the robot starts from."""
        start = time.monotonic()
        while time.monotonic() < start + 2.0:
            states = valid_states(self.probe.states_since(start))
            if states:
                return states[-1].pose
            time.sleep(0.05)
        raise CheckFailed("no state publication within 2 s: the robot's pose is not known")

    def _visits(self, obj: ReferenceObject) -> list[_Visit]:
        """The object's training positions, one visit each: a position for any side is
        merged into one of the same distance on a named side, else taken on the
        object's free side."""
        named = sorted({(e.distance_in, e.orientation_deg) for e in obj.expected if e.orientation_deg is not None})
        first_side: dict[float, float] = {}
        for distance, side in named:
            first_side.setdefault(distance, side)
        visits = []
        for distance, side in named:
            here = tuple(e for e in obj.expected if e.distance_in == distance and (
                e.orientation_deg == side or (e.orientation_deg is None and side == first_side[distance])))
            visits.append(_Visit(obj, distance, side, here))
        for distance in sorted({e.distance_in for e in obj.expected if e.orientation_deg is None} - set(first_side)):
            here = tuple(e for e in obj.expected if e.distance_in == distance and e.orientation_deg is None)
            visits.append(_Visit(obj, distance, self.sides[obj.id], here))
        return visits

    def _free_side(self, obj: ReferenceObject) -> float:
        """The side (from the region's reference axis) for the object's any-side
        positions: the first, turning from the floor's middle, where every one of
        them stands inside the floor, clear of the other objects, with its beam clear."""
        region = self.regions[obj.id]
        x0, x1, y0, y1 = self._floor()
        middle = math.degrees(math.atan2((y0 + y1) / 2 - region.centroid[1], (x0 + x1) / 2 - region.centroid[0]))
        distances = {e.distance_in for e in obj.expected if e.orientation_deg is None} | {obj.grasp_position[0]}
        turns = [0.0] + [s * k * SIDE_STEP_DEG for k in range(1, int(180 / SIDE_STEP_DEG)) for s in (1, -1)] + [180.0]
        for turn in turns:
            side = (middle + turn - region.reference_axis_deg) % 360.0
            try:
                for distance in distances:
                    self._check_stand(obj, distance, side)
            except CheckFailed:
                continue
            return side
        raise CheckFailed(f"{obj.id}: no side of it leaves room for the training positions: place it nearer the "
                          "middle of the floor and farther from the other objects")

    def _floor(self) -> tuple[float, float, float, float]:
        assert self.scene is not None
        image = self.scene.image
        s = image.inches_per_pixel
        rows, cols = image.pixels.shape[:2]
        return image.origin_x_in, image.origin_x_in + cols * s, image.origin_y_in - rows * s, image.origin_y_in

    def _stand(self, obj: ReferenceObject, distance_in: float, side_deg: float) -> PlannerPose:
        return pose_for_position(self.regions[obj.id], distance_in, side_deg, self.geometry)

    def _check_stand(self, obj: ReferenceObject, distance_in: float, side_deg: float) -> None:
        """CheckFailed unless the base at this position is inside the floor, clear of
        the other objects, and the sonar's beam meets no other object first."""
        pose = self._stand(obj, distance_in, side_deg)
        where = f"{obj.id} at ({distance_in:g} in, {side_deg:.0f} deg)"
        self._check_inside(np.array([pose.x_in, pose.y_in]), where)
        others = [r for name, r in self.regions.items() if name != obj.id]
        for other in others:
            gap = math.hypot(pose.x_in - other.centroid[0], pose.y_in - other.centroid[1])
            if gap < self.geometry.base_radius_in + _circumradius(other):
                raise CheckFailed(f"the robot standing at {where} would touch the object at ({other.centroid[0]:.0f}, "
                                  f"{other.centroid[1]:.0f}): place the objects farther apart")
        if beam_blockers(self.regions[obj.id], distance_in, side_deg, others):
            raise CheckFailed(f"another object stands in the sonar's beam at {where}: place the objects farther apart")

    def _check_inside(self, point: np.ndarray, where: str) -> None:
        x0, x1, y0, y1 = self._floor()
        margin = self.geometry.base_radius_in + EDGE_MARGIN_IN
        if not (x0 + margin <= point[0] <= x1 - margin and y0 + margin <= point[1] <= y1 - margin):
            raise CheckFailed(f"the robot would stand at ({point[0]:.0f}, {point[1]:.0f}) for {where}, within "
                              f"{margin:g} in of the floor's edge: place the objects nearer the middle of the floor")

    # -- moving -----------------------------------------------------------------

    def _ring(self, obj_id: str) -> float:
        return _circumradius(self.regions[obj_id]) + self.geometry.base_radius_in + RING_MARGIN_IN

    def _go(self, obj: ReferenceObject, distance_in: float, side_deg: float) -> None:
        """Drive to a position: away from the object the robot stands at onto its ring,
        straight onto the target's ring where it faces the robot (unless it is the same
        object), round that ring to the position's side in chords, straight in; facing
        and centred on the object. Planned in the camera's frame, sent in the driver's
        (:meth:`_localise`)."""
        if self.pose is None:
            raise CheckFailed("needs reference-objects to pass")
        self._localise()
        region = self.regions[obj.id]
        goal = self._stand(obj, distance_in, side_deg)
        bearing = region.reference_axis_deg + side_deg
        centre, ring = np.asarray(region.centroid), self._ring(obj.id)
        points: list[np.ndarray] = []
        was = None
        if self.at is not None:
            name, left = self.at
            if name == obj.id:
                was = left
            else:  # round the object it stands at to where it faces the target
                other = np.asarray(self.regions[name].centroid)
                points.extend(_arc(other, self._ring(name), left, _bearing(other, centre)))
        if was is None:  # onto the target's ring where it faces the robot
            start = points[-1] if points else np.array([self.pose.x_in, self.pose.y_in]) + self.offset
            was = _bearing(centre, start)
        points.extend(_arc(centre, ring, was, bearing))
        points.append(np.array([goal.x_in, goal.y_in]))
        here = np.array([self.pose.x_in, self.pose.y_in]) + self.offset
        for a, b in zip([here, *points[:-1]], points):
            self._check_inside(b, obj.id)
            for name, other in self.regions.items():
                clear = self.geometry.base_radius_in + _circumradius(other) - 1e-6
                if _segment_gap(a, b, np.asarray(other.centroid)) < clear:
                    raise CheckFailed(f"the straight drive from ({a[0]:.0f}, {a[1]:.0f}) to ({b[0]:.0f}, {b[1]:.0f}) "
                                      f"would touch {name}: place the objects farther apart")
        waypoints = []
        for i, point in enumerate(points):
            ahead = points[i + 1] if i + 1 < len(points) else None
            heading = goal.heading_deg if ahead is None else math.degrees(math.atan2(*(ahead - point)[::-1]))
            sent = point - self.offset
            waypoints.append({"x_in": float(sent[0]), "y_in": float(sent[1]), "heading_deg": heading})
        face = centre - self.offset
        outcome = self.probe.outcome("move", {"waypoints": waypoints, "face": [float(face[0]), float(face[1])]})
        if isinstance(outcome, DriverError):
            raise CheckFailed(f"the move to {obj.id} at ({distance_in:g} in, {side_deg:.0f} deg) was refused "
                              f"{outcome.code}: {outcome.message}")
        if not isinstance(outcome, MoveResult):
            raise CheckFailed("the move's reply is not a move result")
        self.pose, self.at = outcome.pose, (obj.id, bearing)
        if outcome.collided or outcome.blocked is not None:
            raise CheckFailed(f"the robot met something driving to {obj.id} at ({distance_in:g} in, {side_deg:.0f} "
                              "deg): clear the floor around the objects")

    def _localise(self) -> None:
        """Correct the driver's dead reckoning as the executive does
        (behaviours/localisation.py): a wheeled base drifts while the pose it reports
        stays put, and at 6 in a drift of 1.5 in puts the object out of a procedure's
        range. The offset is where the camera sees the robot less where the driver says
        it is, changed only when the camera sees it more than LOCALISE_DEADBAND_IN from
        the corrected pose (less is the camera's own error). A robot seen farther than
        CENTRE_TOLERANCE_IN from where the driver says it is, is no drift but an image
        or a pose not to be trusted: driving by it could run the robot into an object."""
        assert self.pose is not None
        seen = self._look().robot
        if seen is None:
            return
        reported = np.array([self.pose.x_in, self.pose.y_in])
        off = np.array([seen.x_in, seen.y_in]) - reported
        if math.hypot(*off) > CENTRE_TOLERANCE_IN:
            raise CheckFailed(f"the camera sees the robot at ({seen.x_in:.1f}, {seen.y_in:.1f}), {math.hypot(*off):.1f} "
                              f"in from where the driver says it is ({reported[0]:.1f}, {reported[1]:.1f}); at most "
                              f"{CENTRE_TOLERANCE_IN:g} in (a stale image, or a pose that is not the robot's?)")
        if math.hypot(*(off - self.offset)) > LOCALISE_DEADBAND_IN:
            self.offset = off

    # -- sensing ------------------------------------------------------------------

    def _sense(self, visit: _Visit, procedure: str) -> SenseResult:
        outcome = self.probe.outcome("sense", {"procedure": procedure})
        if isinstance(outcome, DriverError):
            raise CheckFailed(f"{procedure} at {visit.text()}: {outcome.code}: {outcome.message} (the camera puts "
                              f"it {visit.distance_in:g} in ahead of the sonar)")
        if not isinstance(outcome, SenseResult) or outcome.procedure != procedure:
            raise CheckFailed(f"{procedure} at {visit.text()}: the reply does not echo the procedure")
        if abs(outcome.distance_in - visit.distance_in) > DISTANCE_TOLERANCE_IN:
            raise CheckFailed(f"{procedure} at {visit.text()}: the reply's distance_in is {outcome.distance_in:.1f} "
                              f"in, the camera puts the object {visit.distance_in:g} in ahead of the sonar (at most "
                              f"{DISTANCE_TOLERANCE_IN:g} in apart; distances are inches)")
        return outcome

    def sensing(self) -> str:
        """Every procedure with library values at each training position; a reading
        with a value off its library value is repeated (up to READINGS), and most
        readings of each value must be within its tolerance."""
        if not self.ready:
            raise CheckFailed("needs reference-objects to pass")
        values, worst = 0, 0.0
        for visit in self.visits:
            self._go(visit.object, visit.distance_in, visit.orientation_deg)
            for procedure in sorted({e.procedure for e in visit.expected}):
                expected = [e for e in visit.expected if e.procedure == procedure]
                readings = [self._sense(visit, procedure)]
                if not _agrees(expected, readings[0]):  # read again until each value is settled one way
                    majority = READINGS // 2 + 1
                    while len(readings) < READINGS:
                        readings.append(self._sense(visit, procedure))
                        agreed = [sum(_off(e, r) is None for r in readings) for e in expected]
                        if min(agreed) >= majority or len(readings) - min(agreed) >= majority:
                            break
                    if any(sum(_off(e, r) is None for r in readings) < majority for e in expected):
                        raise CheckFailed(_disagreement(visit, procedure, expected, readings))
                for e in expected:
                    values += 1
                    good = next(r for r in readings if _off(e, r) is None)
                    if e.error > 0:
                        worst = max(worst, abs(float(good.values[e.feature]) - e.value) / e.error)
        return (f"{values} values at {len(self.visits)} training positions within {ERROR_FACTOR:g} expected errors "
                f"of the library's, the farthest {worst:.1f}")

    def stale(self) -> str:
        """One feature sensed twice in a row from two positions whose library values
        differ the most (in expected errors): the readings must differ by at least
        STALE_SHARE of that, in one of STALE_ATTEMPTS tries. A sensor that repeats its
        last value fails every time."""
        if not self.ready:
            raise CheckFailed("needs reference-objects to pass")
        pairs = [(abs(a.value - b.value) / max(a.error, 1e-9), va, a, vb, b)
                 for va in self.visits for vb in self.visits if va is not vb
                 for a in va.expected for b in vb.expected
                 if a.feature == b.feature and va.object is vb.object and abs(a.value - b.value) > 2 * a.error]
        if not pairs:
            raise CheckFailed("no feature of the reference objects has library values far enough apart: "
                              "choose other objects")
        _, first, a, second, b = max(pairs, key=lambda p: p[0])
        needed = STALE_SHARE * abs(a.value - b.value)
        for _attempt in range(STALE_ATTEMPTS):  # a sonar's odd miss is not a stale sensor; a stale one repeats
            values = []
            for visit in (first, second):
                self._go(visit.object, visit.distance_in, visit.orientation_deg)
                values.append(self._sense(visit, a.procedure).values.get(a.feature))
            if None not in values and abs(values[0] - values[1]) >= needed:
                return (f"{a.feature} read {_value(values[0])} at {first.text()}, then {_value(values[1])} at "
                        f"{second.text()} (library {a.value:g}, {b.value:g})")
        raise CheckFailed(f"{a.feature} read {_value(values[0])} at {first.text()} and then {_value(values[1])} "
                          f"at {second.text()}; the library has {a.value:g} and {b.value:g} there, so the readings "
                          f"must differ by at least {needed:g} (a stale or stuck reading?)")

    # -- grasping -----------------------------------------------------------------

    def _grasp_at(self, obj: ReferenceObject, procedure: str) -> GraspResult:
        distance, side = obj.grasp_position
        self._go(obj, distance, self.sides[obj.id] if side is None else side)
        outcome = self.probe.outcome("grasp", {"procedure": procedure})
        if isinstance(outcome, DriverError):
            raise CheckFailed(f"{procedure} on {obj.id} from {distance:g} in: {outcome.code}: {outcome.message} "
                              f"(the camera puts it {distance:g} in ahead)")
        if not isinstance(outcome, GraspResult) or outcome.procedure != procedure:
            raise CheckFailed(f"{procedure} on {obj.id}: the reply does not echo the procedure")
        return outcome

    def _still_on_floor(self, obj: ReferenceObject) -> Region | None:
        """The region of ``obj`` the camera still sees at its place, or None."""
        scene = self._look()
        centre, reach = np.asarray(self.regions[obj.id].centroid), _circumradius(self.regions[obj.id]) + 3.0
        return next((r for r in scene.regions if obj.fits(r)
                     and math.hypot(*(np.asarray(r.centroid) - centre)) <= reach), None)

    def grasp(self) -> str:
        """The first liftable object, with the library's grasp: reported held, and gone
        from the floor in the next image; then released."""
        if not self.ready:
            raise CheckFailed("needs reference-objects to pass")
        obj = next(o for o in self.reference.objects if o.liftable)
        result = self._grasp_at(obj, obj.grasp)
        if not result.success:
            raise CheckFailed(f"{obj.grasp} on {obj.id}, its correct grasp, reported not held")
        left = self._still_on_floor(obj)
        self.probe.result("release", {})
        if left is not None:
            raise CheckFailed(f"{obj.grasp} on {obj.id} reported held, but the camera still sees it on the floor at "
                              f"({left.centroid[0]:.1f}, {left.centroid[1]:.1f})")
        return f"{obj.grasp} held {obj.id}, which left the floor; released"

    def wrong_grasp(self) -> str:
        """Another object with a grasp that cannot lift it (the cheapest one the finger
        sensor confirms and the catalogue does not list for it): it must report not
        held. An object no grasp lifts is preferred, so the fingers have nothing to
        knock over."""
        if not self.ready:
            raise CheckFailed("needs reference-objects to pass")
        lifted = next(o for o in self.reference.objects if o.liftable)
        others = sorted((o for o in self.reference.objects if o is not lifted), key=lambda o: o.liftable)
        obj = others[0]
        wrong = sorted((g for g in self.reference.profile.grasping if g.verifiable and g.name not in obj.correct_grasps
                        and g.applicable_at(obj.grasp_position[0])), key=lambda g: g.time_s)
        if not wrong:
            raise CheckFailed(f"{obj.id}: every grasp of the profile lifts it: choose another object")
        procedure = wrong[0].name
        result = self._grasp_at(obj, procedure)
        if result.success:
            self.probe.result("release", {})
            seen = self._still_on_floor(obj)
            there = "" if seen is None else ", and the camera still sees it on the floor"
            raise CheckFailed(f"{procedure} on {obj.id}, a grasp that cannot lift it, reported held{there} "
                              "(a finger sensor stuck at held?)")
        return f"{procedure} on {obj.id}, a grasp that cannot lift it, reported not held"


def _off(expected: Expected, result: SenseResult) -> str | None:
    """Why one reading's value of ``expected``'s feature is off, or None when it is not."""
    value = result.values.get(expected.feature)
    if value is None:
        return "missing"
    if abs(value - expected.value) > expected.tolerance:
        return f"{value:g}"
    return None


def _agrees(expected: Sequence[Expected], result: SenseResult) -> bool:
    """Whether every value of one reading is within its tolerance of the library's."""
    return all(_off(e, result) is None for e in expected)


def _value(value: float | None) -> str:
    return "nothing" if value is None else f"{value:.4g}"


def _disagreement(visit: _Visit, procedure: str, expected: Sequence[Expected], readings: Sequence[SenseResult]) -> str:
    e = min(expected, key=lambda e: sum(_off(e, r) is None for r in readings))
    read = ", ".join(_value(r.values.get(e.feature)) for r in readings)
    return (f"{procedure} at {visit.text()}: {e.feature} read {read}; the library has {e.value:g} {e.unit} "
            f"within {e.tolerance:g} ({ERROR_FACTOR:g} x its expected error {e.error:g})")
