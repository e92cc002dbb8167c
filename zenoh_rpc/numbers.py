"""What counts as a whole number in a message, for every service on the wire (the
driver link and the learner alike): one rule, so a client that one service accepts is
not refused by the other.

JSON has one number type, and some writers (a C double, JavaScript) cannot tell ``3``
from ``3.0``; JSON Schema's ``integer`` counts ``3.0`` too. So a number with no
fractional part is whole; a boolean is not a number here (Python's ``True == 1``).
"""

from __future__ import annotations

import numbers


def whole_number(value: object) -> int | None:
    """``value`` as an int when it is a whole number (``3`` or ``3.0``); None otherwise
    (a fraction, a boolean, a string, anything else)."""
    if isinstance(value, bool) or type(value).__name__ == "bool_":  # numpy's bool too
        return None
    if isinstance(value, float):
        return int(value) if value.is_integer() else None
    if isinstance(value, numbers.Integral):
        return int(value)
    return None
