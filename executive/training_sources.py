"""Measurement sources for the training stage that need the robot side.

The learner defines what a measurement source is; this module adapts the simulated
HERO to it (one object alone, the robot placed at the training position, as a team
would stage it on the lab floor) and records what any source answered into a replay
file, so a training run can be repeated without the robot. The training objects
themselves come from what the overhead camera sees of each (:func:`camera_objects`),
as in the paper, from the robot's own scans of each (``executive/outline_objects.py``;
both through :func:`seen_objects`), or from the catalogue's true footprints
(:func:`catalogue_objects`).
"""

from __future__ import annotations

import math
from collections.abc import Callable, Mapping
from dataclasses import dataclass

from behaviours.appearance import appearance_of
from hero_driver.interface import DriverError
from hero_driver.sim.probe import approach_pose, probe, probe_world
from hero_driver.sim.catalogue import profile_and_catalogue
from hero_driver.sim.world import SimWorld
from learner.appearance import Appearance
from learner.position import Position
from learner.training.grasps import GraspOutcome
from learner.training.inputs import MeasurementSource, TrainingObject
from planner.vision import Region, look
from robot_profile import RobotProfile

GRASP_DISTANCE_IN = 6.0
_APPROACH_ORIENTATION = {"any": None, "end": 0.0, "side": 90.0}


class SimulatorSource:
    """Senses catalogue objects in the simulator (exact values unless ``noise``), as the
    robot of ``profile`` would (default: the shipped HERO 2000).

    Orientations are relative to each object's reference axis. The simulator stages the
    robot from the catalogue's axis; ``axis_offsets_deg[object]`` is where the axis the
    training positions were chosen from (the perceived one, see :func:`seen_objects`)
    lies relative to it, so the robot stands where the training position means.

    Each noisy measurement is made in a fresh one-object world, so its noise is drawn
    from ``seed`` alone and does not depend on what was measured before. Without noise a
    measurement is a function of the object and the pose only (sensing moves nothing,
    and exact values draw nothing from the random stream), so one world per object
    serves them all: building a world costs more than sensing in it. ``reuse=False``
    builds one per measurement anyway (the reference the reuse is checked against).
    """

    def __init__(self, seed: int = 0, noise: bool = False, profile: RobotProfile | None = None,
                 axis_offsets_deg: Mapping[str, float] | None = None, reuse: bool = True) -> None:
        self.seed, self.noise, self.profile = seed, noise, profile
        self.axis_offsets_deg = dict(axis_offsets_deg or {})
        self.reuse = reuse and not noise
        self._worlds: dict[str, SimWorld] = {}

    def measure(self, object_id: str, procedure: str, position: Position) -> Mapping[str, float | None]:
        if position.distance_in is None or position.orientation_deg is None:
            raise ValueError(f"training position {position} must be concrete to stage the robot")
        orientation = (position.orientation_deg + self.axis_offsets_deg.get(object_id, 0.0)) % 360.0
        try:
            if self.reuse:
                if object_id not in self._worlds:
                    self._worlds[object_id] = probe_world(object_id, self.seed, False, self.profile)
                sim = self._worlds[object_id]
                sim.pose = approach_pose(sim, 0, position.distance_in, orientation)
                result = sim.sense(procedure)
            else:
                result = probe(object_id, procedure, position.distance_in, orientation,
                               seed=self.seed, noise=self.noise, profile=self.profile)
        except DriverError as exc:
            raise ValueError(f"simulator: {procedure} of {object_id!r} at {position}: {exc.message}") from None
        return dict(result.values)


class SimulatorGrasps:
    """Tries grasps on catalogue objects in the simulator, as a team would stage them for
    grasping experiments: each attempt on the object alone, freshly placed (a failed grasp
    may have pushed or knocked it over), the robot at the approach position. Orientations
    are relative to the camera's reference axis, as in :class:`SimulatorSource`."""

    def __init__(self, seed: int = 0, profile: RobotProfile | None = None,
                 axis_offsets_deg: Mapping[str, float] | None = None) -> None:
        self.seed, self.profile = seed, profile
        self.axis_offsets_deg = dict(axis_offsets_deg or {})

    def try_grasp(self, object_id: str, grasp: str, position: Position) -> GraspOutcome:
        if position.distance_in is None:
            raise ValueError(f"grasp position {position} needs a distance to stage the robot")
        orientation = ((position.orientation_deg or 0.0) + self.axis_offsets_deg.get(object_id, 0.0)) % 360.0
        sim = probe_world(object_id, self.seed, False, self.profile)
        sim.pose = approach_pose(sim, 0, position.distance_in, orientation)
        try:
            result = sim.grasp(grasp)
        except DriverError as exc:
            raise ValueError(f"simulator: {grasp} of {object_id!r} at {position}: {exc.message}") from None
        return GraspOutcome(result.success, result.duration_s)


class RecordingSource:
    """Passes measurements through and keeps them for a replay file."""

    def __init__(self, inner: MeasurementSource) -> None:
        self.inner = inner
        self.records: dict[tuple[str, str, Position], Mapping[str, float | None]] = {}

    def measure(self, object_id: str, procedure: str, position: Position) -> Mapping[str, float | None]:
        values = self.inner.measure(object_id, procedure, position)
        self.records[(object_id, procedure, position)] = values
        return values


def catalogue_objects(object_set: str = "training") -> list[TrainingObject]:
    """The simulator catalogue's objects of one set as training objects.

    An object with several correct grasps (a lying can: Top-Vert-Grip end-on,
    Top-Hor-Grip from the side) is labelled with the first, at the orientation its
    approach needs (end: 0°, along the major axis; side: 90°; any: ``*``).
    """
    _, catalogue = profile_and_catalogue()
    objects = []
    for entry in catalogue.values():
        if entry.set != object_set:
            continue
        rule = entry.grasps[0]
        fp = entry.footprint
        if fp.shape == "circle":
            polygon: tuple[tuple[float, float], ...] = ()
        else:
            hl, hw = fp.length_in / 2, fp.width_in / 2
            polygon = ((-hl, -hw), (hl, -hw), (hl, hw), (-hl, hw))
        grasp_position = Position(GRASP_DISTANCE_IN, _APPROACH_ORIENTATION.get(rule.approach))
        objects.append(TrainingObject(entry.id, rule.procedure, grasp_position, polygon, fp.shape == "circle"))
    if not objects:
        raise ValueError(f"the simulator catalogue has no objects in set {object_set!r}")
    return objects


@dataclass(frozen=True)
class SeenObjects:
    """Training objects as a perception sees them (the overhead camera, or the robot's
    own scans), and for each the angle of the perceived reference axis from the
    catalogue's (what :class:`SimulatorSource` needs to stage the robot at the training
    positions chosen on the perceived polygons)."""

    objects: tuple[TrainingObject, ...]
    axis_offsets_deg: Mapping[str, float]


@dataclass(frozen=True)
class Sighting:
    """What one way of perceiving makes of a training object staged alone, aligned with
    the room: its reference axis in world degrees (the object lies at yaw 0, so this is
    also the axis's angle from the catalogue's), its footprint in its own frame (+x
    along that axis; empty when round), whether it is round, and its appearance (None:
    this perception gives none)."""

    axis_deg: float
    polygon: tuple[tuple[float, float], ...]
    round: bool
    appearance: Appearance | None


def seen_objects(object_set: str, sight: Callable[[str], Sighting]) -> SeenObjects:
    """The catalogue's objects of one set as ``sight`` perceives each: footprint, axis,
    roundness and appearance are the perception's; the grasp label is the teacher's
    (:func:`catalogue_objects`), its approach orientation turned onto the perceived axis
    so that it still means the same side of the object."""
    labelled = {o.object_id: o for o in catalogue_objects(object_set)}
    objects, offsets = [], {}
    for object_id, labels in labelled.items():
        seen = sight(object_id)
        offsets[object_id] = seen.axis_deg
        grasp_orientation = labels.grasp_position.orientation_deg
        if grasp_orientation is not None:
            grasp_orientation = float(round(grasp_orientation - seen.axis_deg) % 360)
        objects.append(TrainingObject(object_id, labels.grasp, Position(labels.grasp_position.distance_in,
                                                                        grasp_orientation),
                                      seen.polygon, seen.round, seen.appearance))
    return SeenObjects(tuple(objects), offsets)


def camera_objects(object_set: str = "training", profile: RobotProfile | None = None, seed: int = 0,
                   noise: bool = False) -> SeenObjects:
    """The catalogue's objects of one set, each placed alone on the floor (aligned with
    the room, as a team stages training objects) and seen by the overhead camera.

    As in the paper, the footprint polygon, its reference axis and whether it is round
    are the vision's (``planner/vision.py``), not the catalogue's: training orientations
    come from what the robot can see. So a small object whose pixels look isotropic
    (the lying 16 oz tumbler at 0.8 in per pixel) trains as round, as the robot would
    treat it at run time. Only the grasp label (and where it is made) is the teacher's,
    taken from the catalogue as :func:`catalogue_objects` does. Each object's appearance
    (area, elongation, round) is recorded as the camera saw it here, for its description.
    """
    return seen_objects(object_set, lambda object_id: _camera_sighting(object_id, profile, seed, noise))


def _camera_sighting(object_id: str, profile: RobotProfile | None, seed: int, noise: bool) -> Sighting:
    regions = look(probe_world(object_id, seed, noise, profile).camera()).regions
    if len(regions) != 1:
        raise ValueError(f"camera: {object_id!r} alone on the floor shows {len(regions)} regions, not 1")
    region = regions[0]
    return Sighting(region.reference_axis_deg, () if region.round else _object_frame(region), region.round,
                    appearance_of(region))


def _object_frame(region: Region) -> tuple[tuple[float, float], ...]:
    """The region's polygon about its centroid, +x along its reference axis, to 0.001 in
    (what a training-objects file keeps, so a replay sees the same footprint)."""
    a = math.radians(region.reference_axis_deg)
    cx, cy = region.centroid
    return tuple((round((x - cx) * math.cos(a) + (y - cy) * math.sin(a), 3),
                  round(-(x - cx) * math.sin(a) + (y - cy) * math.cos(a), 3)) for x, y in region.polygon)
