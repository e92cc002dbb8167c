"""The object catalogue: the true geometry and correct grasps of every object the
simulated world can hold (``hero_driver/worlds/catalogue.json``).

Truth lives in a data file rather than in code so that the objects of Table 3 and the
test objects can be read, reviewed and extended without touching the simulator; the
loader checks every field so that a typo fails loudly, naming the entry.
"""

from __future__ import annotations

import json
import math
from collections.abc import Collection, Mapping
from dataclasses import dataclass
from functools import lru_cache
from pathlib import Path
from types import MappingProxyType

from robot_profile import DEFAULT_PROFILE, RobotProfile, load_profile

DEFAULT_CATALOGUE = Path(__file__).resolve().parent.parent / "worlds" / "catalogue.json"

APPROACHES = ("any", "end", "side")
FACES = ("+x", "-x", "+y", "-y")
SETS = ("training", "test", "derived")


@dataclass(frozen=True)
class Footprint:
    """The object's overhead outline in its own frame (local x is the major axis)."""

    shape: str  # "circle" or "rect"
    radius_in: float = 0.0
    length_in: float = 0.0  # along local x
    width_in: float = 0.0  # along local y


@dataclass(frozen=True)
class GraspRule:
    """A grasp that picks the object up when the robot approaches it as ``approach``
    says: "end" (heading within 45° of the major axis), "side" or "any"."""

    procedure: str
    approach: str


@dataclass(frozen=True)
class SideEffects:
    """What a failed grasp does to the object (chosen with the world's seeded RNG)."""

    push_p: float
    knock_over_p: float
    push_in: float
    knocks_to: str | None
    jams: tuple[str, ...]


@dataclass(frozen=True)
class CatalogueEntry:
    id: str
    name: str
    pose: str
    set: str
    footprint: Footprint
    height_in: float
    top_hole: bool
    front_hole: str | None
    round: bool
    grasps: tuple[GraspRule, ...]
    side_effects: SideEffects

    @property
    def rolls(self) -> bool:
        """A round object lying on its side rolls across its axis when pushed."""
        return self.round and self.footprint.shape == "rect"


def _finite(value: float) -> bool:
    """True for a finite number that a float can hold."""
    try:
        return math.isfinite(value)
    except OverflowError:  # an integer beyond the largest float
        return False


class FieldReader:
    """Field checks that name the file, the entry and the field in one line."""

    def __init__(self, source: str, where: str, table: object) -> None:
        if not isinstance(table, dict):
            raise ValueError(f"{source}: {where}: must be an object, got {type(table).__name__}")
        self.source, self.where, self.table = source, where, table

    def only(self, *fields: str) -> None:
        """Reject unknown fields: a misspelt optional field would otherwise be ignored."""
        unknown = sorted(set(self.table) - set(fields))
        if unknown:
            raise self.fail(unknown[0], f"is unknown (known: {', '.join(fields)})")

    def fail(self, field: str, problem: str) -> ValueError:
        """The one-line error for ``field``; its name quoted by ``repr``, so a key
        holding a newline cannot split the line."""
        return ValueError(f"{self.source}: {self.where}: field {field!r} {problem}")

    def number(self, field: str, minimum: float = 0.0, default: float | None = None) -> float:
        """A finite number >= ``minimum``: NaN passes every ``<`` test and an integer
        of 400 digits has no float, so finiteness is checked, not assumed."""
        value = self.table.get(field, default)
        if isinstance(value, bool) or not isinstance(value, (int, float)) or not _finite(value) or value < minimum:
            raise self.fail(field, f"must be a number >= {minimum}, got {value!r}")
        return float(value)

    def text(self, field: str, choices: Collection[str] | None = None, optional: bool = False) -> str | None:
        value = self.table.get(field)
        if value is None and optional:
            return None
        if not isinstance(value, str) or not value or (choices is not None and value not in choices):
            allowed = f" one of {sorted(choices)}" if choices is not None else " a non-empty string"
            raise self.fail(field, f"must be{allowed}, got {value!r}")
        return value

    def flag(self, field: str) -> bool:
        value = self.table.get(field)
        if not isinstance(value, bool):
            raise self.fail(field, f"must be true or false, got {value!r}")
        return value


def _footprint(source: str, where: str, table: object) -> Footprint:
    r = FieldReader(source, f"{where}.footprint", table)
    r.only("shape", "radius_in", "length_in", "width_in")
    shape = r.text("shape", ("circle", "rect"))
    if shape == "circle":
        return Footprint("circle", radius_in=r.number("radius_in", 0.1))
    length, width = r.number("length_in", 0.1), r.number("width_in", 0.1)
    if width > length:
        raise r.fail("width_in", f"must not exceed length_in (local x is the major axis), got {width} > {length}")
    return Footprint("rect", length_in=length, width_in=width)


def _side_effects(source: str, where: str, table: object, defaults: Mapping[str, object],
                  grasp_names: Collection[str]) -> SideEffects:
    r = FieldReader(source, f"{where}.side_effects", {**defaults, **(table or {})})
    r.only("push_p", "knock_over_p", "push_in", "knocks_to", "jams")
    push_p, knock_p = r.number("push_p"), r.number("knock_over_p")
    if push_p + knock_p > 1.0:
        raise r.fail("push_p", f"plus knock_over_p must not exceed 1, got {push_p + knock_p}")
    jams = r.table.get("jams", [])
    if not isinstance(jams, list) or any(j not in grasp_names for j in jams):
        raise r.fail("jams", f"must list known grasping procedures, got {jams!r}")
    knocks_to = r.text("knocks_to", optional=True)
    if knock_p > 0 and knocks_to is None:
        raise r.fail("knocks_to", "must name the lying entry when knock_over_p > 0")
    return SideEffects(push_p, knock_p, r.number("push_in"), knocks_to, tuple(jams))


def load_catalogue(grasp_names: Collection[str], path: str | Path | None = None) -> dict[str, CatalogueEntry]:
    """Read and check a catalogue; ``grasp_names`` are the profile's grasping procedures."""
    file = Path(path) if path is not None else DEFAULT_CATALOGUE
    source = str(file)
    try:
        data = json.loads(file.read_text(encoding="utf-8"))
    except (OSError, json.JSONDecodeError) as exc:
        raise ValueError(f"{source}: cannot read catalogue: {exc}") from exc
    top = FieldReader(source, "catalogue", data)
    top.only("about", "side_effect_defaults", "entries")
    defaults = top.table.get("side_effect_defaults", {})
    entries = top.table.get("entries")
    if not isinstance(entries, list) or not entries:
        raise top.fail("entries", "must be a non-empty list")
    catalogue: dict[str, CatalogueEntry] = {}
    for i, raw in enumerate(entries):
        where = f"entries[{i}]"
        r = FieldReader(source, where, raw)
        entry_id = r.text("id")
        where = f"entries[{i}] '{entry_id}'"
        r = FieldReader(source, where, raw)
        r.only("id", "name", "pose", "set", "footprint", "height_in", "top_hole", "front_hole", "round",
               "grasps", "side_effects")
        if entry_id in catalogue:
            raise r.fail("id", "is a duplicate")
        grasps_raw = r.table.get("grasps")
        if not isinstance(grasps_raw, list) or not grasps_raw:
            raise r.fail("grasps", "must be a non-empty list")
        grasps = []
        for j, g in enumerate(grasps_raw):
            gr = FieldReader(source, f"{where}.grasps[{j}]", g)
            gr.only("procedure", "approach")
            grasps.append(GraspRule(gr.text("procedure", grasp_names), gr.text("approach", APPROACHES)))
        catalogue[entry_id] = CatalogueEntry(
            id=entry_id,
            name=r.text("name"),
            pose=r.text("pose"),
            set=r.text("set", SETS),
            footprint=_footprint(source, where, raw.get("footprint")),
            height_in=r.number("height_in", 0.1),
            top_hole=r.flag("top_hole"),
            front_hole=r.text("front_hole", FACES, optional=True),
            round=r.flag("round"),
            grasps=tuple(grasps),
            side_effects=_side_effects(source, where, raw.get("side_effects"), defaults, grasp_names),
        )
    for entry in catalogue.values():
        target = entry.side_effects.knocks_to
        if target is not None and target not in catalogue:
            raise ValueError(f"{source}: entry '{entry.id}': field 'knocks_to' names unknown entry '{target}'")
    return catalogue


@lru_cache(maxsize=4)
def profile_and_catalogue(profile: RobotProfile | None = None) -> tuple[RobotProfile, Mapping[str, CatalogueEntry]]:
    """The profile (None: the shipped one) and the shipped catalogue checked against
    its grasps, read once per profile: training probes build thousands of one-object
    worlds and must not re-parse files each time."""
    loaded = load_profile(DEFAULT_PROFILE) if profile is None else profile
    return loaded, MappingProxyType(load_catalogue(loaded.grasp_names))
