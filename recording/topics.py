"""The recording's channels: topic, schema and what each carries (docs/recording.md
prints this table; ``csl log`` reads :data:`EVENTS` back). No Foxglove import."""

from __future__ import annotations

from dataclasses import dataclass

WORLD_FRAME = "world"  # x right, y up, as docs/conventions.md; Foxglove's unit, metres
BASE_FRAME = "base_link"  # the base centre, x along the heading
METRES_PER_INCH = 0.0254


@dataclass(frozen=True)
class Topic:
    """One channel of a recording."""

    name: str
    schema: str
    carries: str


TF = Topic("/tf", "foxglove.FrameTransform", "world → base_link at every robot state, along each move's waypoints")
POSE = Topic("/robot/pose", "foxglove.PoseInFrame", "the base's pose in the world frame, with the same times")
BODY = Topic("/robot/body", "foxglove.SceneUpdate", "the base's footprint disc and heading arrow, locked to base_link")
PATHS = Topic("/planner/paths", "foxglove.SceneUpdate",
              "every move's waypoints as planned (a line from where the move began), its order number, "
              "and the base's footprint where it stopped")
SONAR = Topic("/sonar", "foxglove.LaserScan", "each sensing procedure's sonar distance as a ray from the wrist")
CAMERA = Topic("/camera/overhead", "foxglove.RawImage", "every overhead image as taken (mono8, fish-eye if any)")
MAP = Topic("/map", "foxglove.Grid", "the overhead image undistorted and laid on the floor (intensity, uint8)")
OBJECTS = Topic("/objects", "foxglove.SceneUpdate",
                "objects as located (a marker at each centroid), then each outline with its grasp and outcome")
STATUS = Topic("/behaviour_tree/status", "csl.BehaviourTreeStatus",
               "per tick: py_trees' unicode tree with every behaviour's status, the tip and the root's status")
NODES = Topic("/behaviour_tree/nodes", "csl.BehaviourTreeNodes",
              "per tick: every behaviour's id, parent, name, kind, status and feedback, and the blackboard keys "
              "that changed")
EVENTS = Topic("/csl/events", "csl.EpisodeEvent", "the episode log's events, one JSON message each (as episode.jsonl)")

ALL = (TF, POSE, BODY, PATHS, SONAR, CAMERA, MAP, OBJECTS, STATUS, NODES, EVENTS)
