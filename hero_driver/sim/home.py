"""What a world file adds to be a home rather than one lab room: interior walls with
doorways, named rooms, tables the base cannot drive under but a planar sensor sees
through, and whether a ceiling camera exists at all.

Kept apart from :mod:`hero_driver.sim.worldfile` (which reads these fields through
:func:`parse_home` and :func:`furniture_kind`) because a home is an addition: every
field is optional, and a world file without them is the one-room lab it always was.
Nothing here imports the world file module, so it can be read on its own.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import cv2
import numpy as np

from hero_driver.sim.catalogue import FieldReader

DOORWAY_MARGIN_IN = 6.0
"""A doorway must be this much wider than the base's diameter: the base drives through
by dead reckoning, and a gap it fits with an inch to spare is a gap it bumps into."""
WALL_THICKNESS_IN = 4.0  # an interior wall's default thickness (a stud wall and its boards)
TABLE_LEG_IN = 2.0  # a table leg's default side (a square leg)
FURNITURE_KINDS = ("solid", "table")


@dataclass(frozen=True)
class Doorway:
    """A gap in a wall: its centre ``at_in`` inches along the wall from its start."""

    at_in: float
    width_in: float


@dataclass(frozen=True)
class WallPiece:
    """A solid stretch of wall between doorways: a rectangle centred at (x, y),
    ``length_in`` along the unit vector ``along``, ``thickness_in`` across."""

    x_in: float
    y_in: float
    length_in: float
    thickness_in: float
    along: tuple[float, float]

    @property
    def outline(self) -> list[tuple[float, float]]:
        """Its corners, counter-clockwise; from the unit vector, not an angle, so that
        an axis-aligned wall has exact corners and furniture flush against it touches
        without overlapping."""
        ux, uy = self.along
        a, b = self.length_in / 2, self.thickness_in / 2
        return [(self.x_in + su * a * ux - sv * b * uy, self.y_in + su * a * uy + sv * b * ux)
                for su, sv in ((1, -1), (1, 1), (-1, 1), (-1, -1))]


@dataclass(frozen=True)
class Wall:
    """An interior wall: a straight segment with a thickness (centred on the segment,
    ending flush with its end points) and the doorways cut into it."""

    start: tuple[float, float]
    end: tuple[float, float]
    thickness_in: float
    doors: tuple[Doorway, ...] = ()

    @property
    def length_in(self) -> float:
        return math.hypot(self.end[0] - self.start[0], self.end[1] - self.start[1])

    def point_at(self, along_in: float) -> tuple[float, float]:
        """The point ``along_in`` inches from the start, on the wall's centre line."""
        ux, uy = self.direction
        return self.start[0] + along_in * ux, self.start[1] + along_in * uy

    @property
    def direction(self) -> tuple[float, float]:
        """The unit vector from start to end (exact for an axis-aligned wall)."""
        length = self.length_in
        return (self.end[0] - self.start[0]) / length, (self.end[1] - self.start[1]) / length

    def pieces(self) -> tuple[WallPiece, ...]:
        """The solid stretches left once the doorways are cut out, in order along it."""
        along = self.direction
        cuts = [0.0]
        for door in sorted(self.doors, key=lambda d: d.at_in):
            cuts += [door.at_in - door.width_in / 2, door.at_in + door.width_in / 2]
        cuts.append(self.length_in)
        pieces = []
        for lo, hi in zip(cuts[::2], cuts[1::2]):
            if hi - lo > 1e-9:
                x, y = self.point_at((lo + hi) / 2)
                pieces.append(WallPiece(x, y, hi - lo, self.thickness_in, along))
        return tuple(pieces)


@dataclass(frozen=True)
class NamedRoom:
    """A named part of the floor, for reports ("found in the kitchen"): a polygon."""

    name: str
    outline: tuple[tuple[float, float], ...]

    def contains(self, x: float, y: float) -> bool:
        """Whether (x, y) lies inside the outline or on its edge (OpenCV's point-in-polygon test)."""
        return cv2.pointPolygonTest(np.asarray(self.outline, dtype=np.float32), (float(x), float(y)), False) >= 0


@dataclass(frozen=True)
class Home:
    """The home fields of a world (all optional; the defaults are the lab's)."""

    walls: tuple[Wall, ...] = ()
    rooms: tuple[NamedRoom, ...] = ()
    ceiling_camera: bool = True  # False: the ``camera`` verb answers no_camera
    heading_drift: bool = False  # True: the base's heading drifts as the noise says (docs/simulator.md, Moving)

    def room_at(self, x: float, y: float) -> str | None:
        """The name of the first room whose outline holds (x, y); None outside every room."""
        return next((room.name for room in self.rooms if room.contains(x, y)), None)


def furniture_kind(r: FieldReader) -> tuple[str, float]:
    """A furniture entry's ``kind`` (``solid``, the default: nothing under it is seen
    or reached; ``table``: its top keeps the base out, but a sensor at base height
    sees only its four legs) and, for a table, ``leg_in``: the side of its square
    legs, which stand flush with the top's corners."""
    kind = r.text("kind", FURNITURE_KINDS, optional=True) or "solid"
    if kind != "table":
        if "leg_in" in r.table:
            raise r.fail("leg_in", "is for tables only (kind 'table')")
        return kind, 0.0
    leg = r.number("leg_in", 0.5, TABLE_LEG_IN)
    width, depth = r.table.get("width_in"), r.table.get("depth_in")
    if isinstance(width, (int, float)) and isinstance(depth, (int, float)) and 2 * leg > min(width, depth):
        raise r.fail("leg_in", f"is {leg:g} in: two legs do not fit across the {min(width, depth):g} in table")
    return kind, leg


def leg_centres(x: float, y: float, width: float, depth: float, yaw_deg: float,
                leg_in: float) -> list[tuple[float, float]]:
    """World-frame centres of a table's four legs (at the top's corners, inside it)."""
    c, s = math.cos(math.radians(yaw_deg)), math.sin(math.radians(yaw_deg))
    u, v = width / 2 - leg_in / 2, depth / 2 - leg_in / 2
    return [(x + c * a - s * b, y + s * a + c * b) for a, b in ((u, v), (-u, v), (-u, -v), (u, -v))]


def parse_home(top: FieldReader, width: float, depth: float) -> Home:
    """The home fields of a world file's top level: ``walls``, ``rooms``,
    ``ceiling_camera`` and ``heading_drift`` (docs/simulator.md, "Homes")."""
    camera = True if top.table.get("ceiling_camera") is None else top.flag("ceiling_camera")
    drift = False if top.table.get("heading_drift") is None else top.flag("heading_drift")
    return Home(_walls(top, width, depth), _rooms(top, width, depth), camera, drift)


def _point(r: FieldReader, field: str, width: float, depth: float, value: object = None) -> tuple[float, float]:
    """Field ``field`` of ``r`` (or ``value``, an array item named ``field``) as a point inside the room."""
    value = r.table.get(field) if value is None else value
    xy = [_number(v) for v in value] if isinstance(value, list) and len(value) == 2 else [None]
    if None in xy or not (0 <= xy[0] <= width and 0 <= xy[1] <= depth):  # type: ignore[operator]
        raise r.fail(field, f"must be [x_in, y_in] inside the {width:g}x{depth:g} in room, got {value!r:.80}")
    return xy[0], xy[1]  # type: ignore[return-value]


def _number(value: object) -> float | None:
    """A JSON number as a finite float; None for anything else (text, true, NaN, an
    integer of 400 digits, which has no float)."""
    if isinstance(value, bool) or not isinstance(value, (int, float)):
        return None
    try:
        number = float(value)
    except OverflowError:
        return None
    return number if math.isfinite(number) else None


def _list(top: FieldReader, field: str) -> list[object]:
    value = top.table.get(field, [])
    if not isinstance(value, list):
        raise top.fail(field, "must be an array")
    return value


def _walls(top: FieldReader, width: float, depth: float) -> tuple[Wall, ...]:
    walls = []
    for i, raw in enumerate(_list(top, "walls")):
        r = FieldReader(top.source, f"walls[{i}]", raw)
        r.only("from", "to", "thickness_in", "doors")
        start, end = _point(r, "from", width, depth), _point(r, "to", width, depth)
        if math.hypot(end[0] - start[0], end[1] - start[1]) < 1.0:
            raise r.fail("to", f"must be at least 1 in from 'from', got {list(end)}")
        wall = Wall(start, end, r.number("thickness_in", 0.5, WALL_THICKNESS_IN))
        doors = []
        for j, raw_door in enumerate(_list(r, "doors")):
            d = FieldReader(top.source, f"walls[{i}].doors[{j}]", raw_door)
            d.only("at_in", "width_in")
            door = Doorway(d.number("at_in"), d.number("width_in", 0.5))
            if door.at_in - door.width_in / 2 < 0 or door.at_in + door.width_in / 2 > wall.length_in:
                raise d.fail("at_in", f"puts the {door.width_in:g} in doorway beyond the ends of the "
                                      f"{wall.length_in:g} in wall")
            if doors and any(abs(door.at_in - o.at_in) < (door.width_in + o.width_in) / 2 for o in doors):
                raise d.fail("at_in", "puts the doorway over another doorway of the wall")
            doors.append(door)
        walls.append(Wall(start, end, wall.thickness_in, tuple(doors)))
    return tuple(walls)


def _rooms(top: FieldReader, width: float, depth: float) -> tuple[NamedRoom, ...]:
    rooms: list[NamedRoom] = []
    for i, raw in enumerate(_list(top, "rooms")):
        r = FieldReader(top.source, f"rooms[{i}]", raw)
        r.only("name", "outline")
        name = r.text("name")
        if any(room.name == name for room in rooms):
            raise r.fail("name", f"names room '{name}' a second time")
        outline = r.table.get("outline")
        if not isinstance(outline, list) or len(outline) < 3:
            raise r.fail("outline", f"must be a polygon of 3 or more [x_in, y_in] points, got {outline!r}")
        points = tuple(_point(r, f"outline[{k}]", width, depth, p) for k, p in enumerate(outline))
        rooms.append(NamedRoom(name, points))
    return tuple(rooms)


def check_doorways(home: Home, source: str, base_radius_in: float) -> None:
    """Refuse a home whose doorway the base cannot pass: narrower than its diameter
    plus :data:`DOORWAY_MARGIN_IN`. The base is the robot's (its profile), not the
    world's, so the simulator checks this when it puts a robot in the world."""
    need = 2 * base_radius_in + DOORWAY_MARGIN_IN
    for i, wall in enumerate(home.walls):
        for j, door in enumerate(wall.doors):
            if door.width_in < need:
                raise ValueError(f"{source}: walls[{i}].doors[{j}]: field 'width_in' is {door.width_in:g} in, "
                                 f"narrower than the base ({2 * base_radius_in:g} in across) plus a "
                                 f"{DOORWAY_MARGIN_IN:g} in margin ({need:g} in)")
