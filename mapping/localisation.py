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

VGICP's 8 in voxels make it robust to the odometry's heading error (a few degrees per
step, feet at the far wall) but not exact: a voxel holding a wall's end, a table leg or
an object beside a wall has its Gaussian off the surface, and each scan's bias stays in
the map. And no point-based matcher tells the two faces of a wall apart: entering a room
whose wall the map knows only from the other side, the room's face is matched to the far
face, a wall's thickness off (docs/mapping.md, "Refining on the floor"). So the VGICP
result is refined on the floor (:func:`_refine`): each return is matched to the nearest
map return *seen from the same side* (their surface normals, each turned towards the
sensor that saw it, agree), point to line, with a Huber kernel. The refined pose and the
odometry's prediction are then weighed by their information (:func:`_with_odometry`):
where the scan leaves a direction unconstrained (along a bare corridor) the odometry
holds it; elsewhere the returns outweigh it.

An alignment the matcher cannot vouch for — too few returns, too few of them matched to
the map, or a correction larger than the odometry could have drifted in one step — is not
used: the pose is the odometry's step from the last corrected pose, and the correction
says so (``matched`` False). The scan is then not added to the map either, so a bad pose
does not spoil it. Too few matched is not enough to refuse a placing the odometry's own
step vouches for (within its uncertainty, :attr:`MatcherSettings.odometry_vouches_chi2`)
when some of the scan is matched: a scan taken in a doorway sees mostly the room the map
does not know yet, and refused, it would keep that room out of the map, and every scan
after it there as well (docs/mapping.md, "Exploration time").

Such a scan, and one placed with less than :attr:`MatcherSettings.reset_inlier_share` of
its returns matched, is aligned once more from the reported pose as it is: the
odometry may have been reset (at the dock the base knows exactly where it stands, in the
frame it started in, which is the map's), and then the step across the reset carries all
the drift from before it, beyond any one step's correction; dead reckoned from there,
every later scan would be refused as well; or, the drift being within a step's gate, a
wrong alignment near the prediction passes it, and the map is spoilt from there. The
second alignment is used only when most of the scan lies on the map there
(``reset_inlier_share``), and more of it than at the first when that was used.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
import small_gicp
from scipy.spatial import cKDTree

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
    min_inlier_share: float = 0.3  # of the scan's returns paired with the map in the refinement's last stage
    max_step_correction_in: float = 12.0  # a correction beyond these is a mismatch
    max_step_correction_deg: float = 15.0
    # a scan the odometry's step cannot place, or places with fewer than this share of its returns
    # matched, is tried at the reported pose as it is (a reset odometry, :meth:`ScanMatcher._realign`),
    # and placed there when this share is matched there (and more than at the first)
    reset_inlier_share: float = 0.7
    # The refinement on the floor (:func:`_refine`):
    refine_correspondence_in: tuple[float, ...] = (6.0, 3.0)  # stage by stage: farther from a map return, no match
    refine_iterations: int = 15  # per stage; a step under 0.001 in and 0.0006° ends a stage sooner
    normal_neighbours: int = 6  # returns whose line gives a return's normal; map returns searched per return
    same_side_cos: float = 0.5  # normals less alike than 60° are different surfaces (or the far face of a wall)
    huber_in: float = 1.0  # residuals beyond this count linearly, not squared
    range_sigma_in: float = 0.5  # the range sensor's noise, which weighs the returns against the odometry
    # The odometry's step as a prior: sigma of its position error, in + share of the distance
    # driven, and of its heading error, degrees + share of the turn + degrees per inch driven.
    odometry_sigma_in: float = 0.1
    odometry_sigma_frac: float = 0.01
    odometry_sigma_deg: float = 0.5
    odometry_sigma_turn_frac: float = 0.05
    odometry_sigma_deg_per_in: float = 0.01
    # A placing with fewer than min_inlier_share of its returns matched (but min_points or more) is
    # still used when it lies this close to the odometry's prediction: the squared Mahalanobis
    # distance under the step's sigmas above (3 degrees of freedom: 11.34 holds 99 % of steps).
    odometry_vouches_chi2: float = 11.34

    def __post_init__(self) -> None:
        if not (self.voxel_in > 0 and self.downsample_in > 0 and self.max_correspondence_in > 0):
            raise ValueError("matcher voxel_in, downsample_in and max_correspondence_in must be positive")
        if not self.layers_z_in or not all(0.0 <= z < self.voxel_in for z in self.layers_z_in):
            raise ValueError(f"matcher layers_z_in must be heights in [0, voxel_in={self.voxel_in}), "
                             f"got {self.layers_z_in}")
        if not self.refine_correspondence_in or not all(d > 0 for d in self.refine_correspondence_in):
            raise ValueError(f"matcher refine_correspondence_in must be distances > 0, "
                             f"got {self.refine_correspondence_in}")
        if self.normal_neighbours < 2 or self.refine_iterations < 1:
            raise ValueError(f"matcher normal_neighbours must be >= 2 and refine_iterations >= 1, got "
                             f"{self.normal_neighbours} and {self.refine_iterations}")
        if not 0.0 <= self.min_inlier_share <= self.reset_inlier_share <= 1.0:
            raise ValueError(f"matcher inlier shares must satisfy 0 <= min_inlier_share <= reset_inlier_share <= 1, "
                             f"got {self.min_inlier_share} and {self.reset_inlier_share}")
        if not (self.huber_in > 0 and self.range_sigma_in > 0 and self.odometry_sigma_in > 0
                and self.odometry_sigma_deg > 0):
            raise ValueError("matcher huber_in, range_sigma_in, odometry_sigma_in and odometry_sigma_deg "
                             "must be positive")
        if not (math.isfinite(self.odometry_vouches_chi2) and self.odometry_vouches_chi2 >= 0):
            raise ValueError(f"matcher odometry_vouches_chi2 must be finite and not negative, "
                             f"got {self.odometry_vouches_chi2}")


def _transform(x_in: float, y_in: float, heading_rad: float) -> np.ndarray:
    c, s = math.cos(heading_rad), math.sin(heading_rad)
    t = np.eye(4)
    t[:2, :2] = [[c, -s], [s, c]]
    t[:2, 3] = (x_in, y_in)
    return t


def _floor(t: np.ndarray) -> tuple[float, float, float]:
    """x, y, heading (rad) of a 3-D transform: its motion on the floor."""
    return float(t[0, 3]), float(t[1, 3]), math.atan2(t[1, 0], t[0, 0])


def _wrap_deg(angle: float) -> float:
    return -math.remainder(-angle, 360.0)  # in (-180, 180]


def surface_normals(points: np.ndarray, neighbours: int) -> np.ndarray:
    """Each return's surface normal (unit, Nx2), turned towards the sensor at the origin:
    the direction across the line through it and its nearest ``neighbours`` returns of the
    same scan (their covariance's least axis). The side a surface was seen from is what
    tells a wall's two faces apart."""
    k = min(neighbours, len(points))
    _, nearest = cKDTree(points).query(points, k=k)
    around = points[nearest.reshape(len(points), k)]
    spread = around - around.mean(axis=1, keepdims=True)
    covariance = np.einsum("nki,nkj->nij", spread, spread)
    normals = np.linalg.eigh(covariance)[1][:, :, 0]  # eigenvalues ascending: the least spread's axis
    away = np.einsum("ni,ni->n", normals, points) > 0  # pointing away from the sensor
    normals[away] *= -1.0
    return normals


def _rotation(heading_rad: float) -> np.ndarray:
    c, s = math.cos(heading_rad), math.sin(heading_rad)
    return np.array([[c, -s], [s, c]])


class _FloorMap:
    """The map's returns on the floor (world inches) with their normals, for the refinement:
    the returns of every matched scan, averaged per ``cell_in`` square and per eighth of a
    turn of normal (so a thin wall's two faces stay apart), which keeps the map the size of
    the home's surfaces however often they are seen, and averages their range noise."""

    SIDES = 8

    def __init__(self, cell_in: float) -> None:
        self.cell_in = cell_in
        self._keys = np.zeros(0, dtype=np.int64)
        self._sums = np.zeros((0, 4))  # x, y, normal x, normal y summed over the cell's returns
        self._counts = np.zeros(0)
        self.points, self.normals = np.zeros((0, 2)), np.zeros((0, 2))
        self.tree = cKDTree(self.points)

    def add(self, points: np.ndarray, normals: np.ndarray) -> None:
        cells = np.floor(points / self.cell_in).astype(np.int64) + 2 ** 20  # non-negative for any home
        side = np.floor((np.arctan2(normals[:, 1], normals[:, 0]) + math.pi) / (2 * math.pi) * self.SIDES)
        keys = (cells[:, 0] * 2 ** 21 + cells[:, 1]) * self.SIDES + np.clip(side, 0, self.SIDES - 1).astype(np.int64)
        keys, at = np.unique(np.concatenate([self._keys, keys]), return_inverse=True)
        values = np.vstack([self._sums, np.column_stack([points, normals])])
        sums = np.column_stack([np.bincount(at, weights=values[:, i], minlength=len(keys)) for i in range(4)])
        counts = np.bincount(at, weights=np.concatenate([self._counts, np.ones(len(points))]), minlength=len(keys))
        self._keys, self._sums, self._counts = keys, sums, counts
        self.points = sums[:, :2] / counts[:, None]
        normal = sums[:, 2:]
        self.normals = normal / np.maximum(np.linalg.norm(normal, axis=1, keepdims=True), 1e-12)
        self.tree = cKDTree(self.points)


def _refine(floor_map: _FloorMap, points: np.ndarray, normals: np.ndarray, start: tuple[float, float, float],
            s: MatcherSettings) -> tuple[np.ndarray, np.ndarray, int]:
    """The pose (x, y, heading rad) that best lays the scan's returns on the map's, from
    ``start``; its information (3x3, the Gauss-Newton Hessian at that pose); and how many
    returns were matched at the last stage.

    Gauss-Newton on the floor: each return, at the pose, is paired with the nearest map
    return within the stage's distance whose normal is within ``same_side_cos`` of its own
    (turned by the pose) — never the far face of a wall — and its residual is its
    distance from that return's line. Weights: 1/sigma² of the range sensor, times a Huber
    kernel (all returns alike: weighing far returns down by a range-proportional noise
    made the candidate tests' drive through the apartment worse, docs/mapping.md)."""
    sensor_weight = 1.0 / s.range_sigma_in ** 2
    pose = np.array(start, dtype=float)
    information = np.zeros((3, 3))
    none = len(floor_map.points)
    matched = 0
    for reach in s.refine_correspondence_in:
        for _ in range(s.refine_iterations):
            rotation = _rotation(pose[2])
            at = points @ rotation.T + pose[:2]
            facing = normals @ rotation.T
            _, candidates = floor_map.tree.query(at, k=s.normal_neighbours, distance_upper_bound=reach)
            candidates = candidates.reshape(len(at), -1)
            found = candidates < none
            safe = np.where(found, candidates, 0)
            alike = found & (np.einsum("nkj,nj->nk", floor_map.normals[safe], facing) >= s.same_side_cos)
            paired = alike.any(axis=1)
            matched = int(paired.sum())
            if matched < 3:
                return pose, np.zeros((3, 3)), matched
            partner = safe[paired, np.argmax(alike[paired], axis=1)]  # the nearest of those alike
            normal = floor_map.normals[partner]
            residual = np.einsum("ni,ni->n", at[paired] - floor_map.points[partner], normal)
            arm = at[paired] - pose[:2]
            turning = normal[:, 1] * arm[:, 0] - normal[:, 0] * arm[:, 1]  # d residual / d heading
            jacobian = np.column_stack([normal[:, 0], normal[:, 1], turning])
            size = np.abs(residual) / s.huber_in
            weight = sensor_weight * np.where(size <= 1.0, 1.0, 1.0 / np.maximum(size, 1e-12))
            information = jacobian.T @ (jacobian * weight[:, None])
            # least squares: a direction the returns do not constrain (a bare corridor) is not moved
            step = -np.linalg.lstsq(information, jacobian.T @ (weight * residual), rcond=1e-9)[0]
            pose += step
            if math.hypot(step[0], step[1]) < 1e-3 and abs(step[2]) < 1e-5:
                break
    return pose, information, matched


def _with_odometry(matched: np.ndarray, information: np.ndarray, predicted: np.ndarray,
                   prior_information: np.ndarray) -> np.ndarray:
    """The match (x, y, heading rad) and the odometry's prediction, each weighed by its
    information: a direction the scan pins down keeps the match; one it leaves loose
    (along a bare corridor) follows the odometry."""
    towards = predicted - matched
    towards[2] = math.remainder(towards[2], 2 * math.pi)
    return matched + np.linalg.solve(information + prior_information, prior_information @ towards)


class ScanMatcher:
    """Corrects the robot's reported poses, one scan at a time, in the order taken."""

    def __init__(self, settings: MatcherSettings = MatcherSettings()) -> None:
        self.settings = settings
        self._map = small_gicp.GaussianVoxelMap(settings.voxel_in)
        self._map.set_lru(horizon=NEVER_FORGET, clear_cycle=NEVER_FORGET)  # the whole home, not a local map
        self._floor = _FloorMap(settings.downsample_in)
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
        guess, step = reported, np.eye(4)
        if self._last is not None:
            previous_reported, previous_corrected = self._last
            step = np.linalg.inv(previous_reported) @ reported
            guess = previous_corrected @ step
        normals = None
        if cloud is None:
            corrected, matched, inliers = guess, False, 0
        else:
            normals = surface_normals(points, self.settings.normal_neighbours)
            if self._map.size() == 0:
                corrected, matched, inliers = guess, True, 0  # the first scan with returns starts the map
            else:
                corrected, matched, inliers = self._align(guess, step, cloud, points, normals)
                weak = inliers < self.settings.reset_inlier_share * len(points)
                if (not matched or weak) and not np.allclose(guess, reported, atol=1e-6):
                    corrected, matched, inliers = self._realign(reported, step, cloud, points, normals,
                                                                (corrected, matched, inliers))
        if matched and cloud is not None and normals is not None:
            self._map.insert(cloud, corrected)
            self._floor.add(points @ corrected[:2, :2].T + corrected[:2, 3], normals @ corrected[:2, :2].T)
        self._last = (reported, corrected)
        x, y, heading = _floor(corrected)
        pose = Pose(x, y, math.degrees(heading))
        return Correction(pose, scan.x_in - x, scan.y_in - y, _wrap_deg(scan.heading_deg - pose.heading_deg),
                          matched, inliers, scan.stamp_s)

    def _prior_information(self, step: np.ndarray) -> np.ndarray:
        """The inverse covariance (x, y, heading rad) of the odometry's ``step``."""
        s = self.settings
        dx, dy, turn = _floor(step)
        driven = math.hypot(dx, dy)
        sigma_in = s.odometry_sigma_in + s.odometry_sigma_frac * driven
        sigma_deg = (s.odometry_sigma_deg + s.odometry_sigma_turn_frac * abs(math.degrees(turn))
                     + s.odometry_sigma_deg_per_in * driven)
        return np.diag([sigma_in ** -2, sigma_in ** -2, math.radians(sigma_deg) ** -2])

    def _align(self, guess: np.ndarray, step: np.ndarray, cloud: small_gicp.PointCloud, points: np.ndarray,
               normals: np.ndarray) -> tuple[np.ndarray, bool, int]:
        """The aligned pose (on the floor), whether it is to be trusted, and its inliers
        (returns matched on the floor); the guess itself when it is not trusted."""
        s = self.settings
        result = small_gicp.align(self._map, cloud, init_T_target_source=guess,
                                  max_correspondence_distance=s.max_correspondence_in,
                                  max_iterations=s.max_iterations)
        predicted = np.array(_floor(guess))
        coarse = np.array(_floor(result.T_target_source))
        if not self._within_a_step(coarse, predicted):
            coarse = predicted  # VGICP slid (along a corridor, say): refine from the odometry's prediction
        refined, information, inliers = _refine(self._floor, points, normals, tuple(coarse), s)
        prior = self._prior_information(step)
        placed = _with_odometry(refined, information, predicted, prior)
        x, y, heading = placed
        few = inliers < s.min_inlier_share * len(points)
        if few and (inliers < s.min_points or not self._vouched(placed, predicted, prior)):
            return guess, False, inliers
        if not self._within_a_step(placed, predicted):
            return guess, False, inliers
        return _transform(x, y, heading), True, inliers

    def _vouched(self, pose: np.ndarray, predicted: np.ndarray, prior_information: np.ndarray) -> bool:
        """Whether ``pose`` (x, y, heading rad) lies within the odometry step's own
        uncertainty of its prediction (the module docstring)."""
        off = pose - predicted
        off[2] = math.remainder(off[2], 2 * math.pi)
        return float(off @ prior_information @ off) <= self.settings.odometry_vouches_chi2

    def _realign(self, reported: np.ndarray, step: np.ndarray, cloud: small_gicp.PointCloud, points: np.ndarray,
                 normals: np.ndarray, first: tuple[np.ndarray, bool, int]) -> tuple[np.ndarray, bool, int]:
        """The alignment from the reported pose as it is, for a scan the step from the last
        corrected pose could not place, or placed with few of its returns matched
        (``first``: that alignment): an odometry reset (the dock puts the base back in the
        frame it started in, which is the map's) carries the drift before it into the
        step. Used only when most of the scan lies on the map there
        (:attr:`MatcherSettings.reset_inlier_share`) and, when ``first`` was used, more of it."""
        pose, matched, found = self._align(reported, step, cloud, points, normals)
        enough = found >= self.settings.reset_inlier_share * len(points)
        if matched and enough and (not first[1] or found > first[2]):
            return pose, True, found
        return first

    def _within_a_step(self, pose: np.ndarray, predicted: np.ndarray) -> bool:
        """Whether ``pose`` (x, y, heading rad) is a correction the odometry could need in one step."""
        s = self.settings
        return bool(math.hypot(pose[0] - predicted[0], pose[1] - predicted[1]) <= s.max_step_correction_in
                    and abs(math.degrees(math.remainder(pose[2] - predicted[2], 2 * math.pi)))
                    <= s.max_step_correction_deg)
