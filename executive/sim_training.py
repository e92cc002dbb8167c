"""Training in the simulated lab, as ``csl train --sim`` and an experiment run it.

The objects come from the overhead camera (their footprints as vision sees them) or,
without it, from the robot's own scans (their outlines, ``executive/outline_objects.py``);
the measurements from the simulator staged at each training position; the result is the
learned library with the paper's training figures (:class:`TrainingSummary`). The
library can then be held against the simulator's ground truth: every value, at every
training position it stands for, against the exact (noise-free) value there.
"""

from __future__ import annotations

from collections.abc import Callable, Mapping, Sequence
from dataclasses import dataclass

from executive.outline_objects import outline_objects
from executive.training_sources import RecordingSource, SeenObjects, SimulatorGrasps, SimulatorSource, camera_objects
from learner.costs import ModelMoveCost
from learner.description import ObjectDescription
from learner.knowledge import Knowledge
from learner.training.fidelity import FidelityReport, check_fidelity
from learner.training.grasps import GraspSearch, find_grasps
from learner.training.stage import TrainingResult, train
from learner.training.summary import TrainingSummary, summarise
from robot_profile import RobotProfile

PERCEPTIONS: Mapping[str, Callable[[str, RobotProfile | None, int, bool], SeenObjects]] = {
    "camera": camera_objects,  # the overhead camera's regions, as in the paper
    "onboard": outline_objects,  # the robot's own scans: each object's outline from a survey round it
}
"""Where the training objects' footprints come from (``csl train --perception``)."""


@dataclass(frozen=True)
class SimTraining:
    """One training run in the simulator: what perception saw, what was learned, its
    figures, and every measurement made (for a replay file)."""

    seen: SeenObjects
    result: TrainingResult
    summary: TrainingSummary
    source: RecordingSource
    grasp_search: GraspSearch | None = None  # without a teacher: how the grasps were found

    @property
    def robot_s(self) -> float:
        """The whole training's robot time: phases 1 and 2, and finding grasps if it did."""
        search = self.grasp_search
        return self.summary.total_s + (0.0 if search is None else search.grasping_s + search.moving_s)


def train_in_simulator(knowledge: Knowledge, profile: RobotProfile | None = None, seed: int = 0,
                       noise: bool = False, teacher: bool = True, perception: str = "camera") -> SimTraining:
    """Train on the catalogue's training objects (Table 3) as the robot of ``profile`` sees
    and senses it; moves are priced with the knowledge's move model. Without a
    ``teacher`` the catalogue's grasp labels are not used: each object's grasp is found
    by trying grasps on it first (``learner.training.grasps``), and training goes on with
    the grasps found. ``perception`` names how the objects are seen (:data:`PERCEPTIONS`)."""
    if perception not in PERCEPTIONS:
        raise ValueError(f"perception must be one of {', '.join(PERCEPTIONS)}, got {perception!r}")
    seen = PERCEPTIONS[perception]("training", profile, seed, noise)
    for o in seen.objects:
        if not knowledge.has_grasp(o.grasp):
            raise ValueError(f"simulator catalogue: object {o.object_id!r}: grasp {o.grasp!r} is not in "
                             f"{knowledge.source}")
    moves = ModelMoveCost(knowledge.move)
    search = None if teacher else find_grasps(seen.objects, knowledge,
                                              SimulatorGrasps(seed, profile, seen.axis_offsets_deg), moves)
    objects = seen.objects if search is None else search.objects
    source = RecordingSource(SimulatorSource(seed, noise, profile, seen.axis_offsets_deg))
    result = train(objects, knowledge, source, moves)
    return SimTraining(seen, result, summarise(result, objects, knowledge), source, search)


def ground_truth(descriptions: Sequence[ObjectDescription], seen: SeenObjects,
                 knowledge: Knowledge, summary: TrainingSummary,
                 profile: RobotProfile | None = None) -> FidelityReport:
    """Every value of ``descriptions`` against the simulator's exact value for that object,
    feature and position (noise off), at the training positions of ``summary``; a
    faithful training leaves no value off by more than its feature's expected error."""
    exact = SimulatorSource(noise=False, profile=profile, axis_offsets_deg=seen.axis_offsets_deg)
    return check_fidelity(descriptions, seen.objects, knowledge, summary.orientations_deg, summary.distances_in,
                          exact)
