"""An episode as text a snapshot can pin: the behaviours ticked each tick, then every
decision the episode logged.

A snapshot must change only when behaviour changes, so nothing that differs between
two runs of the same scenario may appear: the episode log holds no wall-clock times,
a move's duration and path come from a sampling planner and are left out, and any
memory address or uuid a behaviour's text might carry is masked.
"""

from __future__ import annotations

import re
from collections.abc import Iterable, Mapping

TICKS_HEADER = "# ticks: every behaviour ticked this tick, with its status (S/F/R)"
EVENTS_HEADER = "# events"
NEXT_ENCOUNTER = "# --- next encounter ---"

VARYING: Mapping[str, frozenset[str]] = {"move": frozenset({"seconds", "path"})}
"""Fields left out per event kind: they vary with the planner's sampling, not with
what the robot decided."""

_UUID = re.compile(r"\b[0-9a-fA-F]{8}-[0-9a-fA-F]{4}-[0-9a-fA-F]{4}-[0-9a-fA-F]{4}-[0-9a-fA-F]{12}\b")
_ADDRESS = re.compile(r"\b0x[0-9a-fA-F]{6,}\b")


def masked(text: str) -> str:
    """``text`` with uuids shown as ``<uuid>`` and memory addresses as ``0x…``."""
    return _ADDRESS.sub("0x…", _UUID.sub("<uuid>", text))


def event_line(event: Mapping[str, object]) -> str:
    """One logged event: its tick, kind, and fields in the order they were logged."""
    kind = str(event["event"])
    hidden = {"tick", "event", "behaviour"} | VARYING.get(kind, frozenset())
    shown = ", ".join(f"{k}={v}" for k, v in event.items() if k not in hidden)
    return masked(f"{int(event['tick']):4d} {kind}: {shown}")  # type: ignore[call-overload]


def transcript_text(trace: Iterable[str], events: Iterable[Mapping[str, object]]) -> str:
    """The tick-by-tick trace, then the events, one per line."""
    lines = [TICKS_HEADER, *(masked(line) for line in trace), EVENTS_HEADER, *(event_line(e) for e in events)]
    return "\n".join(lines) + "\n"


def encounters(*transcripts: str) -> str:
    """Several episodes' transcripts in one snapshot (learning across encounters),
    separated by :data:`NEXT_ENCOUNTER` lines."""
    return (NEXT_ENCOUNTER + "\n").join(transcripts)
