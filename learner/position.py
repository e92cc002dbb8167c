"""Positions of the sensor relative to an object: ``(distance in inches, orientation in degrees)``.

Either slot may be ``*`` ("don't care"): a feature whose value does not depend on that
slot was generalised there during training (docs/method.md §4), e.g. ``Height(6,*)``. We
store ``*`` as ``None``.
"""

from __future__ import annotations

import functools
import math
from dataclasses import dataclass

ANY = "*"
_JSON_SLOT = (int, float, str)  # exact types a valid JSON slot has (bool is not int here)
_KNOWN_LIMIT = 4096  # positions are a small grid; a bound keeps hostile input from growing it


_KNOWN: dict[tuple[object, object], Position] = {}  # valid JSON slots -> their shared Position


@functools.total_ordering
@dataclass(frozen=True, slots=True)
class Position:
    """Where a feature was (or is to be) measured, relative to the object."""

    distance_in: float | None
    orientation_deg: float | None

    def __lt__(self, other: Position) -> bool:
        """Concrete slots sort before ``*``, so listings and ties are deterministic."""
        return self.order_key() < other.order_key()

    def order_key(self) -> tuple[bool, float, bool, float]:
        """The sort order as a plain tuple: equal exactly when the positions are equal,
        so a large sort can compare keys in C instead of calling ``__lt__``."""
        return (self.distance_in is None, self.distance_in or 0.0,
                self.orientation_deg is None, self.orientation_deg or 0.0)

    def covers(self, other: Position) -> bool:
        """True when a value recorded at ``self`` holds at ``other``.

        A slot covers another when it is ``*`` or equal: ``Height(6,*)`` holds at
        ``(6, 90)``, but ``Width-Degree-1°(24,0)`` does not hold at ``(24, *)``.
        """
        return _slot_covers(self.distance_in, other.distance_in) and _slot_covers(
            self.orientation_deg, other.orientation_deg
        )

    def overlaps(self, other: Position) -> bool:
        """True when a value measured at either position serves a test at the other: a
        value at ``(6,90)`` serves ``Height(6,*)``, and one recorded at ``(6,*)`` (an
        object with no orientation) serves ``Height(6,90)``."""
        return self.covers(other) or other.covers(self)

    def compatible(self, other: Position) -> bool:
        """True when some concrete position satisfies both (each slot ``*`` or equal)."""
        return _slot_compatible(self.distance_in, other.distance_in) and _slot_compatible(
            self.orientation_deg, other.orientation_deg
        )

    def concrete(self, current: Position) -> Position:
        """Fill ``*`` slots from ``current``: the robot need not move along a don't-care slot."""
        return Position(
            self.distance_in if self.distance_in is not None else current.distance_in,
            self.orientation_deg if self.orientation_deg is not None else current.orientation_deg,
        )

    def to_json(self) -> list[float | str]:
        """``[d, theta]`` with ``"*"`` for a don't-care slot."""
        return [_slot_json(self.distance_in), _slot_json(self.orientation_deg)]

    def __str__(self) -> str:
        """The position as people read it, ``(6,90)`` as the paper writes it: each slot
        to a tenth of an inch or of a degree (a bearing the robot reached is
        ``339.2``, not ``339.16071978233924``), ``*`` for a don't-care slot. Only
        text: the exact values are :meth:`to_json`'s, which logs and files keep."""
        return f"({_slot_text(self.distance_in)},{_slot_text(self.orientation_deg, turn=360.0)})"


def position_from_json(value: object, where: str) -> Position:
    """Parse ``[d, theta]`` (numbers or ``"*"``); ``where`` names the field in errors."""
    known = known_position_json(value)
    if known is not None:
        return known
    if not isinstance(value, (list, tuple)) or len(value) != 2:
        raise ValueError(f"{where}: a position is [distance, orientation], got {value!r}")
    position = _checked(Position(_slot_parse(value[0], f"{where}[0]"), _slot_parse(value[1], f"{where}[1]")), where)
    if len(_KNOWN) < _KNOWN_LIMIT and type(value[0]) in _JSON_SLOT and type(value[1]) in _JSON_SLOT:
        _KNOWN[value[0], value[1]] = position
    return position


def known_position_json(value: object) -> Position | None:
    """The one shared Position for a JSON ``[d, theta]`` already parsed valid, else None.

    A library repeats a few positions hundreds of thousands of times; looking them up
    skips re-validating and re-building each, and shares one object among them. A miss
    says nothing about validity: call :func:`position_from_json` for the error.
    """
    if type(value) is list and len(value) == 2:
        d, theta = value
        if type(d) in _JSON_SLOT and type(theta) in _JSON_SLOT:
            return _KNOWN.get((d, theta))
    return None


def _checked(p: Position, where: str) -> Position:
    """A distance is never negative; an orientation is a bearing in [0, 360)."""
    if p.distance_in is not None and p.distance_in < 0:
        raise ValueError(f"{where}: distance must not be negative, got {p.distance_in:g}")
    if p.orientation_deg is not None and not 0 <= p.orientation_deg < 360:
        raise ValueError(f"{where}: orientation must be in [0, 360) degrees, got {p.orientation_deg:g}")
    return p


def parse_position(text: str, where: str = "position") -> Position:
    """Parse ``"D,THETA"`` as typed on a command line (``*`` allowed)."""
    parts = [p.strip() for p in text.split(",")]
    if len(parts) != 2:
        raise ValueError(f"{where}: expected DISTANCE,ORIENTATION (e.g. 60,0), got {text!r}")
    return _checked(Position(_slot_parse(_number_or_any(parts[0]), f"{where} distance"),
                             _slot_parse(_number_or_any(parts[1]), f"{where} orientation")), where)


def _number_or_any(text: str) -> object:
    if text == ANY:
        return ANY
    try:
        return float(text)
    except ValueError:
        return text


def _slot_parse(value: object, where: str) -> float | None:
    if value == ANY or value is None:
        return None
    if isinstance(value, bool) or not isinstance(value, (int, float)):
        raise ValueError(f"{where}: expected a number or \"*\", got {value!r}")
    if not finite_number(value):
        raise ValueError(f"{where}: expected a finite number, got {value!r}")
    return float(value)


def finite_number(value: float) -> bool:
    """``math.isfinite`` that calls an integer too large for a float not finite (JSON
    allows 400-digit integers; they must give the error, not an OverflowError)."""
    try:
        return math.isfinite(value)
    except OverflowError:
        return False


def _slot_covers(mine: float | None, other: float | None) -> bool:
    return mine is None or (other is not None and math.isclose(mine, other, abs_tol=1e-9))


def _slot_compatible(a: float | None, b: float | None) -> bool:
    return a is None or b is None or math.isclose(a, b, abs_tol=1e-9)


def _slot_json(value: float | None) -> float | str:
    if value is None:
        return ANY
    return int(value) if float(value).is_integer() else value


def _slot_text(value: float | None, turn: float | None = None) -> str:
    """A slot to one decimal, whole numbers without it; an orientation that rounds up
    to a full ``turn`` reads as 0, the bearing it is."""
    if value is None:
        return ANY
    tenths = round(float(value), 1)
    if turn is not None and tenths >= turn:
        tenths -= turn
    return str(int(tenths)) if tenths.is_integer() else f"{tenths:.1f}"
