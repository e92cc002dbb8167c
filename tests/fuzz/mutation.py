"""Hypothesis strategies for hostile input: JSON values, mutated valid documents, and
byte-level damage to a valid encoding.

A fuzzer that only draws random JSON rarely gets past a parser's first check, so most
cases start from a real, valid document (a shipped world, library entry, profile) and
change one to three places in it: a value replaced by something hostile (NaN, 1e308, a
5,000-digit integer, a wrong type, a deep nest), a key deleted or added. The bytes
layer then adds what JSON values cannot say: broken UTF-8, truncation, nesting bombs.
Sizes are bounded so that every case is quick.
"""

from __future__ import annotations

import copy
import json
import math
from typing import Any

from hypothesis import strategies as st

HUGE_DIGITS = 5000
"""A JSON integer longer than Python's 4,300-digit conversion limit."""

NEST = 30_000
"""Nesting deep enough to exhaust Python's recursion limit in ``json.loads``."""

hostile_numbers = st.sampled_from([0, -1, 1, 2**63, -(2**63), 1e308, -1e308, 1e-320, 5e-324,
                                   math.nan, math.inf, -math.inf, 0.5, -0.0, 10**30])
json_scalars = st.one_of(
    st.none(), st.booleans(), st.integers(min_value=-(10**20), max_value=10**20),
    st.floats(allow_nan=True, allow_infinity=True), hostile_numbers,
    st.text(max_size=12), st.sampled_from(["", "*", "../x", "/etc/passwd", "\x00", "é°", "a" * 300]),
)
json_values = st.recursive(
    json_scalars,
    lambda inner: st.lists(inner, max_size=4) | st.dictionaries(st.text(max_size=8), inner, max_size=4),
    max_leaves=10,
)


def _places(doc: Any, path: tuple[Any, ...] = ()) -> list[tuple[Any, ...]]:
    """Every path to a value inside ``doc`` (the root is ``()``)."""
    out = [path]
    if isinstance(doc, dict):
        for key, value in doc.items():
            out += _places(value, path + (key,))
    elif isinstance(doc, list):
        for i, value in enumerate(doc):
            out += _places(value, path + (i,))
    return out


def _get(doc: Any, path: tuple[Any, ...]) -> Any:
    for step in path:
        doc = doc[step]
    return doc


@st.composite
def mutated(draw: st.DrawFn, base: Any, values: st.SearchStrategy[Any] = json_values, root: bool = True) -> Any:
    """``base`` with one to three places replaced, deleted, or given an extra key
    (``root``: the whole document may be replaced too)."""
    doc = copy.deepcopy(base)
    for _ in range(draw(st.integers(1, 3))):
        places = _places(doc)
        numbers = [p for p in places if p and type(_get(doc, p)) in (int, float)]
        op = draw(st.sampled_from(["number", "replace", "replace", "delete", "add"]))
        if op == "number" and numbers:  # aimed at a number: the values a schema check may let through
            path = draw(st.sampled_from(numbers))
            _get(doc, path[:-1])[path[-1]] = draw(hostile_numbers)
            continue
        path = draw(st.sampled_from(places))
        op = "replace" if op == "number" else op
        if not path:
            if op == "replace" and root:
                doc = draw(values)
            continue
        parent, last = _get(doc, path[:-1]), path[-1]
        if op == "replace":
            parent[last] = draw(values)
        elif op == "delete":
            del parent[last]
        elif isinstance(parent, dict):
            parent[draw(st.text(min_size=1, max_size=8))] = draw(values)
        else:
            parent.append(draw(values))
    return doc


def dumps(doc: Any) -> bytes:
    """JSON text of a drawn document; NaN and Infinity are written as Python does,
    since some writers emit them and a reader must refuse them cleanly."""
    return json.dumps(doc, allow_nan=True, ensure_ascii=False).encode("utf-8", "surrogatepass")


@st.composite
def damaged_bytes(draw: st.DrawFn, valid: bytes) -> bytes:
    """``valid`` with bytes flipped, cut, or spliced with hostile tokens."""
    data = bytearray(valid)
    for _ in range(draw(st.integers(1, 3))):
        op = draw(st.sampled_from(["flip", "cut", "insert", "truncate"]))
        at = draw(st.integers(0, max(len(data) - 1, 0)))
        if op == "flip" and data:
            data[at] = draw(st.integers(0, 255))
        elif op == "cut":
            del data[at:at + draw(st.integers(1, 16))]
        elif op == "insert":
            data[at:at] = draw(st.sampled_from(tokens()))
        else:
            data = data[:at]
    return bytes(data)


def tokens() -> list[bytes]:
    return [b"NaN", b"-Infinity", b"1e999", b"9" * HUGE_DIGITS, b"\xff\xfe", b"\x00", b'"', b"{", b"[", b"]",
            b"}", b",", b":", b"null", b"true", b'"\\ud800"', b"\n", b"[" * 100]


def bombs(valid_prefix: bytes = b'{"v": 1, "x": ') -> list[bytes]:
    """Payloads aimed at a JSON parser's limits rather than at a schema."""
    return [
        b"[" * NEST + b"]" * NEST,
        b'{"a":' * NEST + b"1" + b"}" * NEST,
        valid_prefix + b"1" + b"0" * HUGE_DIGITS + b"}",
        b'{"v": ' + b"1" * HUGE_DIGITS + b"}",
        b"",
        b"\xff" * 10,
        b"null",
        b'"v"',
        b"1e400",
    ]


def payloads(valid_doc: Any) -> st.SearchStrategy[bytes]:
    """Request bodies for a parser whose good input is ``valid_doc``."""
    valid = dumps(valid_doc)
    return st.one_of(
        st.just(valid),
        mutated(valid_doc).map(dumps),
        damaged_bytes(valid),
        st.sampled_from(bombs()),
        json_values.map(dumps),
        st.binary(max_size=64),
    )
