"""planner: overhead vision, the vision map, OMPL paths and the move-cost heuristic.

Depends on numpy, OpenCV, OMPL and the robot profile (``robot_profile``: the body's
geometry and motion it plans for); knows nothing of the learner, the behaviours or the
driver (it has its own :class:`Pose`, which the executive converts; the overhead image
it reads is the driver's own, :class:`camera_model.image.CameraImage`). See
docs/planner.md.
"""

from planner.geometry import Pose
from planner.move_cost import CostEstimator, MoveCost, arrived, move_seconds, price_plan
from planner.navigator import Navigator
from planner.paths import PathPlanner, PlanResult
from planner.positions import face_distance_in, pose_for_position, position_of
from planner.vision import Region, Scene, look
from planner.vision_map import VisionMap, build_vision_map

__all__ = [
    "CostEstimator", "MoveCost", "Navigator", "PathPlanner", "PlanResult", "Pose", "Region",
    "Scene", "VisionMap", "arrived", "build_vision_map", "face_distance_in", "look", "move_seconds",
    "pose_for_position", "position_of", "price_plan",
]
