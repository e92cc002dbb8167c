"""Measurement sources for the training stage that need the robot side.

The learner defines what a measurement source is; this module adapts the simulated
HERO to it (one object alone, the robot placed at the training position, as a team
would stage it on the lab floor) and records what any source answered into a replay
file, so a training run can be repeated without the robot.
"""

from __future__ import annotations

from collections.abc import Mapping

from hero_driver.interface import DriverError
from hero_driver.sim.probe import probe
from hero_driver.sim.world import profile_and_catalogue
from learner.position import Position
from learner.training_data import MeasurementSource, TrainingObject
from robot_profile import RobotProfile

GRASP_DISTANCE_IN = 6.0
_APPROACH_ORIENTATION = {"any": None, "end": 0.0, "side": 90.0}


class SimulatorSource:
    """Senses catalogue objects in the simulator (exact values unless ``noise``), as the
    robot of ``profile`` would (default: the shipped HERO 2000)."""

    def __init__(self, seed: int = 0, noise: bool = False, profile: RobotProfile | None = None) -> None:
        self.seed, self.noise, self.profile = seed, noise, profile

    def measure(self, object_id: str, procedure: str, position: Position) -> Mapping[str, float | None]:
        if position.distance_in is None or position.orientation_deg is None:
            raise ValueError(f"training position {position} must be concrete to stage the robot")
        try:
            result = probe(object_id, procedure, position.distance_in, position.orientation_deg,
                           seed=self.seed, noise=self.noise, profile=self.profile)
        except DriverError as exc:
            raise ValueError(f"simulator: {procedure} of {object_id!r} at {position}: {exc.message}") from None
        return dict(result.values)


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
