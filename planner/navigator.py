"""The planner as the executive uses it: one object that sees, plans and prices moves.

It keeps what stays valid while the world is unchanged. Scenes are cached on the
image's content (an identical image costs a hash). Everything built on the obstacles
(the vision map, the planner's roadmap and recent plans, the estimate mode's distance
fields) is cached on the obstacles alone: the robot is not an obstacle, so a new image
after a move reuses all of it, and only a changed world (an object pushed, knocked
over or picked up) builds a new map. Recent worlds are kept, so going back to one
reuses its map.

A moving obstacle the driver reported is drawn into the map with :meth:`Navigator.avoid`
until the next image or until cleared (docs/planner.md, "Moving obstacles").

Band images need nothing else; a real camera's images need a calibrated ``camera``
(docs/camera.md), given, or made from the first image when only the marker ``board``
is known (the in-process realistic simulator: no calibration step before the run).
"""

from __future__ import annotations

import logging
from dataclasses import dataclass

from camera_model.image import CameraImage
from planner.cache import LruCache
from planner.calibration import MarkerBoard
from planner.geometry import Pose
from planner.merging import flag_merged
from planner.move_cost import CostEstimator, MoveCost, arrived, price_plan
from planner.paths import OK, PathPlanner, PlanResult
from planner.positions import free_pose_for_position, position_of
from planner.vision import Region, Scene, look
from planner.roadmap import Roadmap
from planner.segmentation import Camera, calibrated_camera
from planner.vision_map import Disc, VisionMap, build_vision_map, map_key
from robot_profile import Robot

log = logging.getLogger(__name__)
NOTHING_OBSERVED = "no overhead image observed yet: call observe(image) first"
# A roadmap carried to a new map is re-checked every half cell along each edge, as the
# planner checks motions (the strict free space keeps a cell of margin, so no obstacle
# slips between samples), and kept when at least this share of its milestones survives.
ROADMAP_CHECK_STEP_CELLS = 0.5
ROADMAP_KEEP_FRACTION = 0.9


@dataclass(frozen=True, eq=False)
class _World:
    """Everything built on one set of obstacles."""

    map: VisionMap
    paths: PathPlanner
    costs: CostEstimator


class Navigator:
    """Vision, paths and move costs on the latest overhead image."""

    def __init__(self, robot: Robot, *, camera: Camera | None = None, board: MarkerBoard | None = None,
                 time_limit_s: float = 0.25, optimise_time_s: float = 0.5, spacing_in: float = 6.0,
                 worlds_kept: int = 4) -> None:
        """``camera``: the calibrated camera of real images (None: band images);
        ``board``: calibrate one from the first image instead (docs/camera.md)."""
        self.robot = robot
        self.camera = camera
        self._board = board
        self._time_limit_s = time_limit_s
        self._optimise_time_s = optimise_time_s
        self._spacing_in = spacing_in
        self._scenes: LruCache[Scene] = LruCache(worlds_kept)
        self._worlds: LruCache[_World] = LruCache(worlds_kept)
        self._scene: Scene | None = None
        self._current: _World | None = None
        self._avoided: tuple[Disc, ...] = ()

    def observe(self, image: CameraImage) -> Scene:
        """Look at a new overhead image; later calls plan on it. A region covering two
        objects the previous image saw apart is a cluster (:mod:`planner.merging`)."""
        image.check()
        if self.camera is None and self._board is not None:
            self.camera = calibrated_camera(image.pixels, self._board)
        seen = self._scenes.get_or_make(image.content_key(), lambda: look(image, self.camera))
        scene = flag_merged(self._scene, seen, self.robot.geometry.base_radius_in)
        log.debug("overhead image observed: %d object regions", len(scene.regions))
        self._scene, self._avoided = scene, ()
        self._rebuild()
        return scene

    def observe_scene(self, scene: Scene) -> Scene:
        """Take a scene another source made as the latest look; later calls plan on it.
        The onboard map's (``mapping.scene``): its regions are the candidates the scans
        tracked, each with the id of its track, so no merge is inferred here."""
        self._scene, self._avoided = scene, ()
        self._rebuild()
        return scene

    def avoid(self, discs: tuple[Disc, ...]) -> None:
        """Plan around ``discs`` (x, y, radius in inches: moving obstacles a driver
        reported) on the latest image's map as well, until the next image or until
        called with none. Each set of discs is a world of its own in the cache."""
        self.scene  # noqa: B018 (raises without an image)
        self._avoided = tuple(discs)
        self._rebuild()

    @property
    def avoided(self) -> tuple[Disc, ...]:
        """The discs drawn into the current map (none: the image alone)."""
        return self._avoided

    def _rebuild(self) -> None:
        scene, discs = self.scene, self._avoided
        key = map_key(scene, self.robot.geometry, discs)
        self._current = self._worlds.get_or_make(key, lambda: self._build(scene, discs))

    @property
    def scene(self) -> Scene:
        """The latest image's regions, robot pose and obstacle masks."""
        if self._scene is None:
            raise ValueError(NOTHING_OBSERVED)
        return self._scene

    @property
    def vision_map(self) -> VisionMap:
        """The latest image's inflated occupancy grid."""
        return self._world().map

    def pose_for(self, region: Region, distance_in: float, orientation_deg: float) -> Pose:
        """The base pose for a learner position of ``region`` (docs/conventions.md),
        moved within the range tolerance when an obstacle is in the way
        (:func:`~planner.positions.free_pose_for_position`)."""
        self._require_on_map(region)
        return free_pose_for_position(region, distance_in, orientation_deg, self.robot.geometry,
                                      self._world().map.is_free)

    def position_of(self, region: Region, pose: Pose) -> tuple[float, float]:
        """The learner position ``(distance_in, orientation_deg)`` of a robot pose."""
        return position_of(region, pose, self.robot.geometry)

    def plan(self, start: Pose, goal: Pose, *, optimise: bool = False,
             spacing_in: float | None = None) -> PlanResult:
        """A path for the driver from ``start`` to ``goal`` (see PathPlanner.plan)."""
        return _told(start, goal, self._world().paths.plan(start, goal, optimise=optimise, spacing_in=spacing_in))

    def plan_to(self, start: Pose, region: Region, distance_in: float, orientation_deg: float,
                *, optimise: bool = False) -> PlanResult:
        """A path to a learner position of ``region``."""
        return self.plan(start, self.pose_for(region, distance_in, orientation_deg), optimise=optimise)

    def move_cost(self, start: Pose, goal: Pose, *, exact: bool = False) -> MoveCost:
        """Seconds to move from ``start`` to ``goal``: estimated, or priced on a plan."""
        world = self._world()
        if not exact:
            return world.costs.estimate(start, goal)
        start.require_finite("start")
        goal.require_finite("goal")
        if arrived(start, goal):
            return MoveCost(0.0, 0.0, 0.0, True, OK)
        return price_plan(self.robot.motion, _told(start, goal, world.paths.plan(start, goal)))

    def position_cost(self, start: Pose, region: Region, distance_in: float, orientation_deg: float,
                      *, exact: bool = False) -> MoveCost:
        """Seconds to move from ``start`` to a learner position of ``region``."""
        return self.move_cost(start, self.pose_for(region, distance_in, orientation_deg), exact=exact)

    def _build(self, scene: Scene, discs: tuple[Disc, ...] = ()) -> _World:
        vision_map = build_vision_map(scene, self.robot.geometry, discs)
        paths = PathPlanner(vision_map, time_limit_s=self._time_limit_s,
                            optimise_time_s=self._optimise_time_s, spacing_in=self._spacing_in,
                            roadmap=self._reusable_roadmap(vision_map))
        return _World(vision_map, paths, CostEstimator(vision_map, self.robot.motion))

    def _reusable_roadmap(self, vision_map: VisionMap) -> Roadmap | None:
        """The current world's roadmap, pruned to what is still clear on the new map.

        Between two images the map barely changes (an object picked up leaves more free
        space; camera noise flickers a few edge cells), so nearly all of the old roadmap
        stays valid and pruning it costs milliseconds where growing one costs ~0.2 s.
        When much of it was lost (something big moved), a fresh one is grown instead.
        """
        old = self._current
        if old is None or old.paths.roadmap is None:
            return None
        if (old.map.free_strict.shape != vision_map.free_strict.shape
                or old.map.image.inches_per_pixel != vision_map.image.inches_per_pixel):
            return None
        roadmap = old.paths.roadmap
        kept = roadmap.pruned(vision_map.points_strictly_free, ROADMAP_CHECK_STEP_CELLS * vision_map.image.inches_per_pixel)
        return kept if len(kept) >= ROADMAP_KEEP_FRACTION * len(roadmap) else None

    def _world(self) -> _World:
        if self._current is None:
            raise ValueError(NOTHING_OBSERVED)
        return self._current

    def _require_on_map(self, region: Region) -> None:
        if not self._world().map.contains(*region.centroid):
            raise ValueError(f"target region at {region.centroid} lies outside the map")


def _told(start: Pose, goal: Pose, plan: PlanResult) -> PlanResult:
    """``plan``, told on the log (DEBUG, ``csl -vv``): each path planned for the driver."""
    if log.isEnabledFor(logging.DEBUG):
        found = (f"{len(plan.path or ())} waypoints, {plan.length_in:.1f} in, turning {plan.turning_deg:.1f}°"
                 if plan.found else f"no path: {plan.reason}")
        log.debug("path (%.1f, %.1f, %.1f°) to (%.1f, %.1f, %.1f°) by %s: %s", start.x_in, start.y_in,
                  start.heading_deg, goal.x_in, goal.y_in, goal.heading_deg, plan.planner, found)
    return plan
