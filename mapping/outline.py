"""An object's outline from the robot's own scans: its footprint, for training orientations.

The paper's training stage puts the robot square to each face of an object (sonar echoes
best off a face it meets squarely), and finds the faces from the object's footprint as
the ceiling camera sees it (docs/method.md §4). Without a ceiling camera the footprint
comes from planar range scans taken from a few poses around the object (the survey,
:func:`survey_plan`): the returns near the object, merged in world coordinates, are
fitted with a rectangle (every catalogue footprint is a rectangle or a circle) or, when
a circle explains them within the range noise, said to be round. The rectangle's
polygon is what ``learner.training.stage.training_orientations`` reads, exactly as it
reads the camera's (a training object stands alone, as the paper's did: nothing else
may be near it).

A face is *seen* when returns lie on it from a scan taken in front of it (a range
finder sees a face only from the side it faces). One scan sees at most two faces of a
box; a face it meets square-on hides the box's depth. Faces not seen are inferred from
those seen (a rectangle's hidden side is parallel to the one across, and ends where
the seen sides' returns end); when nothing says how deep the box is, the outline is the
seen face alone, flat (docs/mapping.md, "Training orientations from scans").
"""

from __future__ import annotations

import dataclasses
import math
from collections.abc import Sequence
from dataclasses import dataclass

import cv2
import numpy as np

from mapping.scan import PlanarScan
from planner.geometry import Pose, wrap_360

# Every catalogue footprint fits a 12 in square (the largest, the closed box, is 11 x 9
# in), so every return of a catalogue object lies within half its diagonal of the centre.
MAX_ACROSS_IN = 12.0
HALF_DIAGONAL_IN = MAX_ACROSS_IN / math.sqrt(2.0)
NOISE_SIGMAS = 4.0  # a return may stand this many range sigmas off its face
CENTRE_SLACK_IN = 4.0  # how far off the given centre may be: and the rim where nothing else may be
MAX_INCIDENCE_DEG = 75.0  # beams more slanted to a face are not fitted to it (grazing returns are a sensor's worst)
SIZE_TOLERANCE_IN = 1.0  # a fitted side may come out this much over MAX_ACROSS_IN
MIN_POINTS = 10  # fewer returns than this outline nothing
MIN_FACE_POINTS = 3  # returns a face needs to be seen (and its line fitted)
MIN_RIM_POINTS = 3  # returns beyond the object's reach that say something else is there
# A round footprint: a circle explains the returns within the range noise. Each return
# stands off the true outline by the range noise times the cosine of the beam's
# incidence on it, so a circle's own returns have an RMS residual about that noise's
# (the ratio is 1, with a standard error of 1/sqrt(2(n - 3)) for n returns); round when
# the ratio is within ROUND_SIGMAS of those standard errors over 1, the rectangle does
# not fit better by more than that either (a box's corner seen from one side, two
# faces, can pass for an arc within heavy noise; a rectangle fits it exactly), the
# circle is no wider than ROUND_MAX_ACROSS_IN (below), and the returns go round at least
# ROUND_MIN_ARC_DEG of it (a can seen from one side shows almost 180°; a flat face a
# small circle fits, far less).
ROUND_SIGMAS = 3.0
ROUND_MIN_ARC_DEG = 120.0
# Every round footprint in the catalogue is an upright cylinder no wider than 4 in (the
# 20 oz tumbler's); a wider circle that explains the returns is a lying cylinder's or a
# small box's rectangle blurred by the range noise, whose axis the executive needs (a
# lying can's grasp and sweeps are placed along it). Two SIZE_TOLERANCE_IN of slack for
# the radius a noisy arc fits.
ROUND_MAX_ACROSS_IN = 4.0
ROUND_POLYGON_SIDES = 36
COMPLETE_ARC_GAP_DEG = 90.0  # a round outline is complete when no gap round it is wider
# The survey: four views at 24 in (docs/mapping.md): every face of a box within 45° of
# a view's line, and the robot's 18 in base clear of a 12 in object's corners.
SURVEY_VIEWS = 4
SURVEY_STANDOFF_IN = 24.0
FIT_ITERATIONS = 20
START_STEP_DEG = 15.0  # the rectangle fit tries angles this far apart before refining the best
MAX_TURN_STEP_RAD = 0.2  # a linearised turn far from the solution overshoots: at most ~11° a step


@dataclass(frozen=True)
class Outline:
    """An object's footprint as the scans saw it, in world inches.

    ``polygon``: counter-clockwise; a rectangle's four corners (a flat one, two pairs of
    equal corners, when only one face was seen square-on), a round one's fitted circle as
    a regular 36-gon. ``seen``: for each of a rectangle's edges, whether returns lay on it
    from a scan in front of it (a round outline: empty). ``axis_deg``: the reference
    axis, along a rectangle's longer sides, in (-90, 90]; 0 for a round one (the camera's
    convention). ``axis_sigma_deg``: the fit's standard error of that angle (NaN when
    round): with it the robot knows when it has scanned enough (the range noise is
    averaged down by scanning again from the same poses; five standard errors under the
    bound wanted). ``points``: the returns the fit used; ``residual_in``: their RMS
    distance from the outline; ``scans``: the scans that gave any; ``complete``: every
    face was seen (round: the returns go all round, no gap over 90°).
    """

    polygon: tuple[tuple[float, float], ...]
    round: bool
    points: int
    residual_in: float
    centre: tuple[float, float]
    axis_deg: float
    axis_sigma_deg: float
    seen: tuple[bool, ...]
    scans: int
    complete: bool

    def seen_normals_deg(self) -> tuple[float, ...]:
        """The outward normals (world degrees) of the faces returns were seen on."""
        if self.round:
            return ()
        corners = np.asarray(self.polygon)
        out = []
        for i, seen in enumerate(self.seen):
            dx, dy = corners[(i + 1) % len(corners)] - corners[i]
            if seen:
                out.append(wrap_360(math.degrees(math.atan2(-dx, dy))))
        return tuple(out)

    def object_frame(self) -> tuple[tuple[float, float], ...]:
        """The polygon about the centre with +x along ``axis_deg``, to 0.001 in: a training
        object's footprint in its own frame, as the camera's is (a round one: empty)."""
        if self.round:
            return ()
        a = math.radians(self.axis_deg)
        cx, cy = self.centre
        return tuple((round((x - cx) * math.cos(a) + (y - cy) * math.sin(a), 3),
                      round(-(x - cx) * math.sin(a) + (y - cy) * math.cos(a), 3)) for x, y in self.polygon)


def survey_plan(centre: tuple[float, float], start: Pose | None = None, standoff_in: float = SURVEY_STANDOFF_IN,
                views: int = SURVEY_VIEWS) -> tuple[Pose, ...]:
    """The poses to scan an object from: ``views`` evenly round ``centre`` at
    ``standoff_in``, each facing the object, counter-clockwise from the one on the
    robot's side (``start``; else the first is on the object's +x side).

    Four views put every face of a box within 45° of one view's line, whatever its yaw;
    fewer leave faces edge-on or unseen (docs/mapping.md). The standoff must keep a
    view outside a catalogue object (half a 12 in square's diagonal from the centre).
    """
    if not all(math.isfinite(c) for c in centre):
        raise ValueError(f"survey: centre must be finite, got {centre}")
    if isinstance(views, bool) or not isinstance(views, int) or views < 1:
        raise ValueError(f"survey: views must be a whole number >= 1, got {views!r}")
    if not (math.isfinite(standoff_in) and standoff_in > HALF_DIAGONAL_IN):
        raise ValueError(f"survey: standoff_in must be over {HALF_DIAGONAL_IN:.1f} in (outside a "
                         f"{MAX_ACROSS_IN:g} in object), got {standoff_in}")
    cx, cy = centre
    first = 0.0
    if start is not None:
        start.require_finite("survey: start")
        if math.hypot(start.x_in - cx, start.y_in - cy) > 1e-9:
            first = math.degrees(math.atan2(start.y_in - cy, start.x_in - cx))
    poses = []
    for k in range(views):
        bearing = first + 360.0 * k / views
        b = math.radians(bearing)
        poses.append(Pose(cx + standoff_in * math.cos(b), cy + standoff_in * math.sin(b), wrap_360(bearing + 180.0)))
    return tuple(poses)


def outline(views: Sequence[tuple[PlanarScan, Pose]], centre: tuple[float, float],
            range_sigma_in: float) -> Outline:
    """The outline of the one object near ``centre`` from scans taken round it, each at
    its corrected pose; ``range_sigma_in``: the range finder's noise there.

    The returns within reach of the centre (how far a catalogue object's returns reach,
    :data:`HALF_DIAGONAL_IN` plus four range sigmas, plus :data:`CENTRE_SLACK_IN` for an
    approximate centre) are fitted; the returns are then
    gathered again round the fitted centre and fitted again. ValueError (one line) when
    there are too few returns, when returns lie in the rim beyond a catalogue object's
    reach (something else is there: a wall, another object, or something bigger), or
    when the fitted outline is wider than :data:`MAX_ACROSS_IN`.
    """
    if not (math.isfinite(range_sigma_in) and range_sigma_in > 0):
        raise ValueError(f"outline: range_sigma_in must be positive, got {range_sigma_in}")
    if not all(math.isfinite(c) for c in centre):
        raise ValueError(f"outline: centre must be finite, got {centre}")
    reach = HALF_DIAGONAL_IN + NOISE_SIGMAS * range_sigma_in
    radius = reach + CENTRE_SLACK_IN
    points, origins, view = _world_returns(views)
    where = f"({centre[0]:.1f}, {centre[1]:.1f})"

    near = np.hypot(*(points - centre).T) <= radius
    if np.count_nonzero(near) < MIN_POINTS:
        raise ValueError(f"outline: {np.count_nonzero(near)} returns within {radius:.1f} in of {where}, "
                         f"too few to outline (at least {MIN_POINTS})")
    first = _fit(points[near], origins[near], range_sigma_in)
    distance = np.hypot(*(points - first.centre).T)
    near = distance <= radius
    if np.count_nonzero(near) < MIN_POINTS:
        raise ValueError(f"outline: {np.count_nonzero(near)} returns within {radius:.1f} in of the fitted "
                         f"centre, too few to outline (at least {MIN_POINTS})")
    rim = np.count_nonzero(near & (distance > reach))
    if rim >= MIN_RIM_POINTS:
        raise ValueError(f"outline: {rim} returns lie {reach:.1f}-{radius:.1f} in from the object near {where}, "
                         f"beyond a {MAX_ACROSS_IN:g} in object's reach: it is not alone, or bigger")
    found = _fit(points[near], origins[near], range_sigma_in)
    corners = np.asarray(found.polygon)
    if found.round:
        across = 2.0 * float(np.max(np.hypot(*(corners - found.centre).T)))
    else:
        across = max(math.dist(corners[0], corners[1]), math.dist(corners[1], corners[2]))
    if across > MAX_ACROSS_IN + SIZE_TOLERANCE_IN:
        raise ValueError(f"outline: the object near {where} is {across:.1f} in across, more than the "
                         f"catalogue's {MAX_ACROSS_IN:g} in")
    return dataclasses.replace(found, scans=len(np.unique(view[near])))


# -- Returns ------------------------------------------------------------------------------
def _world_returns(views: Sequence[tuple[PlanarScan, Pose]]) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Every return in world inches (Nx2), the position it was seen from (Nx2) and the
    index of its view (N)."""
    points, origins, index = [np.zeros((0, 2))], [np.zeros((0, 2))], [np.zeros(0, dtype=int)]
    for i, (scan, pose) in enumerate(views):
        pose.require_finite(f"outline: views[{i}]")
        seen = scan.world_points(pose.x_in, pose.y_in, pose.heading_deg)
        points.append(seen)
        origins.append(np.tile([pose.x_in, pose.y_in], (len(seen), 1)))
        index.append(np.full(len(seen), i))
    return np.concatenate(points), np.concatenate(origins), np.concatenate(index)


# -- Fitting ------------------------------------------------------------------------------
def _fit(points: np.ndarray, origins: np.ndarray, sigma: float) -> Outline:
    """The rectangle, or the circle if the returns are round (:data:`ROUND_SIGMAS`); its
    ``scans`` are the caller's to say."""
    rect = _Rectangle.fit(points, origins, sigma)
    corners = rect.corners()
    rect_rms = _rms(_boundary_distance(points, corners))
    circle = _fit_circle(points)
    n = len(points)
    if circle is not None and n > 3:
        (cx, cy), r = circle
        rel = points - (cx, cy)
        distance = np.maximum(np.hypot(rel[:, 0], rel[:, 1]), 1e-9)
        beams = points - origins
        beams /= np.maximum(np.hypot(beams[:, 0], beams[:, 1]), 1e-9)[:, None]
        incidence_cos = np.abs(np.einsum("ij,ij->i", rel / distance[:, None], beams))
        noise_rms = sigma * math.sqrt(float(np.mean(incidence_cos ** 2)) * (n - 3) / n)
        circle_rms = _rms(distance - r)
        angles = np.sort(np.arctan2(rel[:, 1], rel[:, 0]))
        widest_gap = math.degrees(float(np.diff(np.concatenate([angles, angles[:1] + 2.0 * math.pi])).max()))
        within = 1.0 + ROUND_SIGMAS / math.sqrt(2.0 * (n - 3))  # a ratio of RMS residuals the noise explains
        if (circle_rms <= noise_rms * within and circle_rms <= rect_rms * within
                and 2.0 * r <= ROUND_MAX_ACROSS_IN + 2.0 * SIZE_TOLERANCE_IN
                and 360.0 - widest_gap >= ROUND_MIN_ARC_DEG):
            polygon = tuple((cx + r * math.cos(2.0 * math.pi * k / ROUND_POLYGON_SIDES),
                             cy + r * math.sin(2.0 * math.pi * k / ROUND_POLYGON_SIDES))
                            for k in range(ROUND_POLYGON_SIDES))
            return Outline(polygon, True, n, circle_rms, (cx, cy), 0.0, math.nan, (), 0,
                           widest_gap <= COMPLETE_ARC_GAP_DEG)
    centre = corners.mean(axis=0)
    return Outline(tuple((float(x), float(y)) for x, y in corners), False, n, rect_rms,
                   (float(centre[0]), float(centre[1])), rect.axis_deg(), math.degrees(rect.theta_sigma), rect.seen,
                   0, all(rect.seen))


def _rms(values: np.ndarray) -> float:
    return float(np.sqrt(np.mean(np.square(values)))) if len(values) else 0.0


def _fit_circle(points: np.ndarray) -> tuple[tuple[float, float], float] | None:
    """Least-squares circle: the algebraic (Kasa) fit refined by Gauss-Newton on the
    geometric distances. None when the returns fit no circle (collinear)."""
    x, y = points[:, 0], points[:, 1]
    design = np.column_stack([2.0 * x, 2.0 * y, np.ones_like(x)])
    solution, *_ = np.linalg.lstsq(design, x * x + y * y, rcond=None)
    a, b, c = solution
    r2 = c + a * a + b * b
    if not (np.isfinite(r2) and r2 > 0):
        return None
    params = np.array([a, b, math.sqrt(r2)])
    for _ in range(10):
        dx, dy = x - params[0], y - params[1]
        rho = np.maximum(np.hypot(dx, dy), 1e-9)
        jacobian = np.column_stack([-dx / rho, -dy / rho, -np.ones_like(x)])
        step, *_ = np.linalg.lstsq(jacobian, -(rho - params[2]), rcond=None)
        params = params + step
        if not np.isfinite(params).all():
            return None
        if np.abs(step).max() < 1e-9:
            break
    return (float(params[0]), float(params[1])), abs(float(params[2]))


def nearest_on_outline(points: np.ndarray, polygon: np.ndarray) -> np.ndarray:
    """For each point (Nx2), the nearest point on the closed polygon's edges (Nx2)."""
    a, b = polygon, np.roll(polygon, -1, axis=0)
    ab = b - a
    length2 = np.sum(ab * ab, axis=1)
    along = np.einsum("nmk,mk->nm", points[:, None, :] - a[None], ab)
    t = np.clip(np.divide(along, length2, out=np.zeros_like(along), where=length2 >= 1e-12), 0.0, 1.0)
    foot = a[None] + t[..., None] * ab[None]
    best = np.argmin(np.sum((points[:, None, :] - foot) ** 2, axis=2), axis=1)
    return foot[np.arange(len(points)), best]


def _boundary_distance(points: np.ndarray, corners: np.ndarray) -> np.ndarray:
    """Each point's distance to the nearest edge of a closed polygon."""
    return np.hypot(*(points - nearest_on_outline(points, corners)).T)


class _Rectangle:
    """A rectangle about ``centre``: side ``s`` (0-3, counter-clockwise from the one
    facing ``theta - 90°``) has outward normal ``theta + (s - 1) 90°`` and lies
    ``offsets[s]`` from the centre along it. ``theta_sigma``: the standard error of
    ``theta`` (radians) from the last fit."""

    def __init__(self, centre: np.ndarray, theta: float, offsets: np.ndarray) -> None:
        self.centre, self.theta, self.offsets = centre, theta, offsets
        self.seen: tuple[bool, ...] = (False,) * 4
        self.theta_sigma = math.nan

    def normals(self, theta: float | None = None) -> np.ndarray:
        t = self.theta if theta is None else theta
        angles = t + (np.arange(4) - 1) * (math.pi / 2.0)
        return np.column_stack([np.cos(angles), np.sin(angles)])

    def corners(self) -> np.ndarray:
        e1, e2 = self.normals()[1], self.normals()[2]
        h = self.offsets
        return np.array([self.centre + sx * e1 + sy * e2
                         for sx, sy in ((-h[3], -h[0]), (h[1], -h[0]), (h[1], h[2]), (-h[3], h[2]))])

    def axis_deg(self) -> float:
        """Along the longer sides, in (-90, 90]."""
        length, width = self.offsets[1] + self.offsets[3], self.offsets[0] + self.offsets[2]
        axis = (math.degrees(self.theta) + (90.0 if width > length else 0.0) + 90.0) % 180.0 - 90.0
        return 90.0 if axis == -90.0 else axis

    @classmethod
    def fit(cls, points: np.ndarray, origins: np.ndarray, sigma: float) -> _Rectangle:
        """The rectangle whose sides best predict the returns' ranges: the angles every
        START_STEP_DEG round a quarter turn are tried (sides placed at that angle, not
        turned), and the best refined (:meth:`fit_from`). Refining alone would stop at
        the fit nearest its start: with a box's faces seen square-on from one view each,
        a start a few degrees off can settle there."""
        (cx, cy), _, _ = cv2.minAreaRect(points.astype(np.float32))
        centre = np.array([cx, cy], dtype=float)
        gate = max(NOISE_SIGMAS * sigma, 1.0)
        tried = [cls.fit_from(points, origins, sigma, centre, math.radians(k * START_STEP_DEG))
                 for k in range(round(90.0 / START_STEP_DEG))]
        return min(tried, key=lambda rect: rect.cost(points, origins, gate))

    @classmethod
    def fit_from(cls, points: np.ndarray, origins: np.ndarray, sigma: float, centre: np.ndarray,
                 theta: float, turn: bool = True) -> _Rectangle:
        """Started from the rectangle at ``theta`` round the returns: each return given
        to the side its beam enters through, then the sides' offsets and one angle for
        all four (``turn``; else the offsets alone) fitted to the returns' ranges
        (:meth:`_solve`), until the angle settles."""
        rect = cls(centre, theta, np.zeros(4))
        rect.offsets = ((points - centre) @ rect.normals().T).max(axis=0)
        gate = max(NOISE_SIGMAS * sigma, 1.0)
        for iteration in range(FIT_ITERATIONS if turn else 2):
            side, inlier, usable = rect._assign(points, origins, gate if iteration else np.inf)
            fitted = np.bincount(side[usable], minlength=4) >= MIN_FACE_POINTS
            if not fitted.any():
                break  # nothing to fit: the starting rectangle stays
            delta = rect._solve(points, origins, side, usable, fitted)
            if turn:
                rect.theta += delta
            rect._fill_unseen(points, side, inlier, fitted)
            rect.seen = tuple(bool(f) for f in fitted)
            if turn and abs(delta) < 1e-7 and iteration:
                break
        return rect

    def cost(self, points: np.ndarray, origins: np.ndarray, gate: float) -> float:
        """How badly the rectangle predicts the returns: the sum over returns of the
        squared range error along the beam, each at most ``gate`` squared (a beam that
        misses the rectangle, or meets it more than ``gate`` from its return, costs that)."""
        normals = self.normals()
        rel, start = points - self.centre, origins - self.centre
        beam = rel - start
        measured = np.hypot(beam[:, 0], beam[:, 1])
        beam /= np.maximum(measured, 1e-12)[:, None]
        out, speed = start @ normals.T, beam @ normals.T
        with np.errstate(divide="ignore", invalid="ignore"):
            t_in = np.where(speed < -1e-12, (self.offsets - out) / speed, -np.inf).max(axis=1)
            t_out = np.where(speed > 1e-12, (self.offsets - out) / speed, np.inf).min(axis=1)
        error = np.where(t_in <= t_out, np.abs(measured - t_in), gate)
        return float(np.sum(np.minimum(error, gate) ** 2))

    def _assign(self, points: np.ndarray, origins: np.ndarray,
                gate: float) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """Each return's side, whether it lies within ``gate`` of it (along its beam when
        the beam enters the rectangle: a slanted beam that strays onto the face beside is
        off by more there than across), and whether its beam meets the side at most
        MAX_INCIDENCE_DEG off its normal (usable for the fit).

        The side is the one the return's beam enters the rectangle through, else (a beam
        that misses it) the nearest side facing the scan: range noise moves a return along
        its beam, and by nearness alone a return pushed inside near a corner would go to
        the side beside and turn the rectangle."""
        normals = self.normals()
        rel, start = points - self.centre, origins - self.centre
        along = rel @ normals.T  # Nx4: each return's distance out along each side's normal
        facing = start @ normals.T > self.offsets
        nearest = np.argmin(np.where(facing, np.abs(along - self.offsets), np.inf), axis=1)
        beam = rel - start
        beam /= np.maximum(np.hypot(beam[:, 0], beam[:, 1]), 1e-12)[:, None]
        out, speed = start @ normals.T, beam @ normals.T  # per side: where the beam starts, how fast it goes out
        with np.errstate(divide="ignore", invalid="ignore"):
            entering = np.where(speed < -1e-12, (self.offsets - out) / speed, -np.inf)
            leaving = np.where(speed > 1e-12, (self.offsets - out) / speed, np.inf)
        t_in = entering.max(axis=1)
        enters = t_in <= leaving.min(axis=1)
        side = np.where(enters, np.argmax(entering, axis=1), nearest)
        rows = np.arange(len(points))
        off = np.where(enters, np.abs(np.hypot(*(rel - start).T) - np.where(enters, t_in, 0.0)),  # along the beam
                       np.abs(along[rows, side] - self.offsets[side]))
        inlier = (enters | facing[rows, side]) & (off <= gate)
        square = -speed[rows, side] >= math.cos(math.radians(MAX_INCIDENCE_DEG))
        return side, inlier, inlier & square

    def _solve(self, points: np.ndarray, origins: np.ndarray, side: np.ndarray, usable: np.ndarray,
               fitted: np.ndarray) -> float:
        """One Gauss-Newton step on the ranges: the fitted sides' offsets (set) and the
        turn (returned) that best predict each usable return's range along its beam.

        Ranges, not distances from the sides: range noise moves a return along its beam,
        which at a slant to a face moves it along the face too, and a fit of distances
        that also turns the sides takes part of that motion for a turn (a bias that grows
        with the square of the noise, about 1° at 0.5 in). A beam's origin and direction
        carry no range noise, so the predicted ranges do not either."""
        use = usable & fitted[side]
        rel, start = points[use] - self.centre, origins[use] - self.centre
        measured = np.hypot(*(rel - start).T)
        beam = (rel - start) / np.maximum(measured, 1e-12)[:, None]
        s = side[use]
        n, t = self.normals()[s], self.normals(self.theta + math.pi / 2.0)[s]  # t: d(normal)/d(theta)
        cos = np.einsum("ij,ij->i", n, beam)  # negative: the beam goes in through the side
        gap = self.offsets[s] - np.einsum("ij,ij->i", n, start)  # from the origin out to the side's line
        predicted = gap / cos
        columns = [k for k in range(4) if fitted[k]]
        design = np.zeros((len(s), 1 + len(columns)))
        design[:, 0] = (-np.einsum("ij,ij->i", t, start) * cos - gap * np.einsum("ij,ij->i", t, beam)) / cos ** 2
        for j, k in enumerate(columns):
            design[s == k, 1 + j] = 1.0 / cos[s == k]
        residual = measured - predicted
        solution, *_ = np.linalg.lstsq(design, residual, rcond=None)
        dof = len(s) - design.shape[1]
        if dof > 0:
            variance = float(np.sum(np.square(residual - design @ solution))) / dof
            self.theta_sigma = math.sqrt(variance * float(np.linalg.pinv(design.T @ design)[0, 0]))
        for j, k in enumerate(columns):
            self.offsets[k] += float(solution[1 + j])
        return float(np.clip(solution[0], -MAX_TURN_STEP_RAD, MAX_TURN_STEP_RAD))

    def _fill_unseen(self, points: np.ndarray, side: np.ndarray, inlier: np.ndarray, fitted: np.ndarray) -> None:
        """A side with too few returns ends where the returns of the sides beside it end
        (grazing ones too: they are not fitted, but they show how far a face goes); with
        none there either, it lies on the side across (the depth was not seen)."""
        normals = self.normals()
        flat = []
        for s in range(4):
            if fitted[s]:
                continue
            beside = inlier & ((side == (s + 1) % 4) | (side == (s + 3) % 4))
            if beside.any():
                self.offsets[s] = float(((points[beside] - self.centre) @ normals[s]).max())
            else:
                flat.append(s)
        for s in flat:
            self.offsets[s] = -self.offsets[(s + 2) % 4]
