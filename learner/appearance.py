"""What the overhead camera already measured of an object: its appearance, a free feature.

Before the robot moves, the camera has seen the object's footprint: whether it looks
round, its area and its elongation. A description recorded with the appearance its object
showed can be ruled out at no cost when the object at hand looks different (a lying can is
longer than any upright can), so the tree need not pay a sweep to learn what the image
already said (docs/method.md §5, docs/library-format.md).

The comparison is on the footprint's equivalent ellipse (the ellipse with the same area
and elongation): its major and minor axes, each within an absolute tolerance in inches.
The camera's error is a pixel or two at the outline whatever the object's size, so a
ratio tolerance that spares a 9-pixel box would blur every large object together. The
round flag is recorded but not compared: small round objects are called round or not
depending on how they fall on the pixel grid (docs/library-format.md gives the numbers).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

# Two pixels at the shipped camera's 0.8 in per pixel; the worst disagreement measured
# over the catalogue (880 views: 22 objects, 10 random floors, 4 noise presets) was
# 1.44 in on the major axis and 1.23 in on the minor (docs/library-format.md).
AXIS_TOLERANCE_IN = 1.6


@dataclass(frozen=True)
class Appearance:
    """An object's footprint as the overhead camera saw it.

    ``area_in2``: footprint area (square inches); ``elongation``: major over minor axis
    of the footprint's second moments (1 for a disc or a square, >= 1 always).
    """

    round: bool
    area_in2: float
    elongation: float

    def __post_init__(self) -> None:
        if not (math.isfinite(self.area_in2) and self.area_in2 > 0):
            raise ValueError(f"appearance area must be a positive number of square inches, got {self.area_in2!r}")
        if not (math.isfinite(self.elongation) and self.elongation >= 1.0):
            raise ValueError(f"appearance elongation must be a number >= 1, got {self.elongation!r}")

    @property
    def axes_in(self) -> tuple[float, float]:
        """Major and minor axis (inches) of the ellipse with this area and elongation:
        ``area = pi/4 * major * minor`` and ``elongation = major / minor``."""
        return equivalent_axes(self.area_in2, self.elongation)

    def agrees(self, other: Appearance, tolerance_in: float = AXIS_TOLERANCE_IN) -> bool:
        """True when ``other`` could be the same object seen again: both axes within
        ``tolerance_in``."""
        (a_major, a_minor), (b_major, b_minor) = self.axes_in, other.axes_in
        return abs(a_major - b_major) <= tolerance_in + 1e-9 and abs(a_minor - b_minor) <= tolerance_in + 1e-9

    def to_json(self) -> dict[str, object]:
        return {"round": self.round, "area_in2": round(self.area_in2, 3), "elongation": round(self.elongation, 3)}


def equivalent_axes(area_in2: float, elongation: float) -> tuple[float, float]:
    """Major and minor axis of the ellipse with ``area_in2`` and ``elongation``."""
    major = 2.0 * math.sqrt(area_in2 * elongation / math.pi)
    return major, major / elongation


def appearance_from_json(data: object, where: str) -> Appearance:
    """Parse ``{"round": bool, "area_in2": number, "elongation": number}``; errors name
    ``where`` and the field."""
    if not isinstance(data, dict):
        raise ValueError(f"{where}: must be an object with 'round', 'area_in2' and 'elongation'")
    unknown = sorted(set(data) - {"round", "area_in2", "elongation"})
    if unknown:
        raise ValueError(f"{where}: unknown key {unknown[0]!r}")
    if not isinstance(data.get("round"), bool):
        raise ValueError(f"{where}: 'round' must be true or false")
    for key in ("area_in2", "elongation"):
        value = data.get(key)
        if isinstance(value, bool) or not isinstance(value, (int, float)):
            raise ValueError(f"{where}: '{key}' must be a number, got {value!r}")
    try:
        return Appearance(data["round"], float(data["area_in2"]), float(data["elongation"]))
    except ValueError as exc:
        raise ValueError(f"{where}: {exc}") from None
