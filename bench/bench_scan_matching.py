"""Scan matching candidates as odometry correctors, side by side on one synthetic home.

    pip install small_gicp kiss-icp   # the candidates (only the chosen one is a dependency)
    python bench/bench_scan_matching.py [--seeds 5] [--loops 2] [--sigma 1.0] [--dropout 0.1]

A robot drives ``--loops`` times round a four-room apartment (tests/mapping/synthetic.py:
480 x 360 in, 36 in doorways, furniture), scanning every 4 in of travel and every 15° of
turn with a 360-beam planar range finder (300 in range, Gaussian range noise ``--sigma``
inches, ``--dropout`` of the beams returning nothing). Its wheel odometry drifts: 3 %
translation scale bias with 2 % noise per step, 0.03°/in heading drift, 2 % turn scale
bias, 0.2° heading noise per step. Each candidate is given the odometry's step as its
initial guess and the scan's points (planar: z = 0, or "extruded": copied at z = -4, 0,
+4 in, or at 1, 2, 3 in inside one voxel layer, so that a wall is a plane), and returns a
corrected pose:

- scan-to-scan: the scan aligned to the previous one, poses chained;
- scan-to-map: the scan aligned to a map of the scans before it at their corrected poses
  (small_gicp's Gaussian voxel map of the last 50 scans or of the whole home; KISS-ICP's voxel hash map, its adaptive
  threshold and robust kernel, with the odometry as the prediction instead of its
  constant-velocity model; and KISS-ICP as shipped, predicting at constant velocity);
- the package's own ``mapping.ScanMatcher`` (small_gicp VGICP against the whole home,
  with its plausibility checks) at three settings, its default last.

Reported per candidate, over ``--seeds`` runs (median of the per-run figures): the final
and mean absolute trajectory error (position, inches; heading, degrees), the median time
per scan, and the largest out-of-plane motion the 3-D library returned (z, roll, pitch),
which says how it copes with planar data. The raw odometry is the baseline.

A second table compares the package's matcher at the same settings on one hard step: a
second scan, 20 in and 10° from the first and reported 6-7 in and up to 5° off, matched to a
map of the first alone (the room of tests/mapping/test_localisation.py), worst error over
``--seeds`` x 3 offsets.
"""

from __future__ import annotations

import argparse
import datetime
import math
import platform
import statistics
import sys
import time
from collections.abc import Callable
from importlib.metadata import PackageNotFoundError, version
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT))

from tests.mapping.synthetic import (APARTMENT_LOOP, Drift, Lidar, apartment, drifting_odometry,  # noqa: E402
                                     loop_poses, relative)

Pose2 = tuple[float, float, float]  # x_in, y_in, heading_rad
EXTRUDE_Z_IN = (-4.0, 0.0, 4.0)
# For the voxel maps: layers inside one 4 in voxel layer (z in [0, 4)), so that each voxel
# holds a piece of a wall plane rather than one layer of it.
EXTRUDE_IN_VOXEL_Z_IN = (1.0, 2.0, 3.0)


def se3(pose: Pose2) -> np.ndarray:
    c, s = math.cos(pose[2]), math.sin(pose[2])
    t = np.eye(4)
    t[:2, :2] = [[c, -s], [s, c]]
    t[:2, 3] = pose[:2]
    return t


def planar(t: np.ndarray) -> Pose2:
    return float(t[0, 3]), float(t[1, 3]), math.atan2(t[1, 0], t[0, 0])


def out_of_plane(t: np.ndarray) -> tuple[float, float]:
    """|z| (in) and the tilt of the z axis (degrees) of a transform."""
    return abs(float(t[2, 3])), math.degrees(math.acos(min(1.0, abs(float(t[2, 2])))))


def points_of(ranges: np.ndarray, angles: np.ndarray, extrude: bool | str) -> np.ndarray:
    seen = np.isfinite(ranges)
    r, a = ranges[seen], angles[seen]
    xy = np.column_stack([r * np.cos(a), r * np.sin(a)])
    layers = EXTRUDE_IN_VOXEL_Z_IN if extrude == "in voxel" else EXTRUDE_Z_IN if extrude else (0.0,)
    return np.vstack([np.column_stack([xy, np.full(len(xy), z)]) for z in layers])


class Corrector:
    """Takes each scan's points (robot frame) and the odometry's step; returns the pose."""

    name = ""
    extrude = False

    def start(self, pose: Pose2, points: np.ndarray) -> None:
        self.pose = se3(pose)
        self.worst = (0.0, 0.0)

    def step(self, odometry_step: Pose2, points: np.ndarray, reported: Pose2, ranges: np.ndarray) -> Pose2:
        guess = self.pose @ se3(odometry_step)
        self.pose = self.correct(guess, points)
        z, tilt = out_of_plane(self.pose)
        self.worst = (max(self.worst[0], z), max(self.worst[1], tilt))
        planar_pose = planar(self.pose)
        self.pose = se3(planar_pose)  # the robot is on the floor: keep the planar part only
        return planar_pose

    def correct(self, guess: np.ndarray, points: np.ndarray) -> np.ndarray:
        return guess


class Odometry(Corrector):
    name = "raw odometry (baseline)"


class SmallGicpScanToScan(Corrector):
    def __init__(self, kind: str, extrude: bool) -> None:
        import small_gicp
        self.sg, self.kind, self.extrude = small_gicp, kind, extrude
        self.name = f"small_gicp {kind} scan-to-scan, {'extruded' if extrude else 'flat z=0'}"

    def start(self, pose: Pose2, points: np.ndarray) -> None:
        super().start(pose, points)
        self.previous = self.sg.preprocess_points(points, downsampling_resolution=1.0, num_neighbors=10)

    def correct(self, guess: np.ndarray, points: np.ndarray) -> np.ndarray:
        source = self.sg.preprocess_points(points, downsampling_resolution=1.0, num_neighbors=10)
        target, tree = self.previous
        initial = np.linalg.inv(self.pose) @ guess
        result = self.sg.align(target, source[0], tree, init_T_target_source=initial, registration_type=self.kind,
                               max_correspondence_distance=12.0, max_iterations=30)
        self.previous = source
        return self.pose @ result.T_target_source


class SmallGicpScanToMap(Corrector):
    """VGICP against a Gaussian voxel map of the corrected scans: voxels not seen in the
    last ``horizon`` scans dropped (a local map), or none dropped (the whole home)."""

    def __init__(self, extrude: bool | str, horizon: int, voxel_in: float = 4.0) -> None:
        import small_gicp
        self.sg, self.extrude, self.voxel_in, self.horizon = small_gicp, extrude, voxel_in, horizon
        shape = {"in voxel": "extruded z=1,2,3", True: "extruded z=-4,0,4", False: "flat z=0"}[extrude]
        self.name = (f"small_gicp VGICP scan-to-map ({'last ' + str(horizon) + ' scans' if horizon < 10**6 else 'whole home'}), "
                     f"{shape}")

    def start(self, pose: Pose2, points: np.ndarray) -> None:
        super().start(pose, points)
        self.map = self.sg.GaussianVoxelMap(self.voxel_in)
        self.map.set_lru(horizon=self.horizon, clear_cycle=10)
        cloud, _ = self.sg.preprocess_points(points, downsampling_resolution=1.0, num_neighbors=10)
        self.map.insert(cloud, self.pose)

    def correct(self, guess: np.ndarray, points: np.ndarray) -> np.ndarray:
        cloud, _ = self.sg.preprocess_points(points, downsampling_resolution=1.0, num_neighbors=10)
        result = self.sg.align(self.map, cloud, init_T_target_source=guess, max_correspondence_distance=12.0,
                               max_iterations=30)
        pose = se3(planar(result.T_target_source))
        self.map.insert(cloud, pose)
        return result.T_target_source


class KissIcpScanToMap(Corrector):
    """KISS-ICP's registration, voxel hash map and adaptive threshold (in metres, as it
    expects), with the odometry step as the prediction."""

    def __init__(self, extrude: bool) -> None:
        from kiss_icp.config import KISSConfig
        from kiss_icp.mapping import get_voxel_hash_map
        from kiss_icp.registration import get_registration
        from kiss_icp.threshold import get_threshold_estimator
        from kiss_icp.voxelization import voxel_down_sample
        self.extrude = extrude
        self.name = f"kiss-icp scan-to-map, {'extruded' if extrude else 'flat z=0'}"
        config = KISSConfig()
        config.data.max_range = 300.0 * 0.0254
        config.data.min_range = 0.0
        config.mapping.voxel_size = 0.1
        config.registration.max_num_threads = 1
        self.config = config
        self.parts = (get_voxel_hash_map, get_registration, get_threshold_estimator, voxel_down_sample)

    def start(self, pose: Pose2, points: np.ndarray) -> None:
        super().start(pose, points)
        new_map, registration, threshold, self.downsample = self.parts
        self.map, self.registration, self.threshold = new_map(self.config), registration(self.config), threshold(self.config)
        self.map.update(self.downsample(points * 0.0254, self.config.mapping.voxel_size * 0.5), self.metres(self.pose))

    @staticmethod
    def metres(t: np.ndarray) -> np.ndarray:
        m = t.copy()
        m[:3, 3] *= 0.0254
        return m

    def correct(self, guess: np.ndarray, points: np.ndarray) -> np.ndarray:
        voxel = self.config.mapping.voxel_size
        frame = self.downsample(points * 0.0254, voxel * 0.5)
        source = self.downsample(frame, voxel * 1.5)
        sigma = self.threshold.get_threshold()
        prediction = self.metres(guess)
        pose = self.registration.align_points_to_map(points=source, voxel_map=self.map, initial_guess=prediction,
                                                     max_correspondance_distance=3 * sigma, kernel=sigma)
        self.threshold.update_model_deviation(np.linalg.inv(prediction) @ pose)
        self.map.update(frame, pose)
        pose = pose.copy()
        pose[:3, 3] /= 0.0254
        return pose


class KissIcpPipeline(Corrector):
    """KISS-ICP as shipped (KissICP.register_frame): no odometry, its constant-velocity
    model predicts each pose."""

    name = "kiss-icp pipeline unmodified (no odometry), flat z=0"

    def start(self, pose: Pose2, points: np.ndarray) -> None:
        from kiss_icp.config import KISSConfig
        from kiss_icp.kiss_icp import KissICP
        super().start(pose, points)
        config = KISSConfig()
        config.data.max_range = 300.0 * 0.0254
        config.data.min_range = 0.0
        config.mapping.voxel_size = 0.1
        config.registration.max_num_threads = 1
        config.data.deskew = False  # one instant per scan (with deskewing on, equal stamps give NaN poses)
        self.origin = self.pose
        self.kiss = KissICP(config)
        self.kiss.register_frame(points * 0.0254, np.zeros(len(points)))

    def correct(self, guess: np.ndarray, points: np.ndarray) -> np.ndarray:
        self.kiss.register_frame(points * 0.0254, np.zeros(len(points)))
        pose = self.kiss.last_pose.copy()
        pose[:3, 3] /= 0.0254
        return self.origin @ pose


class Package(Corrector):
    """The mapping package's ScanMatcher (small_gicp VGICP, whole home, with its checks),
    given the reported poses; its default settings are the choice."""

    def __init__(self, voxel_in: float | None = None, layers_z_in: tuple[float, ...] | None = None) -> None:
        from mapping import MatcherSettings
        default = MatcherSettings()
        self.settings = MatcherSettings(voxel_in=voxel_in or default.voxel_in,
                                        layers_z_in=layers_z_in or default.layers_z_in)
        self.name = f"mapping.ScanMatcher, {settings_text(self.settings)}{' (default)' if self.settings == default else ''}"

    def start(self, pose: Pose2, points: np.ndarray) -> None:
        from mapping import ScanMatcher
        super().start(pose, points)
        self.matcher = ScanMatcher(self.settings)
        self.angles = Lidar().angles_rad
        self.first = pose
        self.worst = (math.nan, math.nan)  # cut back to the floor inside the matcher

    def step(self, odometry_step: Pose2, points: np.ndarray, reported: Pose2, ranges: np.ndarray) -> Pose2:
        from mapping import PlanarScan
        if self.first is not None:
            self.matcher.update(PlanarScan(self.angles, self.ranges0, *self.first[:2], math.degrees(self.first[2]),
                                           0.0, 300.0))
            self.first = None
        correction = self.matcher.update(PlanarScan(self.angles, ranges, reported[0], reported[1],
                                                    math.degrees(reported[2]), 0.0, 300.0))
        p = correction.pose
        return p.x_in, p.y_in, math.radians(p.heading_deg)


def settings_text(settings) -> str:
    layers = ", ".join(f"{z:g}" for z in settings.layers_z_in)
    return f"{settings.voxel_in:g} in voxels, z = {layers}"


def run(make: Callable[[], Corrector], seed: int, loops: int, lidar: Lidar) -> dict[str, float]:
    walls = apartment()
    rng = np.random.default_rng(seed)
    truth = loop_poses(APARTMENT_LOOP)
    for _ in range(loops - 1):
        truth += loop_poses(APARTMENT_LOOP)[1:]
    odometry = drifting_odometry(truth, Drift(), rng)
    scans = [lidar.scan(walls, pose, rng) for pose in truth]
    corrector = make()
    corrector.ranges0 = scans[0]
    corrector.start(truth[0], points_of(scans[0], lidar.angles_rad, corrector.extrude))
    estimates, times = [truth[0]], []
    for k in range(1, len(truth)):
        points = points_of(scans[k], lidar.angles_rad, corrector.extrude)
        began = time.perf_counter()
        estimates.append(corrector.step(relative(odometry[k - 1], odometry[k]), points, odometry[k], scans[k]))
        times.append(time.perf_counter() - began)
    position = [math.dist(e[:2], t[:2]) for e, t in zip(estimates, truth)]
    heading = [abs(math.degrees(math.remainder(e[2] - t[2], 2 * math.pi))) for e, t in zip(estimates, truth)]
    driven = sum(math.dist(a[:2], b[:2]) for a, b in zip(truth, truth[1:]))
    return {"final_in": position[-1], "mean_in": statistics.fmean(position), "max_in": max(position),
            "final_deg": heading[-1], "mean_deg": statistics.fmean(heading), "ms": statistics.median(times) * 1000,
            "z_in": corrector.worst[0], "tilt_deg": corrector.worst[1], "driven_in": driven, "scans": len(truth)}


def installed(distribution: str) -> str:
    try:
        return version(distribution)
    except PackageNotFoundError:
        return ""


CANDIDATES: list[tuple[str, Callable[[], Corrector]]] = [
    ("", Odometry),
    ("small_gicp", lambda: SmallGicpScanToScan("ICP", extrude=False)),
    ("small_gicp", lambda: SmallGicpScanToScan("PLANE_ICP", extrude=False)),
    ("small_gicp", lambda: SmallGicpScanToScan("PLANE_ICP", extrude=True)),
    ("small_gicp", lambda: SmallGicpScanToScan("GICP", extrude=False)),
    ("small_gicp", lambda: SmallGicpScanToScan("GICP", extrude=True)),
    ("small_gicp", lambda: SmallGicpScanToMap(extrude=False, horizon=50)),
    ("small_gicp", lambda: SmallGicpScanToMap(extrude=True, horizon=50)),
    ("small_gicp", lambda: SmallGicpScanToMap(extrude=False, horizon=10**9)),
    ("small_gicp", lambda: SmallGicpScanToMap(extrude="in voxel", horizon=10**9)),
    ("kiss-icp", lambda: KissIcpScanToMap(extrude=False)),
    ("kiss-icp", KissIcpPipeline),
    ("small_gicp", lambda: Package(voxel_in=4.0, layers_z_in=(1.0, 2.0, 3.0))),
    ("small_gicp", lambda: Package(voxel_in=8.0, layers_z_in=(0.0,))),
    ("small_gicp", Package),
]


def out_of_plane_text(m: dict[str, float]) -> str:
    return "n/a (cut inside)" if math.isnan(m["z_in"]) else f"{m['z_in']:.2g}, {m['tilt_deg']:.2g}"


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--seeds", type=int, default=5)
    parser.add_argument("--loops", type=int, default=2)
    parser.add_argument("--sigma", type=float, default=1.0, help="range noise, inches")
    parser.add_argument("--dropout", type=float, default=0.1, help="share of beams returning nothing")
    args = parser.parse_args()
    lidar = Lidar(sigma_in=args.sigma, dropout=args.dropout)
    print(f"date: {datetime.datetime.now(datetime.timezone.utc):%Y-%m-%d %H:%M} UTC")
    print(f"machine: {platform.machine()}, {platform.python_implementation()} {platform.python_version()}, "
          f"numpy {version('numpy')}, small_gicp {installed('small_gicp') or '-'}, "
          f"kiss-icp {installed('kiss-icp') or '-'}")
    print(f"command: python bench/bench_scan_matching.py --seeds {args.seeds} --loops {args.loops} "
          f"--sigma {args.sigma} --dropout {args.dropout}")
    print()
    print("| corrector | final in | mean in | max in | final ° | mean ° | ms / scan | worst z in, tilt ° |")
    print("|---|---:|---:|---:|---:|---:|---:|---|")
    for distribution, make in CANDIDATES:
        if distribution and not installed(distribution):
            print(f"| {distribution}: not installed | | | | | | | |")
            continue
        runs = [run(make, seed, args.loops, lidar) for seed in range(args.seeds)]
        m = {key: statistics.median(r[key] for r in runs) for key in runs[0]}
        print(f"| {make().name} | {m['final_in']:.2f} | {m['mean_in']:.2f} | {m['max_in']:.2f} | "
              f"{m['final_deg']:.2f} | {m['mean_deg']:.2f} | {m['ms']:.2f} | {out_of_plane_text(m)} |",
              flush=True)
    print(f"\n{runs[0]['scans']} scans over {runs[0]['driven_in']:.0f} in driven per run\n")
    one_step(args.seeds, lidar)


def one_step(seeds: int, lidar: Lidar) -> None:
    """Worst error of one scan matched to a one-scan map, z = 0 against layered."""
    from mapping import PlanarScan, ScanMatcher
    from tests.mapping.test_localisation import room
    print("| mapping.ScanMatcher: one step, map of one scan | worst in | worst ° |")
    print("|---|---:|---:|")
    for package in (Package(4.0, (1.0, 2.0, 3.0)), Package(8.0, (0.0,)), Package()):
        worst_in = worst_deg = 0.0
        for seed in range(seeds):
            for dx, dy, dheading in ((5.0, -4.0, 5.0), (-6.0, 3.0, -5.0), (4.0, 4.0, 0.0)):
                walls, rng = room(), np.random.default_rng(seed)
                matcher = ScanMatcher(package.settings)
                matcher.update(PlanarScan(lidar.angles_rad, lidar.scan(walls, (60.0, 50.0, 0.0), rng), 60.0, 50.0,
                                          0.0, 0.0, lidar.max_range_in))
                ranges = lidar.scan(walls, (80.0, 45.0, math.radians(10.0)), rng)
                pose = matcher.update(PlanarScan(lidar.angles_rad, ranges, 80.0 + dx, 45.0 + dy, 10.0 + dheading,
                                                 1.0, lidar.max_range_in)).pose
                worst_in = max(worst_in, math.dist((pose.x_in, pose.y_in), (80.0, 45.0)))
                worst_deg = max(worst_deg, abs(pose.heading_deg - 10.0))
        print(f"| {settings_text(package.settings)} | {worst_in:.2f} | {worst_deg:.2f} |")


if __name__ == "__main__":
    main()
