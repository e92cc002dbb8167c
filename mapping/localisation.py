"""Odometry corrected by scan matching: each scan aligned to the map of the scans before it.

small_gicp's VGICP (voxelised generalised ICP) aligns the scan's returns to a Gaussian
voxel map of every earlier scan at its corrected pose, starting from the reported
odometry's step applied to the last corrected pose. The map is the whole home, never
pruned: when the robot comes back to a room it matches against what it saw there before,
which closes the loop without a pose graph (docs/mapping.md has the measurements that
chose this, and why GTSAM is left out).

The library is 3-D and a planar scan is degenerate for it: a wall seen in one plane is a
line of points, whose fitted covariance has no preferred normal, and small_gicp's
regulariser then takes the vertical for it (point-to-plane ICP finds no constraint at
all; GICP becomes point-to-point). So each return is copied at a few heights inside one
layer of voxels (:attr:`MatcherSettings.layers_z_in`): a wall becomes a strip of plane,
its normal is horizontal, and each voxel holds a piece of that plane. The 6-D result is
cut back to the floor (x, y, heading); docs/mapping.md has the measurements.

An alignment the matcher cannot vouch for — too few returns, no convergence, too few
of the returns matched to the map, or a correction larger than the odometry could have
drifted in one step — is not used: the pose is the odometry's step from the last
corrected pose, and the correction says so (``matched`` False). The scan is then not
added to the map either, so a bad pose does not spoil it.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
import small_gicp

from mapping.scan import PlanarScan
from planner.geometry import Pose


# small_gicp drops voxels no scan has touched for its LRU horizon (100 scans by default).
NEVER_FORGET = 10**9


@dataclass(frozen=True)
class Correction:
    """The corrected pose for one scan, and what the odometry got wrong.

    ``drift_*`` is the reported pose less the corrected one (world inches, degrees in
    (-180, 180]): how far the odometry has wandered since the start. ``matched`` is True
    when the scan was aligned to the map (or, the first with returns, started it) and
    added to it; False when it could not be, and the pose is dead reckoned from the last
    corrected one.
    """

    pose: Pose
    drift_x_in: float
    drift_y_in: float
    drift_heading_deg: float
    matched: bool
    inliers: int
    stamp_s: float


@dataclass(frozen=True)
class MatcherSettings:
    """How scans are thinned and matched (inches)."""

    voxel_in: float = 8.0  # the map's voxels: each a piece of wall, its Gaussian fitted to a few dozen returns
    downsample_in: float = 1.0  # returns closer than this are merged
    neighbours: int = 10  # returns used for each one's local covariance
    max_correspondence_in: float = 12.0  # farther than this from the map is not a match
    max_iterations: int = 100  # a turn of 15° or so takes about 40
    layers_z_in: tuple[float, ...] = (2.0, 4.0, 6.0)  # copies of the scan, all within one voxel layer
    min_points: int = 20  # fewer returns than this: not matched
    min_inlier_share: float = 0.3  # of the scan's (thinned) returns matched to the map
    max_step_correction_in: float = 12.0  # a correction beyond these is a mismatch
    max_step_correction_deg: float = 15.0

    def __post_init__(self) -> None:
        if not (self.voxel_in > 0 and self.downsample_in > 0 and self.max_correspondence_in > 0):
            raise ValueError("matcher voxel_in, downsample_in and max_correspondence_in must be positive")
        if not self.layers_z_in or not all(0.0 <= z < self.voxel_in for z in self.layers_z_in):
            raise ValueError(f"matcher layers_z_in must be heights in [0, voxel_in={self.voxel_in}), "
                             f"got {self.layers_z_in}")


def _transform(x_in: float, y_in: float, heading_rad: float) -> np.ndarray:
    c, s = math.cos(heading_rad), math.sin(heading_rad)
    t = np.eye(4)
    t[:2, :2] = [[c, -s], [s, c]]
    t[:2, 3] = (x_in, y_in)
    return t


def _of_pose(pose: Pose) -> np.ndarray:
    return _transform(pose.x_in, pose.y_in, math.radians(pose.heading_deg))


def _floor(t: np.ndarray) -> tuple[float, float, float]:
    """x, y, heading (rad) of a 3-D transform: its motion on the floor."""
    return float(t[0, 3]), float(t[1, 3]), math.atan2(t[1, 0], t[0, 0])


def _wrap_deg(angle: float) -> float:
    return -math.remainder(-angle, 360.0)  # in (-180, 180]


class ScanMatcher:
    """Corrects the robot's reported poses, one scan at a time, in the order taken."""

    def __init__(self, settings: MatcherSettings = MatcherSettings()) -> None:
        self.settings = settings
        self._map = small_gicp.GaussianVoxelMap(settings.voxel_in)
        self._map.set_lru(horizon=NEVER_FORGET, clear_cycle=NEVER_FORGET)  # the whole home, not a local map
        self._last: tuple[np.ndarray, np.ndarray] | None = None  # (reported, corrected) at the last scan

    def update(self, scan: PlanarScan) -> Correction:
        """The corrected pose of ``scan``, which is added to the map when matched.

        The first scan with returns is taken as right: the map's frame is the odometry's
        at the start.
        """
        reported = _transform(scan.x_in, scan.y_in, math.radians(scan.heading_deg))
        points = scan.points()
        cloud = None
        if len(points) >= self.settings.min_points:
            layers = [np.column_stack([points, np.full(len(points), z)]) for z in self.settings.layers_z_in]
            cloud, _ = small_gicp.preprocess_points(np.vstack(layers),
                                                    downsampling_resolution=self.settings.downsample_in,
                                                    num_neighbors=self.settings.neighbours)
        guess = reported
        if self._last is not None:
            previous_reported, previous_corrected = self._last
            guess = previous_corrected @ np.linalg.inv(previous_reported) @ reported
        if cloud is None:
            corrected, matched, inliers = guess, False, 0
        elif self._map.size() == 0:
            corrected, matched, inliers = guess, True, 0  # the first scan with returns starts the map
        else:
            corrected, matched, inliers = self._align(guess, cloud)
        if matched:
            self._map.insert(cloud, corrected)
        self._last = (reported, corrected)
        x, y, heading = _floor(corrected)
        pose = Pose(x, y, math.degrees(heading))
        return Correction(pose, scan.x_in - x, scan.y_in - y, _wrap_deg(scan.heading_deg - pose.heading_deg),
                          matched, inliers, scan.stamp_s)

    def _align(self, guess: np.ndarray, cloud: small_gicp.PointCloud) -> tuple[np.ndarray, bool, int]:
        """The aligned pose (on the floor), whether it is to be trusted, and its inliers;
        the guess itself when it is not."""
        s = self.settings
        result = small_gicp.align(self._map, cloud, init_T_target_source=guess,
                                  max_correspondence_distance=s.max_correspondence_in,
                                  max_iterations=s.max_iterations)
        x, y, heading = _floor(result.T_target_source)
        gx, gy, gheading = _floor(guess)
        plausible = (result.num_inliers >= s.min_inlier_share * cloud.size()
                     and math.hypot(x - gx, y - gy) <= s.max_step_correction_in
                     and abs(math.degrees(math.remainder(heading - gheading, 2 * math.pi))) <= s.max_step_correction_deg)
        if not plausible:
            return guess, False, int(result.num_inliers)
        return _transform(x, y, heading), True, int(result.num_inliers)
