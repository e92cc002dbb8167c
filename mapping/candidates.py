"""Object candidates: the returns of the scans that are not the home's static structure
and are the size of an object, fused over scans into persistent tracks.

The robot has no list of the home's furniture, so the decision is made from geometry
alone, in four steps (the numbers are :class:`CandidateSettings`; docs/mapping.md,
"Finding objects without a ceiling camera", says why each is what it is):

1. **Segment** each scan, taken at its corrected pose, into clusters: consecutive
   returns (in beam order) belong together unless the gap between them is wider than
   an adaptive breakpoint — a fixed allowance for range noise plus a few times the
   spacing the two beams have on a surface facing the robot at that range (so a surface
   turned up to about 70° from the robot stays whole) — or their beams are more than
   ``max_step_deg`` apart.
2. **Structure**: each cluster is cut into straight pieces (split-and-merge: split at
   the return farthest from the chord while it is farther than ``split_in``), and each
   piece fitted with a line robustly (:func:`_line_fit`). A line at least
   ``structure_min_in`` long — longer than any face of any object in the catalogue — is
   a piece of wall or furniture: a *structure line*, kept for the rest of the run and
   taken to go on ``extend_in`` beyond its ends (over the stretch of wall an object
   against it hides). A return within a line's band (``band_min_in``) is structure, the
   lines of earlier scans included, so a piece of wall seen short between two
   occluders is still known to be wall — unless it stands *proud* of a line this scan
   fitted (:meth:`CandidateFinder._proud`): in front of it by more than
   ``proud_sigmas`` times the noise of that line's own returns, in a run of
   ``proud_min_returns``. The band is wide enough for a far wall's noise and so
   swallows a can 0.7 in from a wall; the wall beside the can in the same scan is
   known far better than that.
3. **Observations**: the returns left, in runs of consecutive returns no more than
   ``run_gap_in`` apart (a segment may join a table leg to a bottle beyond it), are an
   object seen once when the run is no wider than ``max_extent_in`` (the largest
   catalogue object's diagonal, with noise), does not lie mostly *behind* a structure
   line its beams crossed (a far wall's noise: nothing is seen through a wall), and is
   not *attached* to structure: a run
   that touches a structure line and does not stand in front of it (towards the robot)
   by ``front_min_in`` is the end face of a wall at a doorway or of a cabinet between
   its front and the wall. An object against a wall stands in front of it and is kept.
   A single return within ``lone_near_in`` of structure is the range noise of that
   structure and is dropped.
4. **Tracks**: an observation within ``associate_in`` of a track's outline (or whose
   centroid is within ``associate_centroid_in`` of the track's, the two together no
   wider than an object) is that track seen again, as long as it does not widen the
   track beyond an object; otherwise it starts a new track with the next id. A track is
   reported as a :class:`Candidate` once seen ``min_seen`` times, cut to the part of
   its outline off the structure lines (those found since included; what was seen
   proud of a wall stays), unless fewer than
   ``min_outline_points`` are left of it, or it is wider than any object
   (``max_extent_in`` and ``widen_sigmas`` of noise), or it is one of four small tracks
   standing at the corners of a rectangle of table size (a table's legs; a planar scan
   cannot see that a leg is tall), or — when the occupancy grid is given — none of its
   outline's cells is occupied any more (the object was moved) or too little free space
   has been seen around it, or its outline is a straight piece of a longer face in the
   map (:func:`continues_structure`: a nook's back wall, a counter's end face, a bed's
   side seen a piece at a time).

The distances that stand for range noise (``split_in``, ``band_min_in``,
``lone_near_in``) are multiples of the range finder's noise, ``range_sigma_in``, which the
caller sets for its sensor. Pure numpy; stateful only in :class:`CandidateFinder`, which
is fed the scans in order.
"""

from __future__ import annotations

import itertools
import math
from collections.abc import Sequence
from dataclasses import dataclass, field

import numpy as np

from mapping.faces import run_along, straight_face
from mapping.occupancy import OccupancyGrid
from mapping.scan import PlanarScan
from planner.geometry import Pose


CORE_SHARE = 0.9
"""The share of a track's outline its core holds (:attr:`Candidate.core_extent_in`)."""


@dataclass(frozen=True)
class CandidateSettings:
    """The rules' numbers (inches, degrees). docs/mapping.md says why each is what it is."""

    range_sigma_in: float = 0.5  # the range finder's noise (standard deviation): a modern lidar at room ranges
    split_sigmas: float = 3.0  # a return farther than this from its piece's chord splits the piece
    band_sigmas: float = 3.0  # a structure line's band: returns this close to it are on it
    line_share: float = 0.8  # a piece with fewer of its returns in the band of its fit is not straight
    lone_sigmas: float = 5.0  # a single return this close to structure is its noise
    break_min_in: float = 3.0  # gap always allowed between neighbouring returns (3 sigma of 1 in noise)
    break_spacings: float = 3.0  # ... plus this many beam spacings (a surface up to 70° from facing the robot)
    max_step_deg: float = 5.0  # returns farther apart in angle (dropouts, open space) are apart
    structure_min_in: float = 15.0  # a straight piece this long is structure (longest object face: 11 in)
    structure_min_points: int = 5
    extend_in: float = 6.0  # a structure line goes on this far beyond its ends (hidden behind an object)
    run_gap_in: float = 6.0  # neighbouring returns of one object are no farther apart than this
    max_extent_in: float = 16.0  # an object seen once is at most this wide (11 x 9 in box: 14.2 in diagonal)
    widen_sigmas: float = 6.0  # ... and a track, whose outline noise widens, this many sigma more
    front_min_in: float = 1.0  # a run touching a structure line stands in front of it by at least this
    proud_sigmas: float = 4.0  # a return stands proud of its scan's wall line by this many of the line's own noise
    proud_min_returns: int = 2  # ... in a run of at least this many neighbouring returns
    face_min_in: float = 5.0  # grid: a straight outline this long (wider than any round object) has a direction
    face_straight_in: float = 2.0  # ... when nine in ten of its points lie this close to its line
    face_band_in: float = 2.0  # ... and it is structure where occupied cells this close to its line
    face_gap_in: float = 5.0  # ... go on beyond its ends with gaps no longer than this (a 4 in wall's end)
    face_run_min_in: float = 14.0  # ... to this length in all (an 11 in face and a cell beyond each end is less)
    face_side_in: float = 3.0  # ... not where cells fill half of this beyond the band on both sides (a wall crossing it)
    associate_in: float = 3.0  # an observation this close to a track's outline is that track
    associate_centroid_in: float = 6.0  # ... or with its centroid this close to the track's, when the two
    # together are no wider than max_extent_in
    outline_voxel_in: float = 1.0  # a track's outline: the mean of its returns in squares of this side
    min_seen: int = 2  # scans that must see a track before it is a candidate
    min_outline_points: int = 3  # a track with fewer outline points off the structure lines is structure
    leg_max_extent_in: float = 10.0  # a track whose core is no wider may be a table leg (a 2 in leg, widened by noise)
    table_min_in: float = 12.0  # a table's legs stand between these apart (centre to centre)
    table_max_in: float = 96.0
    table_tolerance_in: float = 3.0  # sides and diagonals of a leg rectangle agree within this
    support_share: float = 0.0  # grid: more than this share of the outline lies in occupied cells
    ring_in: tuple[float, float] = (4.0, 10.0)  # grid: the ring around it, beyond extent/2, ...
    ring_free_share: float = 0.25  # ... of which at least this share is seen free

    def __post_init__(self) -> None:
        if not (math.isfinite(self.extend_in) and self.extend_in >= 0):
            raise ValueError(f"candidate setting extend_in must be finite and not negative, got {self.extend_in}")
        positive = ("range_sigma_in", "split_sigmas", "band_sigmas", "lone_sigmas", "break_min_in",
                    "break_spacings", "max_step_deg", "structure_min_in", "run_gap_in", "max_extent_in", "widen_sigmas",
                    "associate_in",
                    "associate_centroid_in",
                    "outline_voxel_in", "proud_sigmas", "face_min_in", "face_straight_in", "face_band_in",
                    "face_gap_in", "face_side_in", "face_run_min_in", "leg_max_extent_in", "table_min_in", "table_max_in",
                    "table_tolerance_in")
        for name in positive:
            value = getattr(self, name)
            if not (math.isfinite(value) and value > 0):
                raise ValueError(f"candidate setting {name} must be positive and finite, got {value}")
        if self.proud_min_returns < 1:
            raise ValueError(f"candidate setting proud_min_returns must be >= 1, got {self.proud_min_returns}")
        if self.min_seen < 1 or self.structure_min_points < 2 or self.min_outline_points < 1:
            raise ValueError("candidate settings min_seen and min_outline_points must be >= 1, "
                             "structure_min_points >= 2")
        if not 0.0 <= self.ring_in[0] < self.ring_in[1]:
            raise ValueError(f"candidate setting ring_in must be (inner, outer) with 0 <= inner < outer, "
                             f"got {self.ring_in}")
        if not all(0.0 <= v <= 1.0 for v in (self.support_share, self.ring_free_share, self.line_share)):
            raise ValueError("candidate settings support_share, ring_free_share and line_share must be in [0, 1]")
        if not self.table_min_in < self.table_max_in:
            raise ValueError("candidate setting table_min_in must be below table_max_in")

    @property
    def split_in(self) -> float:
        return self.split_sigmas * self.range_sigma_in

    @property
    def band_min_in(self) -> float:
        return self.band_sigmas * self.range_sigma_in

    @property
    def lone_near_in(self) -> float:
        return self.lone_sigmas * self.range_sigma_in


@dataclass(frozen=True)
class Candidate:
    """Something object-sized that is not the home's structure, seen ``times_seen`` times.

    ``id`` is stable for the run (a track keeps its id; two tracks found to be one keep
    the older's). ``outline`` is the returns thinned to one point per
    ``outline_voxel_in`` square, those on structure lines left out; ``x_in``/``y_in`` its
    centroid, the sides seen so far (so it lies towards the robot's side of a round
    object until the far side is seen); ``extent_in`` the largest distance between two
    outline points (the object's size, widened by range noise).
    """

    id: int
    x_in: float
    y_in: float
    outline: tuple[tuple[float, float], ...]
    extent_in: float
    times_seen: int
    first_seen_s: float
    last_seen_s: float

    def core(self) -> np.ndarray:
        """The outline's points within the distance from its median that holds
        :data:`CORE_SHARE` of them (Nx2): the outline with a stray return or two left out."""
        points = np.asarray(self.outline, dtype=float).reshape(-1, 2)
        if len(points) < 2:
            return points
        radii = np.hypot(*(points - np.median(points, axis=0)).T)
        return points[radii <= np.quantile(radii, CORE_SHARE)]

    @property
    def core_extent_in(self) -> float:
        """Twice the distance from the outline's median within which :data:`CORE_SHARE`
        of its points lie: the size with a stray return or two left out. A track seen
        many times gathers a few (a mixed return at an edge, a noisy one from far off),
        and its ``extent_in`` grows with them: in a simulated apartment under the
        ``paper`` preset two of a table's 2 in legs grew past the leg bound that way,
        and the table's legs became four candidates to handle."""
        points = np.asarray(self.outline, dtype=float).reshape(-1, 2)
        if len(points) < 2:
            return self.extent_in
        radii = np.hypot(*(points - np.median(points, axis=0)).T)
        return 2.0 * float(np.quantile(radii, CORE_SHARE))


@dataclass(frozen=True)
class Observation:
    """One run of returns in one scan judged object-like (world inches); ``proud``: which
    of them lie in a structure line's band but stand proud of it (an object against a
    wall, :meth:`CandidateFinder.observe`)."""

    points: np.ndarray = field(compare=False)
    stamp_s: float
    proud: np.ndarray | None = field(default=None, compare=False)

    @property
    def centroid(self) -> np.ndarray:
        return self.points.mean(axis=0)


@dataclass
class _Track:
    id: int
    points: np.ndarray  # thinned outline, Nx2
    seen: int
    first_s: float
    last_s: float
    proud: set[tuple[int, int]] = field(default_factory=set)  # outline squares seen standing proud of a wall
    # The outline's mean and bounding box, kept with it: association asks them of every
    # track for every observation, and only a new outline changes them.
    centre: np.ndarray = field(init=False, repr=False)
    low: np.ndarray = field(init=False, repr=False)
    high: np.ndarray = field(init=False, repr=False)

    def __post_init__(self) -> None:
        self.reshape(self.points)

    def reshape(self, points: np.ndarray) -> None:
        """Give the track a new outline."""
        self.points = points
        self.centre = points.mean(axis=0)
        self.low, self.high = points.min(axis=0), points.max(axis=0)


def _extent(points: np.ndarray) -> float:
    if len(points) < 2:
        return 0.0
    d = points[:, None, :] - points[None, :, :]
    return float(np.sqrt((d ** 2).sum(axis=2)).max())


def _thin(points: np.ndarray, voxel_in: float) -> np.ndarray:
    """The mean of the points in each ``voxel_in`` square, ordered by square."""
    keys = np.floor(points / voxel_in).astype(np.int64)
    _, inverse = np.unique(keys, axis=0, return_inverse=True)
    inverse = inverse.reshape(-1)
    count = np.bincount(inverse)
    return np.column_stack([np.bincount(inverse, points[:, 0]) / count, np.bincount(inverse, points[:, 1]) / count])


def split_and_merge(points: np.ndarray, split_in: float) -> list[tuple[int, int]]:
    """Index ranges ``[start, stop]`` (inclusive) of the straight pieces of an ordered run
    of points: a piece is split at the point farthest from its chord while that point is
    farther than ``split_in`` (the iterative end-point fit)."""
    pieces, stack = [], [(0, len(points) - 1)]
    while stack:
        lo, hi = stack.pop()
        if hi - lo < 2:
            pieces.append((lo, hi))
            continue
        a, b = points[lo], points[hi]
        chord = b - a
        length = math.hypot(*chord)
        inner = points[lo + 1:hi] - a
        if length < 1e-9:
            distance = np.hypot(inner[:, 0], inner[:, 1])
        else:
            distance = np.abs(chord[0] * inner[:, 1] - chord[1] * inner[:, 0]) / length
        k = int(np.argmax(distance))
        if distance[k] > split_in:
            stack += [(lo + 1 + k, hi), (lo, lo + 1 + k)]
        else:
            pieces.append((lo, hi))
    return sorted(pieces)


class StructureLines:
    """The straight pieces of wall and furniture seen so far: segments with a band, each
    taken to go on ``extend_in`` beyond its ends (the wall hidden behind an object
    standing against it, whose returns would otherwise join the object's)."""

    def __init__(self, extend_in: float = 0.0) -> None:
        self._segments = np.zeros((0, 5))  # x0, y0, x1, y1, band
        self.extend_in = extend_in

    def __len__(self) -> int:
        return len(self._segments)

    @property
    def segments(self) -> np.ndarray:
        return self._segments

    def add(self, segments: np.ndarray) -> None:
        """Add (N, 5) segments, leaving out those whose two ends both lie in the band of
        one known segment (the same piece of wall seen again)."""
        if len(segments) == 0:
            return
        if len(self._segments):
            ends = np.vstack([segments[:, 0:2], segments[:, 2:4]])
            inside = (self.distances(ends) <= self._segments[None, :, 4]).reshape(2, len(segments), -1)
            segments = segments[~(inside[0] & inside[1]).any(axis=1)]
        self._segments = np.vstack([self._segments, segments])

    def distances(self, points: np.ndarray, segments: np.ndarray | None = None) -> np.ndarray:
        """(N, M) distance of each point to each segment (to its nearest point)."""
        s = self._segments if segments is None else segments
        if len(s) == 0 or len(points) == 0:
            return np.full((len(points), len(s)), np.inf)
        a, b = s[None, :, 0:2], s[None, :, 2:4]
        p = points[:, None, :]
        ab = b - a
        length2 = np.maximum((ab ** 2).sum(axis=2), 1e-12)
        beyond = self.extend_in / np.sqrt(length2)
        t = np.clip(((p - a) * ab).sum(axis=2) / length2, -beyond, 1.0 + beyond)
        nearest = a + t[..., None] * ab
        return np.sqrt(((p - nearest) ** 2).sum(axis=2))

    def within(self, points: np.ndarray) -> np.ndarray:
        """Which points lie in some segment's band."""
        return self.within_each(points).any(axis=1)

    def within_each(self, points: np.ndarray) -> np.ndarray:
        """(N, M): whether each point lies in each segment's band."""
        if len(self._segments) == 0 or len(points) == 0:
            return np.zeros((len(points), len(self._segments)), dtype=bool)
        return self.distances(points) <= self._segments[None, :, 4]


def _breakpoints(points: np.ndarray, ranges: np.ndarray, angles: np.ndarray, s: CandidateSettings) -> np.ndarray:
    """Whether each neighbouring pair (i, i + 1) of ordered returns is apart: farther
    apart than ``break_min_in`` plus ``break_spacings`` times the spacing their beams
    have on a surface facing the robot, or more than ``max_step_deg`` apart in angle."""
    if len(points) < 2:
        return np.zeros(0, dtype=bool)
    gap = np.hypot(*(points[1:] - points[:-1]).T)
    step = np.abs(np.diff(angles))
    allowed = s.break_min_in + s.break_spacings * np.minimum(ranges[1:], ranges[:-1]) * step
    return (gap > allowed) | (step > math.radians(s.max_step_deg))


def _line_fit(points: np.ndarray, s: CandidateSettings) -> np.ndarray | None:
    """A piece's line as a segment (x0, y0, x1, y1, band), or None when it is not one.

    Fitted first to the middle half of the returns, then (three rounds) to the returns
    within ``band_min_in`` (3σ) of the fit before: a piece that ends on an object's side
    (split-and-merge cuts at the chord, which leans towards the object) is so fitted to
    the wall and not to the object. None when less than ``line_share`` of the returns
    are in the band at the end (a step from an object's face to the wall behind it, cut
    as one piece where the returns are sparse, is no line), or when the returns in the
    band are too few or span less than ``structure_min_in``. The segment runs between
    the projections of the first and last returns in the band."""
    inliers = np.zeros(len(points), dtype=bool)
    inliers[len(points) // 4:len(points) - len(points) // 4] = True  # the middle half: the ends are suspect
    band = s.band_min_in
    for _ in range(3):
        centre = points[inliers].mean(axis=0)
        _, _, vt = np.linalg.svd(points[inliers] - centre, full_matrices=False)
        direction = vt[0]
        offset = (points - centre) @ vt[1]
        within = np.abs(offset) <= band
        if within.sum() < s.structure_min_points:
            return None
        if (within == inliers).all():
            break
        inliers = within
    if inliers.mean() < s.line_share:
        return None
    ends = points[np.nonzero(inliers)[0][[0, -1]]]
    along = (ends - centre) @ direction
    a, b = centre + along[0] * direction, centre + along[1] * direction
    if math.dist(a, b) < s.structure_min_in:
        return None
    return np.array([a[0], a[1], b[0], b[1], band])


def _across(segments: np.ndarray, segment: np.ndarray) -> np.ndarray:
    """Which of ``segments`` meet ``segment``'s direction at 45° or more."""
    if len(segments) == 0:
        return np.zeros(0, dtype=bool)
    d = segments[:, 2:4] - segments[:, 0:2]
    e = segment[2:4] - segment[0:2]
    cos = np.abs(d @ e) / np.maximum(np.hypot(d[:, 0], d[:, 1]) * math.hypot(*e), 1e-12)
    return cos < math.cos(math.radians(45.0))


def _behind(points: np.ndarray, robot: np.ndarray, lines: np.ndarray) -> np.ndarray:
    """Which returns lie behind a structure line their beam crossed, farther than the
    line's band beyond it: a far wall's noise (at 300 in a range finder with 1 % error is
    3 in off, and now and then three times that), for nothing seen through a wall is
    there. The lines are taken as they were seen, not extended (a doorway beside a
    wall's end is open)."""
    behind = np.zeros(len(points), dtype=bool)
    if len(lines) == 0 or len(points) == 0:
        return behind
    beam = points - robot  # (N, 2)
    a, edge = lines[:, 0:2], lines[:, 2:4] - lines[:, 0:2]  # (M, 2)
    q = a - robot
    denominator = beam[:, None, 0] * edge[None, :, 1] - beam[:, None, 1] * edge[None, :, 0]
    with np.errstate(divide="ignore", invalid="ignore"):
        t = (q[None, :, 0] * edge[None, :, 1] - q[None, :, 1] * edge[None, :, 0]) / denominator
        u = (q[None, :, 0] * beam[:, None, 1] - q[None, :, 1] * beam[:, None, 0]) / denominator
    length = np.hypot(beam[:, 0], beam[:, 1])[:, None]
    crossed = (np.abs(denominator) > 1e-12) & (u >= 0.0) & (u <= 1.0) & (t > 0.0)
    return (crossed & ((1.0 - t) * length > lines[None, :, 4])).any(axis=1)


def _signed_offset(points: np.ndarray, segment: np.ndarray, towards: np.ndarray) -> np.ndarray:
    """Offsets of points from a segment's line, positive on the side of ``towards``."""
    a, b = segment[0:2], segment[2:4]
    direction = (b - a) / max(float(np.hypot(*(b - a))), 1e-12)
    normal = np.array([-direction[1], direction[0]])
    if (towards - a) @ normal < 0:
        normal = -normal
    return (points - a) @ normal


LegSets = tuple[tuple[int, int, int, int], ...]
"""Sets of four track ids, each judged a table's legs."""


class CandidateFinder:
    """Object candidates from scans at corrected poses, fused into tracks with stable ids."""

    def __init__(self, settings: CandidateSettings = CandidateSettings()) -> None:
        self.settings = settings
        self.structure = StructureLines(settings.extend_in)
        self._tracks: dict[int, _Track] = {}
        self._scans = 0  # counts changes to the tracks and structure lines (each observe and update)
        self._reading: tuple[int, list[Candidate], dict[int, Candidate], LegSets] | None = None  # _read's, at _scans
        self._next_id = 1

    def update(self, scan: PlanarScan, pose: Pose | None = None) -> list[Observation]:
        """Read one scan taken at ``pose`` (the corrected pose; default: the scan's own):
        its structure lines join the known ones, its observations the tracks. Returns the
        observations, for inspection."""
        observations = self.observe(scan, pose)
        for observation in observations:
            self._associate(observation)
        self._scans += 1  # the tracks changed after the structure did
        return observations

    def observe(self, scan: PlanarScan, pose: Pose | None = None) -> list[Observation]:
        """The scan's object-like runs (and its structure lines added to the known ones)."""
        self._scans += 1
        s = self.settings
        x0, y0, heading = (scan.x_in, scan.y_in, scan.heading_deg) if pose is None else (
            pose.x_in, pose.y_in, pose.heading_deg)
        robot = np.array([x0, y0])
        seen = scan.returned
        angles = np.mod(scan.angles_rad[seen], 2.0 * math.pi)
        order = np.argsort(angles, kind="stable")
        angles, ranges = angles[order], scan.ranges_in[seen][order]
        if len(ranges) == 0:
            return []
        world = math.radians(heading) + angles
        points = np.column_stack([x0 + ranges * np.cos(world), y0 + ranges * np.sin(world)])
        apart = _breakpoints(points, ranges, angles, s)
        starts = [0, *(np.nonzero(apart)[0] + 1).tolist()]
        clusters = [np.arange(lo, hi) for lo, hi in zip(starts, starts[1:] + [len(points)])]
        if len(clusters) > 1 and not _breakpoints(points[[-1, 0]], ranges[[-1, 0]],
                                                  np.array([angles[-1], angles[0] + 2 * math.pi]), s)[0]:
            clusters = [np.concatenate([clusters[-1], clusters[0]]), *clusters[1:-1]]  # round the back

        new_lines = []
        for cluster in clusters:
            for lo, hi in split_and_merge(points[cluster], s.split_in):
                piece = points[cluster[lo:hi + 1]]
                if len(piece) >= s.structure_min_points and math.dist(piece[0], piece[-1]) >= s.structure_min_in:
                    line = _line_fit(piece, s)
                    if line is not None:
                        new_lines.append(line)
        scan_lines = np.array(new_lines).reshape(-1, 5)
        self.structure.add(scan_lines)
        lines = self.structure.segments
        distances = self.structure.distances(points, lines)
        on_line = distances <= lines[None, :, 4]
        proud = self._proud(points, clusters, scan_lines, robot)
        structural = on_line.any(axis=1) & ~proud
        line_of = np.full(len(points), -1)
        if len(lines):
            line_of[structural] = np.argmin(np.where(on_line, distances, np.inf)[structural], axis=1)
        near = (distances <= s.lone_near_in).any(axis=1)

        behind = _behind(points, robot, lines)
        observations = []
        for cluster in clusters:
            for run in _runs(cluster, structural, points, s.run_gap_in):
                run_points = points[run]
                if _extent(run_points) > s.max_extent_in:
                    continue
                if 2 * int(behind[run].sum()) > len(run):
                    continue
                if len(run) == 1 and near[run[0]]:
                    continue
                if self._attached(run, cluster, structural, line_of, points, lines, robot):
                    continue
                observations.append(Observation(run_points, scan.stamp_s, proud[run]))
        return observations

    def _proud(self, points: np.ndarray, clusters: list[np.ndarray], scan_lines: np.ndarray,
               robot: np.ndarray) -> np.ndarray:
        """Which returns stand proud of a wall they lie against: within twice the band of
        a line this scan fitted (an object against a wall is no deeper than that where the
        band could take it), in front of it (towards the robot) by more than
        ``proud_sigmas`` times the noise of that line's own returns (and never less than
        ``front_min_in``), and so in front of every other line of this scan whose band
        they lie in, and in front by ``front_min_in`` of every known line at 45° or more
        to it whose band they lie in (a wall meeting it at a corner is not proud of it),
        in runs of at least ``proud_min_returns`` neighbours. Known lines nearer its
        direction are not asked: one fitted from afar across a wall and the object
        against it (a chord from the wall to the object's front, within the band of both)
        would hide the object for good.

        A band wide enough to take in a far wall's noise swallows a can 0.7 in from the
        wall; the wall beside the can, measured in the same scan, is known to a small
        part of that (the pose's error is the same for both, the noise is the range
        finder's at that range), so the can stands out of it."""
        s = self.settings
        proud = np.zeros(len(points), dtype=bool)
        if len(scan_lines) == 0:
            return proud
        distances = self.structure.distances(points, scan_lines)
        own, near = distances <= scan_lines[None, :, 4], distances <= 2.0 * scan_lines[None, :, 4]
        on_known = self.structure.within_each(points)
        allowed = np.ones(len(points), dtype=bool)
        for j, segment in enumerate(scan_lines):
            offset = _signed_offset(points, segment, robot)
            inliers = offset[own[:, j]]
            noise = 1.4826 * float(np.median(np.abs(inliers - np.median(inliers)))) if len(inliers) else 0.0
            ahead = offset > max(s.front_min_in, s.proud_sigmas * noise)
            across = _across(self.structure.segments, segment)
            for k in np.nonzero(across)[0]:  # a wall meeting this one at a corner: proud of it too
                ahead &= ~on_known[:, k] | (_signed_offset(points, self.structure.segments[k], robot) > s.front_min_in)
            proud |= near[:, j] & ahead
            allowed &= ~own[:, j] | ahead
        proud &= allowed
        kept = np.zeros(len(points), dtype=bool)
        for cluster in clusters:
            flags = proud[cluster]
            start = None
            for k, flag in enumerate([*flags, False]):
                if flag and start is None:
                    start = k
                elif not flag and start is not None:
                    if k - start >= s.proud_min_returns:
                        kept[cluster[start:k]] = True
                    start = None
        return kept

    def _attached(self, run: np.ndarray, cluster: np.ndarray, structural: np.ndarray, line_of: np.ndarray,
                  points: np.ndarray, lines: np.ndarray, robot: np.ndarray) -> bool:
        """Whether the run touches, at either end, a structure line it does not stand in front of."""
        position = {int(index): k for k, index in enumerate(cluster)}
        for end, step in ((int(run[0]), -1), (int(run[-1]), 1)):
            k = position[end] + step
            if not 0 <= k < len(cluster):
                continue
            neighbour = int(cluster[k])
            if not structural[neighbour]:
                continue
            offset = _signed_offset(points[run], lines[line_of[neighbour]], robot)
            if float(np.median(offset)) < self.settings.front_min_in:
                return True
        return False

    @property
    def widest_in(self) -> float:
        """The widest a track of one object grows: an object's size and its outline's noise."""
        return self.settings.max_extent_in + self.settings.widen_sigmas * self.settings.range_sigma_in

    def _associate(self, observation: Observation) -> None:
        """Join the observation to the tracks it meets (nearest first, as long as together
        they stay no wider than an object), or start a track. An observation that meets
        tracks but would widen the nearest beyond an object is dropped: it joins two
        things that are apart (a table leg and a bottle 10 in beyond it, seen along one
        line with a beam lost between them)."""
        s = self.settings
        centroid = observation.centroid
        matches = []
        for track in self._within_reach(observation.points, centroid):
            gap = float(np.hypot(*(observation.points[:, None, :] - track.points[None, :, :]).transpose(2, 0, 1)).min())
            if gap <= s.associate_in or (
                    math.dist(centroid, track.centre) <= s.associate_centroid_in
                    and _extent(np.vstack([track.points, observation.points])) <= s.max_extent_in):
                matches.append((gap, track.id, track))
        proud: set[tuple[int, int]] = set()
        if observation.proud is not None and observation.proud.any():
            keys = np.floor(observation.points[observation.proud] / s.outline_voxel_in).astype(np.int64)
            proud = {(int(a), int(b)) for a, b in keys}
        if not matches:
            track = _Track(self._next_id, _thin(observation.points, s.outline_voxel_in), 1, observation.stamp_s,
                           observation.stamp_s, proud)
            self._tracks[track.id] = track
            self._next_id += 1
            return
        joined, points = [], [observation.points]
        for _, _, track in sorted(matches, key=lambda m: m[:2]):
            if _extent(np.vstack([*points, track.points])) <= self.widest_in:
                joined.append(track)
                points.append(track.points)
        if not joined:
            return
        keep = min(joined, key=lambda t: t.id)
        keep.reshape(_thin(np.vstack(points), s.outline_voxel_in))
        keep.seen = sum(t.seen for t in joined) + 1
        keep.first_s = min(t.first_s for t in joined)
        keep.last_s = max(observation.stamp_s, *(t.last_s for t in joined))
        keep.proud = proud.union(*(t.proud for t in joined))
        for t in joined:
            if t is not keep:
                del self._tracks[t.id]

    def _within_reach(self, points: np.ndarray, centroid: np.ndarray) -> list[_Track]:
        """The tracks an observation of ``points`` might join: those whose bounding box
        lies within ``associate_in`` of the observation's, or whose centre lies within
        ``associate_centroid_in`` of ``centroid`` (with a micro-inch to spare, so the
        exact tests in :meth:`_associate` decide). The gap between two boxes is never
        more than between the points in them, so no match is left out; and most tracks,
        across the room, are passed over in one array operation, not one each."""
        tracks = list(self._tracks.values())
        if not tracks:
            return []
        s, spare = self.settings, 1e-6
        low, high = points.min(axis=0), points.max(axis=0)
        lows, highs = np.array([t.low for t in tracks]), np.array([t.high for t in tracks])
        box_gap = np.hypot(*np.maximum(0.0, np.maximum(lows - high, low - highs)).T)
        centre_gap = np.hypot(*(np.array([t.centre for t in tracks]) - centroid).T)
        reach = (box_gap <= s.associate_in + spare) | (centre_gap <= s.associate_centroid_in + spare)
        return [track for track, near in zip(tracks, reach) if near]

    def tracks(self) -> tuple[Candidate, ...]:
        """Every track, whatever the rules say of it, by id."""
        return tuple(_candidate(t.id, t.points, t) for t in sorted(self._tracks.values(), key=lambda t: t.id))

    def _off_structure(self) -> list[Candidate]:
        """The tracks seen ``min_seen`` times, each cut to the part of its outline off the
        structure lines (returns of the wall beside an object join its track when they
        fall just outside a band), left out when fewer than ``min_outline_points`` remain."""
        kept = []
        for track in sorted(self._tracks.values(), key=lambda t: t.id):
            if track.seen < self.settings.min_seen:
                continue
            keys = np.floor(track.points / self.settings.outline_voxel_in).astype(np.int64)
            proud = np.array([(int(a), int(b)) in track.proud for a, b in keys], dtype=bool)
            off = track.points[proud | ~self.structure.within(track.points)]
            if len(off) >= self.settings.min_outline_points:
                kept.append(_candidate(track.id, off, track))
        return kept

    def table_legs(self) -> LegSets:
        """Ids of the sets of four small tracks judged a table's legs."""
        return self._read()[2]

    def table_tops(self) -> tuple[np.ndarray, ...]:
        """Each table's top as the base meets it (:func:`table_top`): a planar scan sees
        only the legs, and a base driven between them stops against the top."""
        _, small, groups = self._read()
        return tuple(table_top([small[i] for i in group]) for group in groups)

    def _read(self) -> tuple[list[Candidate], dict[int, Candidate], LegSets]:
        """The tracks off the structure, the small ones by id, and the sets of four judged
        a table's legs: worked out once per change (:meth:`observe`, :meth:`update`), since the
        candidates and the tables' tops both ask for them after every scan."""
        if self._reading is None or self._reading[0] != self._scans:
            off = self._off_structure()
            small = self._small(off)
            self._reading = (self._scans, off, {c.id: c for c in small}, table_legs(small, self.settings))
        return self._reading[1:]

    def _small(self, candidates: list[Candidate]) -> list[Candidate]:
        """Those that may be a table's leg: their core no wider than ``leg_max_extent_in``."""
        return [c for c in candidates if c.core_extent_in <= self.settings.leg_max_extent_in]

    def candidates(self, grid: OccupancyGrid | None = None) -> tuple[Candidate, ...]:
        """The tracks the rules keep, by id, each with the part of its outline off the
        structure lines (module docstring)."""
        off, _, groups = self._read()
        legs = {i for group in groups for i in group}
        return tuple(c for c in off if c.id not in legs and c.extent_in <= self.widest_in
                     and (grid is None or (grid_supports(grid, c, self.settings)
                                           and not continues_structure(grid, c, self.settings))))


def _runs(cluster: np.ndarray, structural: np.ndarray, points: np.ndarray, gap_in: float) -> list[np.ndarray]:
    """The runs of consecutive non-structural returns of a cluster, cut where two
    neighbours are more than ``gap_in`` apart."""
    runs, current = [], []
    for index in cluster:
        if structural[index] or (current and math.dist(points[current[-1]], points[index]) > gap_in):
            if current:
                runs.append(np.array(current))
            current = []
        if not structural[index]:
            current.append(int(index))
    if current:
        runs.append(np.array(current))
    return runs


def _candidate(track_id: int, points: np.ndarray, track: _Track) -> Candidate:
    centre = points.mean(axis=0)
    outline = tuple((float(x), float(y)) for x, y in points)
    return Candidate(track_id, float(centre[0]), float(centre[1]), outline, _extent(points), track.seen,
                     track.first_s, track.last_s)


def table_legs(small: list[Candidate], settings: CandidateSettings = CandidateSettings()
               ) -> tuple[tuple[int, int, int, int], ...]:
    """Sets of four of ``small`` whose centroids stand at the corners of a rectangle of
    table size: both pairs of opposite sides and the two diagonals agree within
    ``table_tolerance_in``, the sides between ``table_min_in`` and ``table_max_in``. Each
    candidate is in at most one set (the first found, in id order)."""
    s = settings
    by_id = sorted(small, key=lambda c: c.id)
    reach = math.hypot(s.table_max_in, s.table_max_in) + s.table_tolerance_in  # the longest diagonal
    centres = np.array([(c.x_in, c.y_in) for c in by_id]).reshape(-1, 2)
    close = np.hypot(*(centres[:, None, :] - centres[None, :, :]).transpose(2, 0, 1)) <= reach
    used: set[int] = set()
    found = []
    for i, first in enumerate(by_id):  # only sets whose legs are all within a table's reach of each other
        later = [j for j in range(i + 1, len(by_id)) if close[i, j]]
        for rest in itertools.combinations(later, 3):
            four = (first, *(by_id[j] for j in rest))
            if used & {c.id for c in four} or not all(close[a, b] for a, b in itertools.combinations(rest, 2)):
                continue
            if _is_rectangle([(c.x_in, c.y_in) for c in four], s):
                found.append(tuple(c.id for c in four))
                used |= {c.id for c in four}
    return tuple(found)  # type: ignore[return-value]


def table_top(legs: Sequence[Candidate]) -> np.ndarray:
    """The top of the table whose four ``legs`` these are (a 4x2 polygon, world inches,
    counter-clockwise): the rectangle through the legs' centroids. The true top reaches
    half a leg beyond it (the legs stand flush with its corners), which the base's
    inflation covers many times over. Widening it by the legs' size as the scans see it
    put its edge inches out: range noise widens a 2 in leg to 5-10 in, and in the
    simulated apartment-2 a base the simulator had stopped against the true edge stood
    deeper inside the inflated top than a plan's start may be (``planner.paths.ESCAPE_LIMIT_IN``),
    so every view was priced unreachable and the exploration ended there."""
    centres = np.array([(c.x_in, c.y_in) for c in legs], dtype=float)
    middle = centres.mean(axis=0)
    return centres[np.argsort(np.arctan2(*(centres - middle).T[::-1]))]


def _is_rectangle(corners: list[tuple[float, float]], s: CandidateSettings) -> bool:
    """Whether four points, in some order, are a rectangle of table size."""
    p = np.array(corners)
    centre = p.mean(axis=0)
    order = np.argsort(np.arctan2(p[:, 1] - centre[1], p[:, 0] - centre[0]))
    a, b, c, d = p[order]
    sides = [math.dist(a, b), math.dist(b, c), math.dist(c, d), math.dist(d, a)]
    tol = s.table_tolerance_in
    return (abs(sides[0] - sides[2]) <= tol and abs(sides[1] - sides[3]) <= tol
            and abs(math.dist(a, c) - math.dist(b, d)) <= tol
            and all(s.table_min_in <= side <= s.table_max_in for side in sides))


def continues_structure(grid: OccupancyGrid, candidate: Candidate,
                        settings: CandidateSettings = CandidateSettings()) -> bool:
    """The candidate's outline is a straight piece of a longer face of the home: it is
    straight and at least ``face_min_in`` long (:func:`mapping.faces.straight_face`), and
    the occupied cells it lies on run on straight, beyond its ends, to at least
    ``face_run_min_in`` (:func:`mapping.faces.run_along`): longer than any object's face.
    The outline's core is asked (:meth:`Candidate.core`): a stray return of the wall
    beside a can would give the can a straight "face" along the wall.
    A nook's back wall seen between a wall and a wardrobe, or a counter's end face seen
    past its corner, is object-sized in every scan, and is a piece of wall in the map."""
    s = settings
    face = straight_face(candidate.core(), s.face_min_in, s.face_straight_in)
    if face is None:
        return False
    if face.length_in >= s.face_run_min_in:
        return True
    return run_along(grid, face, s.face_band_in, s.face_gap_in, s.face_run_min_in,
                     s.face_side_in) >= s.face_run_min_in


def grid_supports(grid: OccupancyGrid, candidate: Candidate, settings: CandidateSettings = CandidateSettings()) -> bool:
    """The grid agrees the candidate is there: at least ``support_share`` of its outline
    lies in occupied cells (range noise off a wall lands in cells the beams to the wall
    cross, which are free; a moved object's cells turn free), and at least
    ``ring_free_share`` of the ring around it (``ring_in`` beyond its half-extent from its
    centroid) has been seen free (it stands in the open, not inside unexplored space)."""
    s = settings
    outline = np.array(candidate.outline)
    rows, cols = (np.floor(v).astype(int) for v in grid.grid.to_cell(outline[:, 0], outline[:, 1]))
    height, width = grid.shape
    inside = (rows >= 0) & (rows < height) & (cols >= 0) & (cols < width)
    support = np.zeros(len(outline), dtype=bool)
    support[inside] = grid.occupied[rows[inside], cols[inside]]
    if not support.mean() > s.support_share:
        return False
    half = candidate.extent_in / 2.0
    reach = half + s.ring_in[1]
    r0, c0 = (math.floor(v) for v in grid.grid.to_cell(candidate.x_in - reach, candidate.y_in + reach))
    r1, c1 = (math.floor(v) + 1 for v in grid.grid.to_cell(candidate.x_in + reach, candidate.y_in - reach))
    r0, c0, r1, c1 = max(r0, 0), max(c0, 0), min(r1, height), min(c1, width)
    if r0 >= r1 or c0 >= c1:
        return False
    window = np.indices((r1 - r0, c1 - c0)).reshape(2, -1) + np.array([[r0], [c0]])
    centres = grid.grid.to_world(window[0], window[1])
    distance = np.hypot(centres[:, 0] - candidate.x_in, centres[:, 1] - candidate.y_in)
    ring = (distance > half + s.ring_in[0]) & (distance <= reach)
    return bool(ring.any() and grid.free[window[0][ring], window[1][ring]].mean() >= s.ring_free_share)
