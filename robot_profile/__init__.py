"""robot_profile: the one validated reader of a robot profile TOML file.

A leaf package (standard library only, imports nothing of this project): the planner
and the simulator take their typed parts from it directly; the learner gets its
:class:`~learner.knowledge.Knowledge` through the executive's adaptor
(``executive.profile``), since the learner may import nothing of ours. Format:
docs/knowledge-format.md.
"""

from robot_profile.model import (
    FeatureSpec, GraspingProcedure, MoveModel, Robot, RobotGeometry, RobotMotion, RobotProfile, SensingProcedure,
)
from robot_profile.reader import DEFAULT_PROFILE, load_profile, profile_from_dict
from robot_profile.stamp import ProfileStamp, profile_stamp

__all__ = [
    "DEFAULT_PROFILE", "FeatureSpec", "GraspingProcedure", "MoveModel", "Robot", "RobotGeometry", "RobotMotion",
    "ProfileStamp", "RobotProfile", "SensingProcedure", "load_profile", "profile_from_dict", "profile_stamp",
]
