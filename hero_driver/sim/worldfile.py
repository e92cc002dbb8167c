"""World files: the room, its furniture, the robot's start pose and the objects on the
floor (catalogue ids and poses), as JSON in ``hero_driver/worlds/``.

A world is data so that scenarios (the demo lab, the training floor, one-object probe
worlds) differ by a file, not by code. Loading checks geometry too: an object through
a wall or inside another one would make every later measurement meaningless.
"""

from __future__ import annotations

import json
import logging
import math
import os
import re
import stat
from collections.abc import Mapping
from dataclasses import dataclass
from pathlib import Path

from hero_driver.shipped import WORLDS_DIR
from hero_driver.sim.battery import Charge, Dock
from hero_driver.sim.catalogue import CatalogueEntry, Footprint, FieldReader
from hero_driver.sim.events import Disturbance, parse_events
from hero_driver.sim.home import Home, furniture_kind, leg_centres, parse_home
from hero_driver.sim.movers import MoverSpec, parse_movers_field
from hero_driver.sim.noise import NoiseConfig

log = logging.getLogger(__name__)

DEFAULT_WORLD = "lab"
HOME_FIELDS = ("walls", "rooms", "ceiling_camera", "heading_drift")  # read by hero_driver.sim.home
WORLD_NAME = re.compile(r"[A-Za-z0-9_-]{1,64}")
"""What ``reset`` accepts as a world: a name, never a path (no '/', no '.', so no '..')."""


@dataclass(frozen=True)
class Furniture:
    """A rectangle the robot must not enter: a cabinet, a sofa, a table's top. A
    ``solid`` one is solid to the floor; under a ``table`` a planar sensor at base
    height sees only its four legs (``leg_in`` square, hero_driver.sim.home). ``glass``
    (a glass door or partition) lets a lidar's light through (docs/simulator.md, Scans)."""

    name: str
    x_in: float
    y_in: float
    width_in: float  # along the furniture's own x
    depth_in: float  # along its own y
    yaw_deg: float = 0.0
    kind: str = "solid"  # "solid" or "table" (hero_driver.sim.home.FURNITURE_KINDS)
    leg_in: float = 0.0  # a table's leg side; 0 for solid furniture
    glass: bool = False

    @property
    def outline(self) -> list[tuple[float, float]]:
        """The footprint the base may not enter (a table's top)."""
        return rect_polygon(self.x_in, self.y_in, self.width_in, self.depth_in, self.yaw_deg)

    def at_scan_plane(self) -> list[list[tuple[float, float]]]:
        """What a sensor just above the floor meets: the whole outline, or a table's legs."""
        if self.kind != "table":
            return [self.outline]
        legs = leg_centres(self.x_in, self.y_in, self.width_in, self.depth_in, self.yaw_deg, self.leg_in)
        return [rect_polygon(x, y, self.leg_in, self.leg_in, self.yaw_deg) for x, y in legs]


@dataclass(frozen=True)
class Placement:
    """One object on the floor: a catalogue entry at a centre and yaw (of local x)."""

    entry_id: str
    x_in: float
    y_in: float
    yaw_deg: float = 0.0


@dataclass(frozen=True)
class WorldSpec:
    name: str
    source: str
    room_width_in: float  # x from 0 to width
    room_depth_in: float  # y from 0 to depth
    furniture: tuple[Furniture, ...]
    robot: tuple[float, float, float]  # x_in, y_in, heading_deg
    objects: tuple[Placement, ...]
    noise: NoiseConfig | None
    board: Path | None = None  # the marker board printed on its floor (docs/camera.md)
    dock: Dock | None = None  # the charging dock, if the world has one (docs/simulator.md, Battery)
    battery: Charge | None = None  # start level and drain multiplier; None: full, or tethered without a dock
    events: tuple[Disturbance, ...] = ()  # scheduled disturbances (docs/simulator.md, Disturbances)
    movers: tuple[MoverSpec, ...] = ()  # people and carts crossing the floor (docs/simulator.md, Moving obstacles)
    home: Home = Home()  # interior walls, named rooms, no ceiling camera (docs/simulator.md, Homes)

    def wall_outlines(self) -> list[list[tuple[float, float]]]:
        """The interior walls' solid pieces (doorways cut out) as polygons."""
        return [p.outline for wall in self.home.walls for p in wall.pieces()]


def resolve(world: str | Path | None) -> Path:
    """A world argument as the driver takes it: None (the default lab), a bare name of
    a shipped world ("lab", "training") or a path."""
    if world is None:
        world = DEFAULT_WORLD
    candidate = Path(world)
    if candidate.suffix == "" and not candidate.exists() and (WORLDS_DIR / f"{world}.json").exists():
        return WORLDS_DIR / f"{world}.json"
    return candidate


def footprint_polygon(footprint: Footprint, x: float, y: float, yaw_deg: float,
                      segments: int = 48) -> list[tuple[float, float]]:
    """World-frame outline (counter-clockwise); circles become ``segments``-gons."""
    if footprint.shape == "circle":
        return [(x + footprint.radius_in * math.cos(2 * math.pi * k / segments),
                 y + footprint.radius_in * math.sin(2 * math.pi * k / segments)) for k in range(segments)]
    return rect_polygon(x, y, footprint.length_in, footprint.width_in, yaw_deg)


def rect_polygon(x: float, y: float, length: float, width: float, yaw_deg: float) -> list[tuple[float, float]]:
    c, s = math.cos(math.radians(yaw_deg)), math.sin(math.radians(yaw_deg))
    corners = ((length / 2, width / 2), (-length / 2, width / 2), (-length / 2, -width / 2), (length / 2, -width / 2))
    return [(x + c * u - s * v, y + s * u + c * v) for u, v in corners][::-1]


def _bounds(points: list[tuple[float, float]]) -> tuple[float, float, float, float]:
    xs, ys = [p[0] for p in points], [p[1] for p in points]
    return min(xs), min(ys), max(xs), max(ys)


def _overlap(a: list[tuple[float, float]], b: list[tuple[float, float]]) -> bool:
    """Separating-axis test for convex polygons."""
    for poly in (a, b):
        for i in range(len(poly)):
            (x1, y1), (x2, y2) = poly[i], poly[(i + 1) % len(poly)]
            nx, ny = y2 - y1, x1 - x2
            pa = [nx * px + ny * py for px, py in a]
            pb = [nx * px + ny * py for px, py in b]
            if max(pa) <= min(pb) or max(pb) <= min(pa):
                return False
    return True


def parse_world(data: object, source: str, catalogue: Mapping[str, CatalogueEntry]) -> WorldSpec:
    """Check and build a world from decoded JSON (``source`` names it in errors)."""
    top = FieldReader(source, "world", data)
    top.only("about", "name", "room", "furniture", "robot", "objects", "noise", "board", "dock", "battery",
             "battery_drain", "events", "movers", *HOME_FIELDS)
    room = FieldReader(source, "room", top.table.get("room"))
    room.only("width_in", "depth_in")
    width, depth = room.number("width_in", 24.0), room.number("depth_in", 24.0)
    furniture = []
    for i, raw in enumerate(_array(top, "furniture")):
        r = FieldReader(source, f"furniture[{i}]", raw)
        r.only("name", "x_in", "y_in", "width_in", "depth_in", "yaw_deg", "kind", "leg_in", "glass")
        kind, leg = furniture_kind(r)
        furniture.append(Furniture(r.text("name"), r.number("x_in"), r.number("y_in"),
                                   r.number("width_in", 0.5), r.number("depth_in", 0.5),
                                   r.number("yaw_deg", -360.0, 0.0), kind, leg,
                                   "glass" in r.table and r.flag("glass")))
    rr = FieldReader(source, "robot", top.table.get("robot"))
    rr.only("x_in", "y_in", "heading_deg")
    robot = (rr.number("x_in"), rr.number("y_in"), rr.number("heading_deg", -360.0, 0.0))
    for field, value, side in (("x_in", robot[0], width), ("y_in", robot[1], depth)):
        if not value <= side:  # also NaN, which every comparison refuses
            raise rr.fail(field, f"puts the robot outside the {width:g}x{depth:g} in room, got {value:g}")
    objects = []
    for i, raw in enumerate(_array(top, "objects")):
        r = FieldReader(source, f"objects[{i}]", raw)
        r.only("id", "x_in", "y_in", "yaw_deg")
        entry_id = r.text("id")
        if entry_id not in catalogue:
            raise r.fail("id", f"names unknown catalogue entry '{entry_id}'")
        objects.append(Placement(entry_id, r.number("x_in"), r.number("y_in"), r.number("yaw_deg", -360.0, 0.0)))
    noise_table = top.table.get("noise")
    noise = None
    if noise_table is not None:
        if not isinstance(noise_table, dict):
            raise top.fail("noise", "must be an object")
        noise = NoiseConfig.from_mapping(noise_table, f"{source}: noise")
    spec = WorldSpec(str(top.table.get("name", Path(source).stem)), source, width, depth,
                     tuple(furniture), robot, tuple(objects), noise, _board(top, source),
                     dock=_dock(source, top.table.get("dock"), width, depth), battery=_battery(top),
                     events=parse_events(top.table.get("events"), source, [p.entry_id for p in objects], catalogue),
                     movers=parse_movers_field(top.table.get("movers"), source, width, depth),
                     home=parse_home(top, width, depth))
    _check_layout(spec, catalogue)
    return spec


def _board(top: FieldReader, source: str) -> Path | None:
    """The optional ``board`` file, relative to the world file's folder, else one of
    the shipped boards (so a copy of ``lab.json`` edited elsewhere keeps the lab's
    board): the marker board the realistic camera prints on the floor and calibration
    reads."""
    name = top.table.get("board")
    if name is None:
        return None
    if not isinstance(name, str) or not name:
        raise top.fail("board", "must be the name of a marker board file")
    path = Path(source).parent / name
    if not _is_file(path):
        shipped = WORLDS_DIR / name
        if Path(name).name != name or not _is_file(shipped):
            raise top.fail("board", f"names {path}, which is not a file (nor a shipped board)")
        path = shipped
    return path


def _is_file(path: Path) -> bool:
    """``Path.is_file``, but a name the system refuses (longer than 255 bytes, say)
    is not a file instead of an OSError."""
    try:
        return path.is_file()
    except OSError:
        return False


def _dock(source: str, raw: object, width: float, depth: float) -> Dock | None:
    """The optional charging dock: the pose the base charges at, inside the room."""
    if raw is None:
        return None
    r = FieldReader(source, "dock", raw)
    r.only("x_in", "y_in", "heading_deg")
    dock = Dock(r.number("x_in"), r.number("y_in"), r.number("heading_deg", -360.0, 0.0))
    if dock.x_in > width or dock.y_in > depth:
        raise r.fail("x_in" if dock.x_in > width else "y_in", f"puts the dock outside the {width:g}x{depth:g} in room")
    return dock


def _battery(top: FieldReader) -> Charge | None:
    """The optional start level of the battery and multiplier on its drain rates
    (``battery_drain``, > 0; either one meters the battery)."""
    if top.table.get("battery") is None and top.table.get("battery_drain") is None:
        return None
    level = 1.0 if top.table.get("battery") is None else top.number("battery", 0.0)
    if level > 1.0:
        raise top.fail("battery", f"must be a level from 0 to 1, got {level:g}")
    drain = 1.0 if top.table.get("battery_drain") is None else top.number("battery_drain", 0.0)
    if drain <= 0.0:
        raise top.fail("battery_drain", f"must be a multiplier > 0 on the drain rates, got {drain:g}")
    return Charge(level, drain)


def _array(reader: FieldReader, field: str) -> list[object]:
    """An optional array field (absent: empty); anything else, null included, is refused."""
    value = reader.table.get(field, [])
    if not isinstance(value, list):
        raise reader.fail(field, "must be an array")
    return value


# The kinds of shape the layout check compares; which pairs may overlap is :func:`_may_overlap`'s.
WALL, SOLID, TABLE_TOP, LEG, OBJECT = "wall", "solid", "table top", "leg", "object"


def _check_layout(spec: WorldSpec, catalogue: Mapping[str, CatalogueEntry]) -> None:
    """Everything inside the room, and nothing through anything else: walls, furniture
    (a table's top and its legs), objects. Walls may meet walls (corners and junctions);
    an object may lie under a table's top, not in one of its legs."""
    shapes: list[tuple[str, list[tuple[float, float]], str, int]] = [  # label, polygon, kind, owner
        (f"walls[{i}]", poly, WALL, -1 - i) for i, poly in _wall_outlines_by_wall(spec)]
    for k, f in enumerate(spec.furniture):
        shapes.append((f"furniture '{f.name}'", f.outline, SOLID if f.kind != "table" else TABLE_TOP, k))
        if f.kind == "table":
            shapes += [(f"furniture '{f.name}' leg {j}", leg, LEG, k) for j, leg in enumerate(f.at_scan_plane())]
    for i, p in enumerate(spec.objects):
        shapes.append((f"objects[{i}] '{p.entry_id}'",
                       footprint_polygon(catalogue[p.entry_id].footprint, p.x_in, p.y_in, p.yaw_deg),
                       OBJECT, len(spec.furniture) + i))
    for label, poly, _, _ in shapes:
        x0, y0, x1, y1 = _bounds(poly)
        if x0 < 0 or y0 < 0 or x1 > spec.room_width_in or y1 > spec.room_depth_in:
            room = f"{spec.room_width_in:g}x{spec.room_depth_in:g} in"
            raise ValueError(f"{spec.source}: {label}: lies outside the {room} room")
    for i, (label_a, a, kind_a, owner_a) in enumerate(shapes):
        for label_b, b, kind_b, owner_b in shapes[i + 1:]:
            if not _may_overlap(kind_a, owner_a, kind_b, owner_b) and _overlap(a, b):
                raise ValueError(f"{spec.source}: {label_b}: overlaps {label_a}")


def _may_overlap(kind_a: str, owner_a: int, kind_b: str, owner_b: int) -> bool:
    """Pairs the layout check allows to overlap: one table's top and its own legs, two
    walls (where they meet), and an object under a table's top."""
    return owner_a == owner_b or {kind_a, kind_b} in ({WALL}, {TABLE_TOP, OBJECT})


def _wall_outlines_by_wall(spec: WorldSpec) -> list[tuple[int, list[tuple[float, float]]]]:
    return [(i, p.outline) for i, wall in enumerate(spec.home.walls) for p in wall.pieces()]


def load_world(world: str | Path | None, catalogue: Mapping[str, CatalogueEntry]) -> WorldSpec:
    """Read a world file (see :func:`resolve` for what ``world`` may be)."""
    path = resolve(world)
    try:
        data = json.loads(path.read_text(encoding="utf-8"))
    except RecursionError:
        raise ValueError(f"{path}: cannot read world file: JSON nested too deeply") from None
    except (OSError, ValueError) as exc:  # ValueError: not JSON, not UTF-8, an integer too long
        raise ValueError(f"{path}: cannot read world file: {exc}") from exc
    return parse_world(data, str(path), catalogue)


def one_object_world(entry_id: str, catalogue: Mapping[str, CatalogueEntry], *,
                     yaw_deg: float = 0.0, room_in: float = 400.0) -> WorldSpec:
    """An empty square room with one object at its centre, for training probes: large
    enough that a sweep at the sonar's full range never sees a wall behind the robot
    interfere with the object."""
    if entry_id not in catalogue:
        raise ValueError(f"one_object_world: unknown catalogue entry '{entry_id}'")
    centre = room_in / 2
    data = {"name": f"probe:{entry_id}", "room": {"width_in": room_in, "depth_in": room_in},
            "robot": {"x_in": 20.0, "y_in": 20.0, "heading_deg": 0.0},
            "objects": [{"id": entry_id, "x_in": centre, "y_in": centre, "yaw_deg": yaw_deg}]}
    return parse_world(data, f"<probe {entry_id}>", catalogue)


class WorldRefused(ValueError):
    """A world ``reset`` will not load; the text is safe to send to any client: it names
    nothing of the driver's file system beyond the name the client itself sent."""

    @classmethod
    def cannot_load(cls, name: str) -> WorldRefused:
        """World ``name`` exists but does not load (the reason goes to the driver's log)."""
        return cls(f"world: {name!r} cannot be loaded on this driver (see the driver's log)")


@dataclass(frozen=True)
class WorldShelf:
    """The worlds a driver's ``reset`` may restore, by name: ``<folder>/<name>.json``,
    plus ``named`` worlds served under a name of their own (the world the driver
    was started with, under its file's stem).

    A protocol client is anyone who reaches the port, so a name is all it may give:
    a path would let it read any file the driver can (and learn from the error
    whether one exists), and a FIFO would hang the driver while its token stays up.
    """

    folder: Path = WORLDS_DIR
    named: tuple[tuple[str, Path], ...] = ()

    def path_of(self, name: str) -> Path:
        """Where world ``name`` lives; WorldRefused for a non-name or an unknown one."""
        if not isinstance(name, str) or not WORLD_NAME.fullmatch(name):
            raise WorldRefused("world: expected a world name (up to 64 letters, digits, '_' or '-'), not a path")
        for served, path in self.named:
            if served == name:
                return path
        return self.folder / f"{name}.json"

    def load(self, name: str, catalogue: Mapping[str, CatalogueEntry]) -> WorldSpec:
        """Read and check world ``name``. Every failure is one WorldRefused line that
        says no more than "no such world" or "cannot be loaded"; the driver's own log
        gets the reason."""
        path = self.path_of(name)
        text = _read_regular_file(path)
        if text is None:
            raise WorldRefused(f"world: no world named {name!r} on this driver")
        try:
            return parse_world(json.loads(text), str(path), catalogue)
        except (ValueError, RecursionError) as exc:  # JSONDecodeError is a ValueError
            log.warning("world %r (%s) cannot be loaded: %s", name, path, exc)
            raise WorldRefused.cannot_load(name) from None


def _read_regular_file(path: Path) -> str | None:
    """The text of ``path`` if it is a regular file that can be read, else None.

    Opened without blocking and checked on the open descriptor, so a FIFO or a device
    put in the folder is refused instead of hanging the reader.
    """
    try:
        fd = os.open(path, os.O_RDONLY | os.O_NONBLOCK)
    except OSError:
        return None
    try:
        if not stat.S_ISREG(os.fstat(fd).st_mode):
            return None
        with os.fdopen(fd, "rb", closefd=False) as stream:
            data = stream.read()
    except OSError:
        return None
    finally:
        os.close(fd)
    try:
        return data.decode("utf-8")
    except UnicodeDecodeError:
        return ""  # not a world either: parsed, refused as "cannot be loaded"


def shelf_for(start: str | Path | WorldSpec | None, folder: Path | None = None) -> WorldShelf:
    """The shelf of a driver started with world ``start`` (see :func:`resolve`) and
    worlds folder ``folder`` (None: the shipped worlds): the start world is also
    served under its file's stem, so ``csl driver sim --world my/room.json`` answers
    ``reset {"world": "room"}``. A world built in memory (a :class:`WorldSpec`, as
    tests and the experiment make) has no file, so it adds no name."""
    shelf = WORLDS_DIR if folder is None else folder
    if isinstance(start, WorldSpec):
        return WorldShelf(shelf, ())
    path = resolve(start)
    return WorldShelf(shelf, ((path.stem, path),))
