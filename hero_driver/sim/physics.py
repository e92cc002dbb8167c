"""The pymunk space behind the simulated world: walls, furniture and the objects on
the floor, used for every geometric question (sonar rays, the base's swept path) and
for the motion a failed grasp causes. A home's interior walls and a table's legs are
static shapes like the outer walls; a table's top is in a space of its own
(``above_floor``) that only the base's questions consult.

There is no gravity in a top-down world; floor friction is a pivot joint and a gear
joint from each object to the static body with zero bias and a bounded force, which
brakes a pushed object at a constant deceleration (Coulomb friction). A round object
lying on its side rolls: it is pushed across its axis and braked far less.
"""

from __future__ import annotations

import math
from collections.abc import Mapping, Sequence
from dataclasses import dataclass

import pymunk

from hero_driver.sim.catalogue import CatalogueEntry
from hero_driver.sim.movers import Movers, MoverSpec
from hero_driver.sim.worldfile import WorldSpec, rect_polygon

WALL_IN = 6.0  # wall thickness, outside the room's interior
SLIDE_DECEL_IN_S2 = 12.0  # friction braking of a sliding object
ROLL_DECEL_IN_S2 = 1.5  # rolling resistance of a lying round object
SPIN_FRICTION = 40.0  # bound of the gear joint's torque: pushes rarely spin objects far
SETTLE_DT_S = 1.0 / 120.0
SETTLE_MAX_STEPS = 1200
REST_SPEED_IN_S = 0.01
OVERLAP_IN = 0.15  # deeper than this, two shapes overlap (pymunk leaves its collision slop, 0.1)


@dataclass
class SimObject:
    """One physical object: its catalogue entry may change (knocked over) while its
    index stays, so the executive's notion of "the same object" survives."""

    index: int
    entry: CatalogueEntry
    body: pymunk.Body
    shape: pymunk.Shape
    joints: tuple[pymunk.Constraint, ...]
    status: str = "floor"  # "floor", "held" or "binned"

    @property
    def x_in(self) -> float:
        return float(self.body.position.x)

    @property
    def y_in(self) -> float:
        return float(self.body.position.y)

    @property
    def yaw_deg(self) -> float:
        return math.degrees(self.body.angle) % 360.0


class Physics:
    """Owns the pymunk space and keeps every body and shape referenced (pymunk does not
    keep Python objects alive on its own)."""

    def __init__(self, spec: WorldSpec, catalogue: Mapping[str, CatalogueEntry],
                 movers: Sequence[MoverSpec] = ()) -> None:
        self.space = pymunk.Space()
        self.space.gravity = (0.0, 0.0)
        self.static_shapes: list[pymunk.Shape] = []
        self.glass: set[pymunk.Shape] = set()  # furniture a lidar's light passes (hero_driver.sim.scan)
        w, d, t = spec.room_width_in, spec.room_depth_in, WALL_IN
        walls = ((w / 2, -t / 2, w + 2 * t, t), (w / 2, d + t / 2, w + 2 * t, t),
                 (-t / 2, d / 2, t, d + 2 * t), (w + t / 2, d / 2, t, d + 2 * t))
        for x, y, length, width in walls:
            self._add_static(rect_polygon(x, y, length, width, 0.0))
        # Table tops stand above the floor: the base's sweep meets them, rays at the
        # scan plane and objects on the floor do not, so they live in a space of their own.
        self.above_floor = pymunk.Space()
        for f in spec.furniture:
            for polygon in f.at_scan_plane():
                shape = self._add_static(polygon)
                if f.glass:
                    self.glass.add(shape)
            if f.kind == "table":
                self.above_floor.add(pymunk.Poly(self.above_floor.static_body, f.outline))
        for polygon in spec.wall_outlines():
            self._add_static(polygon)
        self.objects: list[SimObject] = []
        self._owner: dict[pymunk.Shape, SimObject] = {}
        for i, p in enumerate(spec.objects):
            self.objects.append(self._make_object(i, catalogue[p.entry_id], p.x_in, p.y_in, p.yaw_deg))
        self.movers = Movers(movers, self.space)  # people and carts (hero_driver.sim.movers): no query sees them

    def _add_static(self, polygon: list[tuple[float, float]]) -> pymunk.Shape:
        shape = pymunk.Poly(self.space.static_body, polygon)
        shape.friction, shape.elasticity = 0.6, 0.2
        self.space.add(shape)
        self.static_shapes.append(shape)
        return shape

    def _make_object(self, index: int, entry: CatalogueEntry, x: float, y: float, yaw_deg: float) -> SimObject:
        body = pymunk.Body(mass=1.0, moment=1.0)
        fp = entry.footprint
        if fp.shape == "circle":
            shape: pymunk.Shape = pymunk.Circle(body, fp.radius_in)
            body.moment = pymunk.moment_for_circle(1.0, 0.0, fp.radius_in)
        else:
            shape = pymunk.Poly.create_box(body, (fp.length_in, fp.width_in))
            body.moment = pymunk.moment_for_box(1.0, (fp.length_in, fp.width_in))
        shape.friction, shape.elasticity = 0.5, 0.2
        body.position = (x, y)
        body.angle = math.radians(yaw_deg)
        slide = pymunk.PivotJoint(self.space.static_body, body, (0.0, 0.0), (0.0, 0.0))
        slide.max_bias, slide.max_force = 0.0, SLIDE_DECEL_IN_S2
        spin = pymunk.GearJoint(self.space.static_body, body, 0.0, 1.0)
        spin.max_bias, spin.max_force = 0.0, SPIN_FRICTION
        self.space.add(body, shape, slide, spin)
        obj = SimObject(index, entry, body, shape, (slide, spin))
        self._owner[shape] = obj
        return obj

    def owner(self, shape: pymunk.Shape | None) -> SimObject | None:
        """The floor object a shape belongs to; None for walls and furniture."""
        return self._owner.get(shape) if shape is not None else None

    def ray(self, start: tuple[float, float], end: tuple[float, float]) -> pymunk.SegmentQueryInfo | None:
        """First shape a thin ray at the scan plane meets (walls, furniture and objects
        all occlude; a table's top is above it, its legs are not)."""
        return self.space.segment_query_first(start, end, 0.0, pymunk.ShapeFilter())

    def sweep_circle(self, start: tuple[float, float], end: tuple[float, float], radius: float) -> float | None:
        """Fraction of the way from start to end at which a disc of ``radius`` first
        touches anything, or None when the whole path is clear. A shape the disc
        already touches at the start only counts when the path heads into it, so a
        base that stopped against something can still back away."""
        dx, dy = end[0] - start[0], end[1] - start[1]
        # Each shape near the sweep asked in turn: the spaces' own segment query with a
        # radius missed a table's top when the thin segment's bounding box did not reach
        # the top's (a base driven 0.8 in short of a top's edge went on 7 in under it).
        swept = pymunk.BB(min(start[0], end[0]) - radius, min(start[1], end[1]) - radius,
                          max(start[0], end[0]) + radius, max(start[1], end[1]) + radius)
        near = [*self.space.bb_query(swept, pymunk.ShapeFilter()), *self.above_floor.bb_query(swept, pymunk.ShapeFilter())]
        hits = sorted((h for h in (shape.segment_query(start, end, radius) for shape in near) if h is not None),
                      key=lambda h: h.alpha)
        for hit in hits:
            touching = hit.shape.point_query(start)
            if touching.distance < radius and dx * touching.gradient.x + dy * touching.gradient.y >= 0:
                continue
            return float(hit.alpha)
        return None

    def overlaps_disc(self, centre: tuple[float, float], radius: float) -> bool:
        """Whether a disc at ``centre`` touches any wall, furniture (a table's top
        included), object or mover."""
        hit = self.space.point_query_nearest(centre, radius, pymunk.ShapeFilter())
        top = self.above_floor.point_query_nearest(centre, radius, pymunk.ShapeFilter())
        return hit is not None or top is not None or self.movers.nearest_gap(centre, radius) < 0.0

    def lift(self, obj: SimObject) -> None:
        """Take an object off the floor (held or binned): gone from rays and images."""
        self.space.remove(obj.body, obj.shape, *obj.joints)
        del self._owner[obj.shape]
        obj.status = "held"

    def replace(self, obj: SimObject, entry: CatalogueEntry, x: float, y: float, yaw_deg: float) -> None:
        """Swap an object's entry in place (a knocked-over cup becomes a lying cup)."""
        self.space.remove(obj.body, obj.shape, *obj.joints)
        del self._owner[obj.shape]
        fresh = self._make_object(obj.index, entry, x, y, yaw_deg)
        obj.entry, obj.body, obj.shape, obj.joints = fresh.entry, fresh.body, fresh.shape, fresh.joints
        self._owner[obj.shape] = obj

    def push(self, obj: SimObject, direction: tuple[float, float], distance_in: float, rolling: bool) -> None:
        """Give an object the speed that friction brakes to rest after ``distance_in``
        (v0 = sqrt(2 a s)); walls and other objects may stop it sooner."""
        decel = ROLL_DECEL_IN_S2 if rolling else SLIDE_DECEL_IN_S2
        obj.joints[0].max_force = decel * obj.body.mass
        speed = math.sqrt(2.0 * decel * max(distance_in, 0.0))
        obj.body.velocity = (direction[0] * speed, direction[1] * speed)
        self.settle()
        obj.joints[0].max_force = SLIDE_DECEL_IN_S2 * obj.body.mass

    def settle(self) -> None:
        """Step until every object rests and none overlaps another or a wall (a
        knocked-over object laid onto a neighbour). Overlaps are checked as well as
        speeds because pymunk pushes overlapping shapes apart with bias velocities
        that never show in a body's velocity: they look at rest while overlapping."""
        floor = [o for o in self.objects if o.status == "floor"]
        for _ in range(SETTLE_MAX_STEPS):
            self.space.step(SETTLE_DT_S)
            if (all(o.body.velocity.length < REST_SPEED_IN_S and abs(o.body.angular_velocity) < 0.01 for o in floor)
                    and not any(self._overlapping(o) for o in floor)):
                break
        for o in floor:
            o.body.velocity, o.body.angular_velocity = (0.0, 0.0), 0.0

    def _overlapping(self, obj: SimObject) -> bool:
        """Whether ``obj`` overlaps anything by more than OVERLAP_IN (people and carts,
        which no query sees, aside)."""
        # Only shapes that touch are returned; the depth's sign depends on the pair's
        # order in pymunk, so its size is what counts.
        return any(abs(p.distance) > OVERLAP_IN for hit in self.space.shape_query(obj.shape)
                   for p in hit.contact_point_set.points)
