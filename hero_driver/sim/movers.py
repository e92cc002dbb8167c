"""Moving obstacles: people and carts crossing the floor while the robot works.

The paper's CSL "can not handle ... moving obstacles" (docs/method.md); the simulator
makes them so the driver's safety stop and the executive's blocked-move branch can be
tested. Two sources, both seeded and repeatable (docs/simulator.md, "Moving obstacles"):

- a world file's ``movers`` list: a person (``disc``) or a cart (``box``) walking a
  path of points back and forth at ``speed_in_s``, starting ``start_in`` along it;
- a ``--movers N[:SPEED]`` preset: N movers, people and carts in turn, each crossing
  the room wall to wall on a straight line drawn from the world's seed.

Movers are kinematic pymunk bodies advanced with the simulated clock, in steps of at
most ``STEP_S``, during every verb that takes robot time. Their shapes collide with
nothing and every query of the rest of the simulator filters them out: people step
over objects on the floor and the sonar looks past their legs. The overhead camera
draws them as obstacles (:meth:`Movers.outlines`). Only the robot's base
meets them, and a mover never walks into the base: it waits while its next step would
bring it within ``YIELD_GAP_IN`` of it (people give way to a robot). A person kept
waiting ``PATIENCE_S`` steps aside to walk round the robot (behind it if it can), back
onto the path once past; a cart kept waiting turns round and goes back the way it came. So a contact
happens only when the robot drives into a mover, which the driver's safety stop
(``blocked_moves``, docs/driver-protocol.md "Moving obstacles") prevents.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np
import pymunk

from hero_driver.sim.catalogue import FieldReader

SHAPES = ("disc", "box")
STEP_S = 0.5  # movers and the base advance together in steps of at most this much robot time
STRIDE_IN = 3.0  # a mover's position is checked at least every this many inches it walks
YIELD_GAP_IN = 8.0  # a mover waits rather than come closer than this to the robot's base (beyond its safety stop)
PASS_GAP_IN = 2.0  # walking round the robot, a person passes it this close
PATIENCE_S = 10.0  # a person kept waiting this long by the robot walks round it
MAX_ASIDE_IN = 60.0  # the farthest a mover steps off its path to walk round the robot
PERSON_RADIUS_IN = 9.0  # a preset person: a disc of this radius (shoulder width 18 in)
CART_SIZE_IN = (30.0, 20.0)  # a preset cart: a box this long (along its path) and wide
PRESET_SPEED_IN_S = 12.0  # a preset mover's speed unless the preset gives one (a slow walk is ~40)
WALL_CLEARANCE_IN = 2.0  # a preset path ends this far from the walls (plus the mover's reach)
OUTLINE_SEGMENTS = 48  # a person's disc is drawn as a polygon of this many sides
NEVER_MOVES = pymunk.ShapeFilter(categories=0, mask=0)  # no collision, no query of the simulator sees it


@dataclass(frozen=True)
class MoverSpec:
    """One moving obstacle: a ``disc`` of ``radius_in`` (a person) or a ``box``
    ``length_in`` x ``width_in`` along its direction of travel (a cart), walking
    ``path`` (world points, at least two) back and forth at ``speed_in_s``, starting
    ``start_in`` inches along it."""

    shape: str
    path: tuple[tuple[float, float], ...]
    speed_in_s: float
    radius_in: float = PERSON_RADIUS_IN
    length_in: float = CART_SIZE_IN[0]
    width_in: float = CART_SIZE_IN[1]
    start_in: float = 0.0

    @property
    def reach_in(self) -> float:
        """How far the mover's outline reaches from its centre."""
        return self.radius_in if self.shape == "disc" else math.hypot(self.length_in, self.width_in) / 2


@dataclass(frozen=True)
class MoverPreset:
    """``--movers N[:SPEED]``: N movers crossing the room, at SPEED in/s."""

    count: int = 0
    speed_in_s: float = PRESET_SPEED_IN_S

    @property
    def active(self) -> bool:
        return self.count > 0


def parse_movers(text: str) -> MoverPreset:
    """``--movers``' value: ``N`` or ``N:SPEED`` (one error line naming the flag)."""
    count_text, _, speed_text = text.partition(":")
    try:
        count = int(count_text)
    except ValueError:
        raise ValueError(f"--movers: {text!r}: expected N or N:SPEED with N a whole number") from None
    if not 0 <= count <= 20:
        raise ValueError(f"--movers: {text!r}: N must be from 0 to 20")
    speed = PRESET_SPEED_IN_S
    if speed_text:
        try:
            speed = float(speed_text)
        except ValueError:
            raise ValueError(f"--movers: {text!r}: SPEED must be a number of inches per second") from None
        if not (math.isfinite(speed) and 0.0 < speed <= 200.0):
            raise ValueError(f"--movers: {text!r}: SPEED must be above 0 and at most 200 in/s")
    return MoverPreset(count, speed)


def parse_movers_field(raw: object, source: str, width: float, depth: float) -> tuple[MoverSpec, ...]:
    """A world file's ``movers`` array: each path inside the ``width`` x ``depth`` room."""
    if raw is None:
        return ()
    if not isinstance(raw, list):
        raise ValueError(f"{source}: world: field 'movers' must be an array")
    out = []
    for i, item in enumerate(raw):
        r = FieldReader(source, f"movers[{i}]", item)
        r.only("shape", "path", "speed_in_s", "radius_in", "length_in", "width_in", "start_in")
        shape = r.text("shape", SHAPES)
        assert shape is not None
        allowed = ("radius_in",) if shape == "disc" else ("length_in", "width_in")
        stray = sorted(k for k in ("radius_in", "length_in", "width_in") if k in r.table and k not in allowed)
        if stray:
            raise r.fail(stray[0], f"does not apply to shape '{shape}'")
        path = _path(r, width, depth)
        speed = r.number("speed_in_s", 0.0)
        if speed <= 0.0:
            raise r.fail("speed_in_s", "must be above 0")
        size = {"radius_in": PERSON_RADIUS_IN, "length_in": CART_SIZE_IN[0], "width_in": CART_SIZE_IN[1]}
        for key in allowed:
            size[key] = r.number(key, 0.5, size[key])
        out.append(MoverSpec(shape, path, speed, start_in=r.number("start_in", 0.0, 0.0), **size))
    return tuple(out)


def _path(r: FieldReader, width: float, depth: float) -> tuple[tuple[float, float], ...]:
    raw = r.table.get("path")
    if not isinstance(raw, list) or len(raw) < 2:
        raise r.fail("path", f"must be an array of at least two [x_in, y_in] points, got {raw!r}")
    points = []
    for j, p in enumerate(raw):
        ok = (isinstance(p, list) and len(p) == 2
              and all(isinstance(v, (int, float)) and not isinstance(v, bool) and math.isfinite(v) for v in p))
        if not ok or not (0.0 <= p[0] <= width and 0.0 <= p[1] <= depth):
            raise r.fail("path", f"point {j} must be [x_in, y_in] inside the {width:g}x{depth:g} in room, got {p!r}")
        points.append((float(p[0]), float(p[1])))
    if _length(points) <= 0.0:
        raise r.fail("path", "must not stay on one point")
    return tuple(points)


def _length(points: Sequence[tuple[float, float]]) -> float:
    return sum(math.dist(a, b) for a, b in zip(points, points[1:], strict=False))


def preset_movers(preset: MoverPreset, width: float, depth: float, seed: int) -> tuple[MoverSpec, ...]:
    """The preset's movers: people and carts in turn, each on a straight line across
    the room (along x or y, drawn at random) at a random offset and starting point.
    Drawn from a stream of their own, so turning movers on changes nothing else."""
    rng = np.random.default_rng([seed, 0x30BE5])
    out = []
    for i in range(preset.count):
        shape = SHAPES[i % 2]
        spec = MoverSpec(shape, ((0.0, 0.0), (1.0, 0.0)), preset.speed_in_s)
        margin = spec.reach_in + WALL_CLEARANCE_IN
        if rng.random() < 0.5:
            at = float(rng.uniform(margin, depth - margin))
            path = ((margin, at), (width - margin, at))
        else:
            at = float(rng.uniform(margin, width - margin))
            path = ((at, margin), (at, depth - margin))
        out.append(MoverSpec(shape, path, preset.speed_in_s, start_in=float(rng.uniform(0.0, 2.0 * _length(path)))))
    return tuple(out)


@dataclass(frozen=True)
class MoverTruth:
    """Where a mover is now (ground truth for reports and tests)."""

    index: int
    shape: str
    x_in: float
    y_in: float
    reach_in: float


class Mover:
    """One mover in the pymunk space: its progress along the path (walked back and
    forth, so progress runs over twice the path's length) and its kinematic body."""

    def __init__(self, index: int, spec: MoverSpec, space: pymunk.Space) -> None:
        self.index, self.spec = index, spec
        self.cumulative = np.concatenate([[0.0], np.cumsum([math.dist(a, b) for a, b in
                                                           zip(spec.path, spec.path[1:], strict=False)])])
        self.length = float(self.cumulative[-1])
        self.progress = spec.start_in % (2.0 * self.length)
        self.aside = 0.0  # how far it stepped off its path to its left (negative: right), walking round the robot
        self.waited_s = 0.0  # how long the robot has kept it waiting
        self.body = pymunk.Body(body_type=pymunk.Body.KINEMATIC)
        self.shape: pymunk.Shape = (pymunk.Circle(self.body, spec.radius_in) if spec.shape == "disc"
                                    else pymunk.Poly.create_box(self.body, (spec.length_in, spec.width_in)))
        self.shape.filter = NEVER_MOVES
        space.add(self.body, self.shape)
        self._place(self.progress)

    def pose_at(self, progress: float) -> tuple[float, float, float]:
        """Centre and heading (radians) at ``progress`` inches along the back-and-forth walk."""
        s = progress % (2.0 * self.length)
        backwards = s > self.length
        if backwards:
            s = 2.0 * self.length - s
        k = min(int(np.searchsorted(self.cumulative, s, side="right")) - 1, len(self.spec.path) - 2)
        (x0, y0), (x1, y1) = self.spec.path[k], self.spec.path[k + 1]
        seg = self.cumulative[k + 1] - self.cumulative[k]
        f = 0.0 if seg <= 0 else (s - self.cumulative[k]) / seg
        heading = math.atan2(y1 - y0, x1 - x0) + (math.pi if backwards else 0.0)
        return x0 + f * (x1 - x0), y0 + f * (y1 - y0), heading

    def _place(self, progress: float, aside: float | None = None) -> None:
        x, y, heading = self.pose_at(progress)
        off = self.aside if aside is None else aside
        self.body.position = (x - off * math.sin(heading), y + off * math.cos(heading))
        self.body.angle = heading
        self.shape.cache_bb()

    def gap(self, point: tuple[float, float], radius: float) -> float:
        """Clearance between the mover's outline and a disc (negative: they overlap)."""
        return float(self.shape.point_query(point).distance) - radius

    def advance(self, seconds: float, base: tuple[float, float, float], facing: tuple[float, float]) -> None:
        """Walk on for ``seconds`` in strides of at most ``STRIDE_IN`` (so none jumps
        past the base), each unless it would bring the mover within ``YIELD_GAP_IN``
        of the base ``(x, y, radius)``, which faces the unit vector ``facing``, while
        not moving away: then it waits."""
        distance = seconds * self.spec.speed_in_s
        strides = max(1, math.ceil(distance / STRIDE_IN))
        for _ in range(strides):
            self._stride(distance / strides, base, facing, seconds / strides)

    def _stride(self, length: float, base: tuple[float, float, float], facing: tuple[float, float],
                seconds: float) -> None:
        """One stride: on along the path (drifting back onto it); else, out of
        patience, a person steps round the robot (aside, to the robot's back first,
        with or without going on) and a cart turns round; else it waits."""
        before = self.gap(base[:2], base[2])
        if self.spec.shape == "box" and self.waited_s >= PATIENCE_S:
            self.progress, self.waited_s = (2.0 * self.length - self.progress) % (2.0 * self.length), 0.0
            self._place(self.progress)  # the same place, heading back
            return
        heading = self.pose_at(self.progress)[2]
        behind = -1.0 if facing[0] * -math.sin(heading) + facing[1] * math.cos(heading) > 0 else 1.0
        back = self.aside - math.copysign(min(abs(self.aside), length), self.aside)
        tries = [(length, back, YIELD_GAP_IN)]
        if self.spec.shape == "disc" and self.waited_s >= PATIENCE_S:
            for side in (behind, -behind):
                wider = max(-MAX_ASIDE_IN, min(MAX_ASIDE_IN, self.aside + side * length))
                tries += [(length, wider, PASS_GAP_IN), (0.0, wider, PASS_GAP_IN)]
        for ahead, aside, keep in tries:
            self._place(self.progress + ahead, aside)
            after = self.gap(base[:2], base[2])
            if after >= keep or after >= before:
                self.progress = (self.progress + ahead) % (2.0 * self.length)
                self.aside, self.waited_s = aside, 0.0
                return
        self._place(self.progress)  # the robot is in the way: waits this stride
        self.waited_s += seconds

    def outline(self) -> tuple[tuple[float, float], ...]:
        """The mover's outline on the floor now (world points): what the overhead
        camera draws (a person's disc as a polygon, a cart's four corners)."""
        body = self.body
        if self.spec.shape == "disc":
            x, y, r = float(body.position.x), float(body.position.y), self.spec.radius_in
            return tuple((x + r * math.cos(2 * math.pi * k / OUTLINE_SEGMENTS),
                          y + r * math.sin(2 * math.pi * k / OUTLINE_SEGMENTS)) for k in range(OUTLINE_SEGMENTS))
        assert isinstance(self.shape, pymunk.Poly)
        return tuple((float(p.x), float(p.y)) for p in (body.local_to_world(v) for v in self.shape.get_vertices()))

    def truth(self) -> MoverTruth:
        return MoverTruth(self.index, self.spec.shape, float(self.body.position.x), float(self.body.position.y),
                          self.spec.reach_in)


class Movers:
    """Every mover of a world, advanced together."""

    def __init__(self, specs: Sequence[MoverSpec], space: pymunk.Space) -> None:
        self.all = [Mover(i, s, space) for i, s in enumerate(specs)]

    def advance(self, seconds: float, base: tuple[float, float, float], heading_deg: float) -> None:
        """Let ``seconds`` of robot time pass with the base standing at ``base``
        (x, y, radius), facing ``heading_deg``."""
        steps = max(1, math.ceil(seconds / STEP_S)) if seconds > 0 else 0
        facing = (math.cos(math.radians(heading_deg)), math.sin(math.radians(heading_deg)))
        for _ in range(steps):
            for mover in self.all:
                mover.advance(seconds / steps, base, facing)

    def make_room(self, base: tuple[float, float, float]) -> None:
        """Walk each mover that starts on or next to the base ``(x, y, radius)`` on
        along its path until it is ``YIELD_GAP_IN`` clear (a preset line may cross
        where the robot starts)."""
        for mover in self.all:
            for _ in range(math.ceil(2.0 * mover.length)):
                if mover.gap(base[:2], base[2]) >= YIELD_GAP_IN:
                    break
                mover.progress = (mover.progress + 1.0) % (2.0 * mover.length)
                mover._place(mover.progress)  # noqa: SLF001 (the movers' own bookkeeping)

    def outlines(self) -> tuple[tuple[tuple[float, float], ...], ...]:
        """Every mover's outline now, for the overhead camera."""
        return tuple(m.outline() for m in self.all)

    def nearest_gap(self, point: tuple[float, float], radius: float) -> float:
        """The smallest clearance from a disc to any mover (inf without movers)."""
        return min((m.gap(point, radius) for m in self.all), default=math.inf)

    def ahead(self, base: tuple[float, float, float], course: tuple[float, float],
              safety_in: float) -> Mover | None:
        """The mover that blocks a base driving along ``course`` (a unit vector): its
        outline is within ``safety_in`` of the base, ahead of the base's centre and
        within the base's width (plus ``YIELD_GAP_IN``) of its line; None if none is."""
        for mover in self.all:
            q = mover.shape.point_query(base[:2])
            if q.distance - base[2] >= safety_in:
                continue
            dx, dy = q.point.x - base[0], q.point.y - base[1]
            forward, lateral = dx * course[0] + dy * course[1], abs(dx * course[1] - dy * course[0])
            if forward > 0.0 and lateral < base[2] + YIELD_GAP_IN:
                return mover
        return None
