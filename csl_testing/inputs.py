"""A scenario's keyword arguments turned into the domain values an episode needs.

A snapshot test is written by hand, so each value comes in the form a person has at
hand (a shipped world's name, a preset's name, a library file) and every mistake is
one line naming the keyword, not a traceback from deep inside the simulator.
"""

from __future__ import annotations

import dataclasses
import json
from collections.abc import Mapping, Sequence
from pathlib import Path

from hero_driver.shipped import shipped_worlds
from executive.defaults import EXAMPLE_LIBRARY
from hero_driver.sim.catalogue import CatalogueEntry
from hero_driver.sim.noise import NOISE_PRESETS, NoiseConfig
from hero_driver.sim.worldfile import Placement, WorldSpec, parse_world, resolve
from learner.choosing.criteria import Criterion, criterion
from learner.description import ObjectDescription
from learner.library.store import load_library

ObjectEntry = Placement | tuple[str, float, float] | tuple[str, float, float, float]
"""An object on the floor: a :class:`Placement`, or ``(entry, x_in, y_in[, yaw_deg])``."""

BARE_ROOM: Mapping[str, object] = {
    "name": "scenario", "room": {"width_in": 200.0, "depth_in": 140.0},
    "robot": {"x_in": 30.0, "y_in": 30.0, "heading_deg": 0.0}}
"""The world when none is given: an empty 200 x 140 in room, the robot in a corner, so
the objects placed are all the episode sees."""

STEADY_NOISE = NoiseConfig(odometry_frac=0.0, odometry_heading_deg=0.0, pixel_sigma=0.0)
"""The default noise: the simulator's mild sonar noise (so recoveries happen), with
exact odometry and a clean camera, so that the poses and regions in a transcript
depend on the seed and the sonar alone."""


def placements(objects: Sequence[ObjectEntry]) -> tuple[Placement, ...]:
    """Each entry as a :class:`Placement`; anything else is refused naming its index."""
    placed = []
    for i, entry in enumerate(objects):
        if isinstance(entry, Placement):
            placed.append(entry)
            continue
        if (not isinstance(entry, tuple) or len(entry) not in (3, 4) or not isinstance(entry[0], str)
                or not all(isinstance(v, (int, float)) and not isinstance(v, bool) for v in entry[1:])):
            raise ValueError(f"objects[{i}]: expected a Placement or (entry, x_in, y_in[, yaw_deg]), got {entry!r}")
        placed.append(Placement(entry[0], *(float(v) for v in entry[1:])))
    return tuple(placed)


def world_spec(world: str | Path | WorldSpec | None, objects: Sequence[ObjectEntry] | None,
               catalogue: Mapping[str, CatalogueEntry]) -> WorldSpec:
    """The world to simulate: ``world`` (None: :data:`BARE_ROOM`; a shipped world's name;
    a world file; a :class:`WorldSpec`) with its objects replaced by ``objects`` when
    given. Files and the bare room go through the world-file checks, so an unknown
    catalogue entry or an object through a wall is refused before the episode."""
    placed = None if objects is None else placements(objects)
    if isinstance(world, WorldSpec):
        return world if placed is None else dataclasses.replace(world, objects=placed)
    if world is None:
        data, source = dict(BARE_ROOM), "<scenario>"
    else:
        path = resolve(world)
        if not path.is_file():
            raise ValueError(f"world: {str(world)!r} is neither a world file nor a shipped world "
                             f"(shipped: {', '.join(shipped_worlds())})")
        try:
            data = json.loads(path.read_text(encoding="utf-8"))
        except (OSError, UnicodeDecodeError, json.JSONDecodeError) as exc:
            raise ValueError(f"world: {path}: cannot read world file: {exc}") from None
        if not isinstance(data, dict):
            raise ValueError(f"world: {path}: a world file is a JSON object")
        source = str(path)
    if placed is not None:
        data["objects"] = [{"id": p.entry_id, "x_in": p.x_in, "y_in": p.y_in, "yaw_deg": p.yaw_deg} for p in placed]
    return parse_world(data, source, catalogue)


def noise_config(noise: str | NoiseConfig | None) -> NoiseConfig | None:
    """A preset's name (clean, mild, paper, harsh) or a :class:`NoiseConfig`; None
    leaves the world's own ``noise`` table (else the mild preset) to the simulator."""
    if noise is None or isinstance(noise, NoiseConfig):
        return noise
    if isinstance(noise, str) and noise in NOISE_PRESETS:
        return NOISE_PRESETS[noise]
    raise ValueError(f"noise: expected a NoiseConfig or one of {', '.join(NOISE_PRESETS)}, got {noise!r}")


def seed_library(library: str | Path | Sequence[ObjectDescription] | None) -> list[ObjectDescription]:
    """The descriptions a fresh store starts from: the shipped example library (None),
    a library file (``.json`` or a SQLite store) or the descriptions themselves."""
    if library is None:
        return load_library(EXAMPLE_LIBRARY)
    if isinstance(library, (str, Path)):
        try:
            return load_library(library)
        except ValueError as exc:
            raise ValueError(f"library: {exc}") from None
    descriptions = list(library)
    for i, d in enumerate(descriptions):
        if not isinstance(d, ObjectDescription):
            raise ValueError(f"library[{i}]: expected an ObjectDescription, got {type(d).__name__}")
    return descriptions


def criterion_of(chosen: str | Criterion | None) -> Criterion | None:
    """A criterion's name (a key of ``learner.choosing.criteria.CRITERIA``) or a built one; None is the
    executive's default."""
    if chosen is None or not isinstance(chosen, str):
        return chosen
    try:
        return criterion(chosen)
    except ValueError as exc:
        raise ValueError(f"criterion: {exc}") from None
