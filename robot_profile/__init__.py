"""robot_profile: the one validated reader of a robot profile TOML file.

A kit below the planner and the simulator, which take their typed parts from it
directly. Standard library only, plus :mod:`learner.knowledge`: the procedures, their
features and the ``[move]`` model are the learner's own frozen dataclasses, and this
reader builds them, so each is defined once and the learner gets its
:class:`~learner.knowledge.Knowledge` with nothing translated (``load_knowledge``, or
``RobotProfile.knowledge()``).

Why that way round: the learner imports nothing of ours (it is a library that serves
any robot through its knowledge input), so the types it computes with must be its
own; ``learner.knowledge`` is a module of plain dataclasses with no imports of ours,
so depending on it keeps this package free of cycles and of anything heavy
(docs/conventions.md, "Adding a robot constant"). Format: docs/knowledge-format.md.
"""

from robot_profile.model import SCANNER_DEFAULTS, Robot, RobotGeometry, RobotMotion, RobotProfile, ScannerSpec
from robot_profile.reader import DEFAULT_PROFILE, knowledge_from_dict, load_knowledge, load_profile, profile_from_dict
from robot_profile.stamp import ProfileStamp, profile_stamp

__all__ = [
    "DEFAULT_PROFILE", "SCANNER_DEFAULTS", "ProfileStamp", "Robot", "RobotGeometry", "RobotMotion", "RobotProfile",
    "ScannerSpec", "knowledge_from_dict",
    "load_knowledge", "load_profile", "profile_from_dict", "profile_stamp",
]
