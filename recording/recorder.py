"""The recorder: one Foxglove channel per topic of :mod:`recording.topics`,
fed from the driver's verbs, the episode log and the tree's ticks (as text and as data,
:mod:`recording.tree_nodes`), stamped in robot time.

Every message is stamped with the robot's clock (nanoseconds of robot time since the
driver's reset), never the wall clock, so two runs of one seed give the same file.
Messages logged at the same robot instant (ticks while nothing moved) are spaced 1 µs
apart so that readers replay them in the order they happened.
"""

from __future__ import annotations

import json
import math
import threading
from collections.abc import Sequence

import foxglove
import py_trees
from foxglove.channels import (FrameTransformChannel, GridChannel, LaserScanChannel, PoseInFrameChannel,
                               RawImageChannel, SceneUpdateChannel)

from camera_model.image import CameraImage
from recording import scene
from recording.status import status_tree
from recording.topics import BODY, CAMERA, EVENTS, MAP, NODES, OBJECTS, PATHS, POSE, SONAR, STATUS, TF, Topic
from recording.tree_nodes import SCHEMA as NODES_SCHEMA
from recording.tree_nodes import BlackboardChanges, tree_message
from hero_driver.interface import MoveResult, RobotState, SenseResult
from hero_driver.interface import Pose as RobotPose
from robot_profile.model import RobotGeometry

_TIE_NS = 1_000  # 1 µs between messages of one robot instant

STATUS_SCHEMA = {
    "title": STATUS.schema, "type": "object",
    "properties": {"tick": {"type": "integer"}, "status": {"type": "string", "description": "the root's status"},
                   "tip": {"type": "string", "description": "the behaviour the tick ended in"},
                   "tree": {"type": "string", "description": "py_trees.display.unicode_tree(show_status=True)"}},
    "required": ["tick", "status", "tip", "tree"]}
EVENT_SCHEMA = {
    "title": EVENTS.schema, "type": "object",
    "properties": {"tick": {"type": "integer"}, "event": {"type": "string"}, "object": {"type": "integer"}},
    "required": ["tick", "event"]}


def _channels(context: foxglove.Context) -> dict[Topic, object]:
    typed = {TF: FrameTransformChannel, POSE: PoseInFrameChannel, BODY: SceneUpdateChannel, PATHS: SceneUpdateChannel,
             SONAR: LaserScanChannel, CAMERA: RawImageChannel, MAP: GridChannel, OBJECTS: SceneUpdateChannel}
    out: dict[Topic, object] = {topic: cls(topic.name, context=context) for topic, cls in typed.items()}
    out[STATUS] = foxglove.Channel(STATUS.name, schema=STATUS_SCHEMA, context=context)
    out[NODES] = foxglove.Channel(NODES.name, schema=NODES_SCHEMA, context=context)
    out[EVENTS] = foxglove.Channel(EVENTS.name, schema=EVENT_SCHEMA, context=context)
    return out


class Recorder:
    """Writes what happened to the channels of one Foxglove context (its sinks, an MCAP
    file or a WebSocket server, are the session's). Safe to call from the driver's reply
    threads and the tick thread alike."""

    def __init__(self, context: foxglove.Context, geometry: RobotGeometry) -> None:
        self.geometry = geometry
        self._channels = _channels(context)
        self._lock = threading.Lock()
        self._last_ns = -_TIE_NS
        self._pose: RobotPose | None = None
        self._moves = 0
        self._blackboard = BlackboardChanges()

    def watch_blackboard(self, prefix: str) -> None:
        """Send the changes of the blackboard keys under ``prefix`` only (one robot's
        namespace; every key until told)."""
        self._blackboard = BlackboardChanges(prefix)

    def _at(self, clock_s: float) -> int:
        """The stamp for robot time ``clock_s``: never before the last one."""
        return self._after(round(clock_s * 1e9))

    def _after(self, ns: int) -> int:
        """``ns``, or just after the last stamp when that is later."""
        self._last_ns = max(ns, self._last_ns + _TIE_NS)
        return self._last_ns

    def _log(self, topic: Topic, message: object, ns: int) -> None:
        self._channels[topic].log(message, log_time=ns)  # type: ignore[attr-defined]

    def _place(self, pose: RobotPose, ns: int) -> None:
        self._log(TF, scene.base_transform(pose, ns), ns)
        self._log(POSE, scene.base_pose(pose, ns), ns)
        self._pose = pose

    def state(self, state: RobotState) -> None:
        """The robot where the driver says it is; the body is drawn with the first."""
        with self._lock:
            ns = self._at(state.clock_s)
            if self._pose is None:
                self._log(BODY, scene.body(self.geometry, ns), ns)
            if state.pose != self._pose:
                self._place(state.pose, ns)

    def camera(self, image: CameraImage, clock_s: float) -> None:
        with self._lock:
            ns = self._at(clock_s)
            self._log(CAMERA, scene.raw_image(image, ns), ns)
            self._log(MAP, scene.floor_map(image, ns), ns)

    def move(self, origin: RobotPose, waypoints: Sequence[RobotPose], result: MoveResult, began_s: float) -> None:
        """A finished move: the path as planned, then the base along it over the move's
        robot time (spread by distance; turning and centring are not separated out)."""
        with self._lock:
            self._moves += 1
            start_ns = self._at(began_s)
            self._log(PATHS, scene.planned_path(self._moves, origin, waypoints, result.pose, result.collided,
                                                self.geometry, start_ns), start_ns)
            points = [origin, *waypoints]
            steps = [math.dist((a.x_in, a.y_in), (b.x_in, b.y_in)) for a, b in zip(points, points[1:])]
            total = sum(steps) or 1.0
            span = max(round(result.duration_s * 1e9), 0)
            along = 0.0
            for waypoint, step in zip(waypoints[:-1], steps):
                along += step
                self._place(waypoint, self._after(start_ns + round(span * along / total)))
            self._place(result.pose, self._after(start_ns + span))

    def sense(self, pose: RobotPose, result: SenseResult, began_s: float) -> None:
        with self._lock:
            ns = self._at(began_s + result.duration_s)
            self._log(SONAR, scene.sonar_ray(pose, result.distance_in, self.geometry, ns), ns)

    def event(self, record: dict[str, object], clock_s: float) -> None:
        """One episode-log event; a ``located`` one also marks the regions found."""
        with self._lock:
            ns = self._at(clock_s)
            self._log(EVENTS, json.dumps(record, ensure_ascii=False, allow_nan=False), ns)
            regions = record.get("regions")
            if record.get("event") == "located" and isinstance(regions, list) and regions:
                self._log(OBJECTS, scene.located(regions, ns), ns)

    def handled(self, index: int, polygon: Sequence[tuple[float, float]], label: str, grasp: str | None,
                outcome: str | None, clock_s: float) -> None:
        with self._lock:
            ns = self._at(clock_s)
            self._log(OBJECTS, scene.handled(index, polygon, label, grasp, outcome, ns), ns)

    def tick(self, tick: int, root: py_trees.behaviour.Behaviour, clock_s: float) -> None:
        with self._lock:
            ns = self._at(clock_s)
            tip = root.tip()
            message = {"tick": tick, "status": root.status.value, "tip": tip.name if tip is not None else "",
                       "tree": status_tree(root)}
            self._log(STATUS, json.dumps(message, ensure_ascii=False), ns)
            self._log(NODES, json.dumps(tree_message(tick, root, self._blackboard), ensure_ascii=False,
                                        allow_nan=False), ns)
