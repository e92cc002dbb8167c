"""Onboard perception: the robot's own range scans instead of the ceiling camera.

The paper's closing step ("if the robot could determine sensing positions through an
onboard sensor, then CSL could eliminate the ceiling camera"), as one
:class:`~behaviours.perception.Perception` among two. Each look is a ``scan`` (the
driver's ``scan`` feature: a lidar, or HERO's sonar swept in place), and reading it:

1. the scan matcher aligns it to the map of the scans before it
   (:class:`mapping.ScanMatcher`): the corrected pose, heading and all, which the
   localisation decorator then takes for where the robot stands
   (:class:`behaviours.localisation.CameraLocalised`, given a heading);
2. the occupancy grid integrates it at that pose (:class:`mapping.OccupancyGrid`);
3. the candidate finder tracks object-sized returns that are not the home's structure
   (:class:`mapping.CandidateFinder`); each candidate kept is a region, outlined from
   the scans near it (:func:`mapping.scene.candidate_region`);
4. the scene (regions, the corrected pose, the grid as obstacle masks with unknown
   space blocked: :func:`mapping.scene.map_scene`) becomes the planner's map
   (:meth:`planner.Navigator.observe_scene`): the OMPL planner plans on it as on the
   vision map.

Where to look from next is the exploration rule's goal (:func:`mapping.next_goal`:
the frontier whose viewing pose is cheapest to reach for its size), priced by the
planner's move-cost estimate on the current map; the robot drives to it in legs with a
look after each (``behaviours.exploration``), keeping it while the rule still offers a
view near it (else it would turn round after every leg as the costs shift); a view
the robot failed to reach is not offered again. The map's frame is the odometry's at the first scan.

A candidate's region is outlined again each time it is seen again, until it was seen
``settled_seen`` times; then it stays as it is. The checks that look again at an object
(before a sensing or a grasp, after a failed grasp) compare its region with the one it
was located by, at a camera's precision (``behaviours.sameness``: an inch, a quarter
of the area); an outline still being refined as the robot comes closer would read as
the object pushed or changed. Each look also fits every region to the returns of that
scan near it (:func:`mapping.scene.refit`), so a push shows as the region moved, its
size kept, as the camera would see it. A place the latest scan looks through is not there now,
whatever the map still holds (:func:`mapping.scene.seen_through`): the object was
taken or moved, and the checks see it so. When the scan still sees the candidate
itself, only not where its kept region lies (a failed grasp knocked it over, or it
rolled), the region is outlined anew from that scan on and settles again: a kept
region left in place would have made a knocked-over object read as gone.

The matcher must see each scan in the driver's own frame (it applies the odometry's
step between scans to its last corrected pose), so the perception scans through the
driver *below* the localisation decorator.
"""

from __future__ import annotations

import math
from concurrent.futures import Future
import dataclasses
from dataclasses import dataclass

import cv2
import numpy as np

from hero_driver.interface import RangeScan, Scanner
from mapping import CandidateFinder, CandidateSettings, ExplorationSettings, OccupancyGrid, ScanMatcher
from mapping.exploration import exploration_goals
from mapping.candidates import Candidate
from mapping.scan import PlanarScan
from mapping.scene import bridged, candidate_region, map_scene, refit, seen_through, with_keep_out
from planner import Navigator, Pose, Region, Scene
from planner.paths import ESCAPE_LIMIT_IN


ONBOARD_CANDIDATES = CandidateSettings(range_sigma_in=1.0)
"""The candidate rules for a home: a range finder's error grows with the range (the
simulator's ``paper`` preset: 1 % of it, an inch at 100 in), and the rules' bands are
multiples of it; at the default half inch, far walls broke into object-sized runs
(seen on the simulated apartments: dozens of false candidates along a bed's side)."""


BUMP_RADIUS_IN = 3.0
"""A place the bumper met where the map holds nothing is kept out of the plans from then
on (:meth:`OnboardPerception.bumped`): a disc this wide, just ahead of the base (the
base stops a tenth of an inch short of what it met, heading where it drove). A planar
scan misses what stands above its plane: a table's top whose legs were not all seen
yet, a shelf's overhang. Without it the planner, seeing free floor, sent every move
into the same table edge (seen on the simulated apartment-2 under the ``paper``
preset: every move of the episode's last thirteen objects ended collided where it
began, and each such grasp move counted as a failed grasp)."""
BUMP_CLEAR_IN = 6.0
"""A bump this near an object's region (or an occupied cell) is not kept: the map
explains it (the object itself, or an error in where the robot stands), and a disc
there would close the positions the object is handled from."""

AHEAD_DEG = 2.0
"""Beams this close to the heading measure what lies straight ahead: at a procedure's
range the object's near face fills them (the move ends facing the object)."""


@dataclass(frozen=True)
class OnboardSettings:
    """The onboard map's extent and resolution (inches), and how far a refused view reaches."""

    half_extent_in: float = 720.0  # the map reaches this far from the first scan each way (a 120 ft square)
    inches_per_cell: float = 1.0
    outline_reach_in: float = 60.0  # scans taken farther than this from a candidate do not outline it
    outline_views: int = 12  # the latest views that saw a candidate, for its outline
    refused_within_in: float = 12.0  # a view this close to one the robot failed to reach is not offered
    settled_seen: int = 6  # a candidate seen this often keeps the region it has (module docstring)
    keep_goal_in: float = 24.0  # the view driven to is kept while the exploration still offers one this near it
    leg_in: float = 60.0  # a move drives this far at most between two scans (behaviours.legs): a step the matcher corrects surely

    def __post_init__(self) -> None:
        for name in ("half_extent_in", "inches_per_cell", "outline_reach_in", "refused_within_in", "keep_goal_in",
                     "leg_in"):
            value = getattr(self, name)
            if not (math.isfinite(value) and value > 0):
                raise ValueError(f"onboard setting {name} must be positive, got {value}")
        if self.settled_seen < 1:
            raise ValueError(f"onboard setting settled_seen must be at least 1, got {self.settled_seen}")
        if self.outline_views < 1:
            raise ValueError(f"onboard setting outline_views must be at least 1, got {self.outline_views}")


def planar_scan(scan: RangeScan) -> PlanarScan:
    """The driver's scan as the mapping takes it (angles in radians, no echo as ``inf``)."""
    ranges = np.array([math.inf if r is None else r for r in scan.ranges_in], dtype=float)
    return PlanarScan(np.radians(np.asarray(scan.angles_deg, dtype=float)), ranges, scan.pose.x_in,
                      scan.pose.y_in, scan.pose.heading_deg, scan.clock_s, scan.range_max_in)


@dataclass(frozen=True, eq=False)
class _View:
    scan: PlanarScan
    pose: Pose
    returns: np.ndarray  # world inches, Nx2


class OnboardPerception:
    """Looks are scans; the scene is the map they built (the module docstring)."""

    verb = "scan"
    corrects_heading = True
    measures_ahead = True

    def __init__(self, scanner: Scanner, navigator: Navigator, settings: OnboardSettings | None = None,
                 candidates: CandidateSettings = ONBOARD_CANDIDATES,
                 exploration: ExplorationSettings = ExplorationSettings()) -> None:
        """``scanner``: the driver in its own frame (below the localisation decorator)."""
        self._scanner, self._navigator = scanner, navigator
        self.settings, self.exploration = settings or OnboardSettings(), exploration
        self.matcher = ScanMatcher()
        self.finder = CandidateFinder(candidates)
        self.grid: OccupancyGrid | None = None
        self._bridged: OccupancyGrid | None = None  # the grid with the gaps between beams closed
        self.poses: list[tuple[float, Pose, Pose]] = []  # (clock, reported, corrected) of each scan
        self._views: list[_View] = []
        self._regions: dict[int, tuple[int, Region]] = {}  # candidate id -> (times seen, its region)
        self._since: dict[int, tuple[float, int]] = {}  # candidate id -> (clock, times seen) its outline starts at
        self._refused: list[Pose] = []
        self._goal: Pose | None = None  # the view being driven to
        self._candidates: tuple[Candidate, ...] = ()  # those the latest scan's reading kept
        self._bumps: list[np.ndarray] = []  # places the bumper met (polygons): kept out of the plans
        self.stranded: str | None = None  # behaviours.perception.Perception.stranded
        self._given: Scene | None = None  # the scene the navigator plans on

    @property
    def leg_in(self) -> float:
        return self.settings.leg_in

    def look(self) -> Future[RangeScan]:
        return self._scanner.scan()

    def scene(self, observation: RangeScan) -> Scene:
        scene = self._given = self._read(observation)
        self._navigator.observe_scene(scene)
        return scene

    def glance(self, observation: RangeScan) -> Scene:
        return self._read(observation)  # the map takes every scan: what the planner plans on is unchanged

    def distance_ahead(self, observation: RangeScan) -> float | None:
        """The nearest return within :data:`AHEAD_DEG` of the heading, less the sonar's
        offset ahead of the base centre the scan ranges from."""
        scan = planar_scan(observation)
        ahead = scan.ranges_in[scan.returned & (np.abs(scan.angles_rad) <= math.radians(AHEAD_DEG))]
        if not len(ahead):
            return None
        return float(ahead.min()) - self._navigator.robot.geometry.sensor_offset_in

    def next_view(self, robot: Pose) -> Pose | None:
        if self._bridged is None:
            return None
        s = self.settings

        def cost(pose: Pose) -> float:
            if any(math.hypot(pose.x_in - r.x_in, pose.y_in - r.y_in) <= s.refused_within_in for r in self._refused):
                return math.inf
            return self._navigator.move_cost(robot, pose).seconds

        goals = exploration_goals(self._bridged, robot, self._candidates, cost, self.exploration)
        self.stranded = None if goals else self._stranded(robot)
        kept = self._goal
        if kept is not None and math.hypot(kept.x_in - robot.x_in, kept.y_in - robot.y_in) <= self.exploration.arrived_in:
            kept = None  # reached: choose anew
        if kept is not None and any(math.hypot(g.pose.x_in - kept.x_in, g.pose.y_in - kept.y_in) <= s.keep_goal_in
                                    for g in goals):
            return kept  # still worth it: on toward it (a view is reached in legs, a look after each)
        self._goal = goals[0].pose if goals else None
        return self._goal

    def unreachable(self, view: Pose) -> None:
        self._refused.append(view)
        self._goal = None

    def _stranded(self, robot: Pose) -> str | None:
        """Why no view can be reached when the robot itself can go nowhere: it stands
        in an obstacle of its own map, farther in than a plan may start
        (``planner.paths.ESCAPE_LIMIT_IN``). Then every view is priced unreachable, and
        "the home is mapped" would be a claim nobody checked."""
        floor = self._navigator.vision_map
        if floor.nearest_free(robot.x_in, robot.y_in, ESCAPE_LIMIT_IN) is not None:
            return None
        return (f"no view can be reached: the robot at ({robot.x_in:.0f}, {robot.y_in:.0f}) stands in an obstacle "
                f"of its map, more than {ESCAPE_LIMIT_IN:g} in from free floor")

    def bumped(self, pose: Pose) -> tuple[float, float] | None:
        """The base stopped collided at ``pose``: unless the map explains it
        (:data:`BUMP_CLEAR_IN`), the place just ahead is kept out of the plans from now on,
        at once (:data:`BUMP_RADIUS_IN` says why); that place, or None."""
        ahead = self._navigator.robot.geometry.base_radius_in + BUMP_RADIUS_IN
        h = math.radians(pose.heading_deg)
        x, y = pose.x_in + ahead * math.cos(h), pose.y_in + ahead * math.sin(h)
        if self._explained(x, y):
            return None
        angles = np.linspace(0.0, 2.0 * math.pi, 16, endpoint=False)
        disc = np.column_stack([x + BUMP_RADIUS_IN * np.cos(angles), y + BUMP_RADIUS_IN * np.sin(angles)])
        self._bumps.append(disc)
        if self._given is not None:
            self._given = with_keep_out(self._given, [disc])
            self._navigator.observe_scene(self._given)
        return (x, y)

    def _explained(self, x: float, y: float) -> bool:
        """Whether an object's region, or an occupied cell of the map, lies within
        :data:`BUMP_CLEAR_IN` of the point ``(x, y)``."""
        reach = BUMP_CLEAR_IN
        if self._given is not None and any(
                cv2.pointPolygonTest(r.polygon_array().astype(np.float32), (x, y), True) >= -reach
                for r in self._given.regions):
            return True
        if self.grid is None:
            return False
        return bool(self.grid.occupied_within(x, y, reach))

    def _keep_out(self) -> list[np.ndarray]:
        """What the base cannot enter though the scans see nothing there: each table's
        top (:meth:`mapping.CandidateFinder.table_tops`) and each bump."""
        return [*self.finder.table_tops(), *self._bumps]

    def _read(self, observation: RangeScan) -> Scene:
        scan = planar_scan(observation)
        correction = self.matcher.update(scan)
        pose = correction.pose
        reported = Pose(scan.x_in, scan.y_in, scan.heading_deg)
        self.poses.append((scan.stamp_s, reported, pose))
        if self.grid is None:
            e = self.settings.half_extent_in
            self.grid = OccupancyGrid(pose.x_in - e, pose.y_in - e, pose.x_in + e, pose.y_in + e,
                                      self.settings.inches_per_cell)
        self.grid.integrate(scan, pose)
        self.finder.update(scan, pose)
        self._views.append(_View(scan, pose, scan.world_points(pose.x_in, pose.y_in, pose.heading_deg)))
        loose = self._views[-1].returns
        if len(loose) and len(self.finder.structure):
            loose = loose[~self.finder.structure.within(loose)]  # the returns off the home's structure
        regions = []
        self._candidates = self.finder.candidates(self.grid)
        for candidate in self._candidates:
            region = self._region(candidate)
            if seen_through(region, scan, pose):
                if candidate.last_seen_s < scan.stamp_s:
                    continue  # the map is slow to forget: not there now
                # still seen, but not where its kept region is (knocked over, rolled): outlined anew from now on
                self._since[candidate.id] = (scan.stamp_s, candidate.times_seen - 1)
                self._regions.pop(candidate.id, None)
                region = self._region(candidate)
                if seen_through(region, scan, pose):
                    continue
            moved = refit(region, loose)
            if moved is not region:  # pushed: it stays where the scan saw it
                self._regions[candidate.id] = (self._regions[candidate.id][0], moved)
            regions.append(moved)
        self._bridged = bridged(self.grid)
        return map_scene(self._bridged, tuple(regions), pose, keep_out=self._keep_out())

    def _region(self, candidate: Candidate) -> Region:
        """The candidate's region, outlined again only when it was seen again, and no more
        once it was seen ``settled_seen`` times (the module docstring); from the scans
        since it was last found changed (:meth:`_read`), when it was."""
        kept = self._regions.get(candidate.id)
        since_s, seen_before = self._since.get(candidate.id, (-math.inf, 0))
        if kept is not None and (kept[0] == candidate.times_seen
                                 or kept[0] - seen_before >= self.settings.settled_seen):
            return kept[1]
        s = self.settings
        centre = np.array([candidate.x_in, candidate.y_in])
        near = [v for v in self._views
                if v.scan.stamp_s >= since_s
                and math.hypot(v.pose.x_in - centre[0], v.pose.y_in - centre[1]) <= s.outline_reach_in
                and len(v.returns) and float(np.min(np.hypot(*(v.returns - centre).T))) <= 12.0]
        views = [(v.scan, v.pose) for v in near[-s.outline_views:]]
        if candidate.id in self._since:
            candidate = self._seen_since(candidate, near)
        region = candidate_region(candidate, views, self.finder.settings.range_sigma_in)
        self._regions[candidate.id] = (candidate.times_seen, region)
        return region

    def _seen_since(self, candidate: Candidate, views: list[_View]) -> Candidate:
        """``candidate`` as ``views`` (those since it changed) see it: its returns in them
        off the home's structure, within an object's reach of it, for the outline to fall
        back on when the few views since do not fit one (the track's own outline holds the
        returns from before the change as well)."""
        if not views:
            return candidate
        points = np.concatenate([v.returns for v in views])
        points = points[np.hypot(*(points - (candidate.x_in, candidate.y_in)).T) <= self.finder.settings.max_extent_in]
        if len(points) and len(self.finder.structure):
            points = points[~self.finder.structure.within(points)]
        if len(points) < self.finder.settings.min_outline_points:
            return candidate
        x, y = points.mean(axis=0)
        return dataclasses.replace(candidate, x_in=float(x), y_in=float(y),
                                   outline=tuple((float(a), float(b)) for a, b in points))
