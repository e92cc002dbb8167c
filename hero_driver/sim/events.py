"""Disturbances as declared: a world file's ``events`` list and the ``--disturb`` preset.

The paper's CSL "can not handle ... the disappearance of an object during sensing"
(docs/method.md); the simulator makes it happen so the executive's camera check can be
tested. Two sources, both seeded and repeatable (docs/simulator.md, "Disturbances"):

- a world file's ``events`` list: each disturbance at a robot step (the N-th move,
  sensing, grasp or charge) or at a robot time, on one object;
- a ``--disturb`` preset (``nudge:0.2``): each object, the first time the sonar senses
  it, is disturbed with that probability right after that measurement.

This module only reads and checks them (the world file reads its ``events`` here);
:mod:`hero_driver.sim.disturber` carries them out on the physics, so a world spec
needs nothing of the pymunk space.
"""

from __future__ import annotations

import math
from collections.abc import Mapping, Sequence
from dataclasses import dataclass

from hero_driver.sim.catalogue import CatalogueEntry, FieldReader

KINDS = ("nudge", "remove", "replace")


@dataclass(frozen=True)
class Disturbance:
    """One scheduled disturbance: when (``at_step`` or ``at_s``), to which object (its
    index in the world's ``objects``), and what: ``nudge`` by ``(dx_in, dy_in,
    dyaw_deg)``, ``remove``, or ``replace`` with catalogue entry ``entry``."""

    object: int
    do: str
    at_step: int | None = None
    at_s: float | None = None
    nudge: tuple[float, float, float] = (0.0, 0.0, 0.0)
    entry: str | None = None

    def due(self, steps: int, clock_s: float) -> bool:
        return (self.at_step is not None and steps >= self.at_step) or (self.at_s is not None and clock_s >= self.at_s)


@dataclass(frozen=True)
class DisturbPreset:
    """Per kind, the probability that an object is disturbed so during its sensing."""

    rates: tuple[tuple[str, float], ...] = ()

    @property
    def active(self) -> bool:
        return any(p > 0 for _, p in self.rates)


def parse_disturb(text: str) -> DisturbPreset:
    """``--disturb``'s value: ``KIND:P[,KIND:P...]`` with KIND one of nudge, remove,
    replace and the probabilities summing to at most 1 (one error line naming the flag)."""
    rates: dict[str, float] = {}
    for part in (p.strip() for p in text.split(",")):
        kind, _, value = part.partition(":")
        if kind not in KINDS:
            raise ValueError(f"--disturb: {part!r}: expected KIND:P with KIND one of {', '.join(KINDS)}")
        try:
            p = float(value)
        except ValueError:
            raise ValueError(f"--disturb: {part!r}: the probability must be a number from 0 to 1") from None
        if not 0.0 <= p <= 1.0:
            raise ValueError(f"--disturb: {part!r}: the probability must be a number from 0 to 1")
        if kind in rates:
            raise ValueError(f"--disturb: {kind} is given twice")
        rates[kind] = p
    if sum(rates.values()) > 1.0 + 1e-9:
        raise ValueError(f"--disturb: the probabilities sum to {sum(rates.values()):g}, more than 1")
    return DisturbPreset(tuple(rates.items()))


def parse_events(raw: object, source: str, placements: Sequence[str],
                 catalogue: Mapping[str, CatalogueEntry]) -> tuple[Disturbance, ...]:
    """A world file's ``events`` array; ``placements`` are its objects' entry ids, so an
    event may name its object by index or by entry id (the first object of that entry)."""
    if raw is None:
        return ()
    if not isinstance(raw, list):
        raise ValueError(f"{source}: world: field 'events' must be an array")
    out = []
    for i, item in enumerate(raw):
        r = FieldReader(source, f"events[{i}]", item)
        r.only("at_step", "at_s", "object", "do", "dx_in", "dy_in", "dyaw_deg", "entry")
        if ("at_step" in r.table) == ("at_s" in r.table):
            raise r.fail("at_step", "or 'at_s' must be given, not both and not neither")
        at_step = int(r.number("at_step", 1.0)) if "at_step" in r.table else None
        if at_step is not None and r.table["at_step"] != at_step:
            raise r.fail("at_step", f"must be a whole number of robot steps, got {r.table['at_step']!r}")
        at_s = r.number("at_s") if "at_s" in r.table else None
        index = _object_index(r, placements)
        do = r.text("do", KINDS)
        assert do is not None
        allowed = {"nudge": ("dx_in", "dy_in", "dyaw_deg"), "replace": ("entry",), "remove": ()}[do]
        stray = sorted(k for k in ("dx_in", "dy_in", "dyaw_deg", "entry") if k in r.table and k not in allowed)
        if stray:
            raise r.fail(stray[0], f"does not apply to do '{do}'")
        nudge = (_signed(r, "dx_in"), _signed(r, "dy_in"), _signed(r, "dyaw_deg"))
        entry = r.text("entry") if do == "replace" else None
        if entry is not None and entry not in catalogue:
            raise r.fail("entry", f"names unknown catalogue entry '{entry}'")
        out.append(Disturbance(index, do, at_step, at_s, nudge, entry))
    return tuple(out)


def _object_index(r: FieldReader, placements: Sequence[str]) -> int:
    value = r.table.get("object")
    if isinstance(value, str) and value in placements:
        return placements.index(value)
    if isinstance(value, int) and not isinstance(value, bool) and 0 <= value < len(placements):
        return value
    raise r.fail("object", f"must be an index into objects (0-{len(placements) - 1}) or one of their entry ids, "
                           f"got {value!r}")


def _signed(r: FieldReader, field: str) -> float:
    value = r.table.get(field, 0.0)
    if isinstance(value, bool) or not isinstance(value, (int, float)) or not math.isfinite(value):
        raise r.fail(field, f"must be a number, got {value!r}")
    return float(value)
