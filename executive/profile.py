"""The learner's knowledge, taken from the robot profile.

The learner may import nothing of ours and reads no files, so the executive, which
composes the packages, adapts the one validated profile (``robot_profile``) into the
learner's input types. Only the parts the learner uses cross over: procedures, their
features and the ``[move]`` model; the ``[robot]`` table goes to the planner and the
simulator directly.
"""

from __future__ import annotations

from pathlib import Path

import robot_profile
from learner.knowledge import FeatureSpec, GraspingProcedure, Knowledge, MoveModel, SensingProcedure


def knowledge_of(profile: robot_profile.RobotProfile) -> Knowledge:
    """The learner's view of ``profile`` (its ``source`` names the file in messages)."""
    move = profile.move
    return Knowledge(
        sensing=tuple(_sensing(p) for p in profile.sensing),
        grasping=tuple(_grasping(g) for g in profile.grasping),
        move=MoveModel(move.seconds_per_inch, move.seconds_per_degree, move.overhead_s),
        source=profile.source,
    )


def load_knowledge(path: str | Path) -> Knowledge:
    """Read and validate a profile file and keep the learner's part of it."""
    return knowledge_of(robot_profile.load_profile(path))


def _sensing(proc: robot_profile.SensingProcedure) -> SensingProcedure:
    features = tuple(FeatureSpec(f.name, f.error, f.unit, f.binary, f.span, f.angular_of) for f in proc.features)
    return SensingProcedure(proc.name, proc.time_s, proc.range_in, features)


def _grasping(grasp: robot_profile.GraspingProcedure) -> GraspingProcedure:
    return GraspingProcedure(grasp.name, grasp.time_s, grasp.range_in, grasp.side_effect_penalty_s, grasp.verifiable)
