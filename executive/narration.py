"""The episode told on Python's ``logging``: what ``csl -v`` shows while a run goes on.

Every event the behaviours report goes through the episode log
(:class:`executive.episode_log.EpisodeLog`), so the story is told from there, one line
an event, and no behaviour logs for itself: a new event kind is told without a line
here. At INFO (``-v``) a line names the tick, the object, the event and its fields,
a bulky one by its count (a move's path, the candidates left, the regions located); a
test chosen says its cost (``move + sense``), and a recovery says it is one. At DEBUG
(``-vv``) the bulky fields follow whole on a line of their own. Each object's outcome, settled, closes its part
of the story (:func:`tell_outcome`).

Nothing here is measured from the wall clock: the lines repeat from run to run, as the
episode log does.
"""

from __future__ import annotations

import json
import logging
from collections.abc import Mapping

from behaviours.events import Event
from behaviours.records import ObjectRecord

log = logging.getLogger(__name__)

BULKY_CHARS = 60
"""A field whose JSON is longer than this (a path, a list of candidates) is detail:
told at DEBUG, on a line of its own."""
_UNTOLD = frozenset({"tick", "event", "object", "behaviour"})  # said in the line's head, or not at all


def tell(record: Mapping[str, object]) -> None:
    """Log one episode-log event (as logged: tick, event, fields)."""
    if not log.isEnabledFor(logging.INFO):
        return
    kind = Event(str(record["event"]))
    bulky = {k: v for k, v in record.items() if k not in _UNTOLD and _bulky(v)}
    short = {k: f"({len(v)})" if k in bulky else v  # type: ignore[arg-type]
             for k, v in record.items() if k not in _UNTOLD}
    head = _head(record)
    log.info("%s%s%s", head, "recovery " if kind.recovery else "", _say(kind, short))
    if bulky and log.isEnabledFor(logging.DEBUG):
        log.debug("%s%s detail: %s", head, kind.value, _fields(bulky))


def tell_outcome(record: ObjectRecord) -> None:
    """Log an object's outcome once it is reported: outcome, grasp, robot time."""
    if not log.isEnabledFor(logging.INFO):
        return
    log.info("object %d: outcome %s%s, %.1f robot min", record.index, record.outcome or "unfinished",
             f" with {record.grasp}" if record.grasp else "", record.ledger.robot_s / 60)


def _head(record: Mapping[str, object]) -> str:
    where = f"tick {record.get('tick')}"
    if "object" in record:
        where += f", object {record['object']}"
    return where + ": "


def _say(kind: Event, fields: dict[str, object]) -> str:
    """The event's words: a test chosen with its cost, else its name and fields."""
    if kind is Event.CHOOSE:
        move_s, sense_s = fields.pop("move_s", None), fields.pop("sense_s", None)
        test, how = fields.pop("test", "?"), fields.pop("how", "?")
        cost = (f", cost {move_s + sense_s:.1f} s (move {move_s:g} s + sense {sense_s:g} s)"
                if isinstance(move_s, (int, float)) and isinstance(sense_s, (int, float)) else "")
        rest = _fields(fields)
        return f"choose {test} ({how}){cost}{', ' + rest if rest else ''}"
    rest = _fields(fields)
    return f"{kind.value}{': ' + rest if rest else ''}"


def _fields(fields: Mapping[str, object]) -> str:
    return ", ".join(f"{name} {_value(value)}" for name, value in fields.items())


def _value(value: object) -> str:
    """A field as a person reads it: a point as (x, y), a mapping as name value pairs,
    numbers as logged (the behaviours round them), true/false/none lower case."""
    if value is None or isinstance(value, bool):
        return json.dumps(value)
    if isinstance(value, float):
        return f"{value:g}"
    if isinstance(value, Mapping):
        return "{" + _fields({str(k): v for k, v in value.items()}) + "}"
    if isinstance(value, (list, tuple)):
        if value and all(isinstance(v, (int, float)) and not isinstance(v, bool) for v in value):
            return "(" + ", ".join(_value(v) for v in value) + ")"
        return "[" + ", ".join(_value(v) for v in value) + "]"
    return str(value)


def _bulky(value: object) -> bool:
    return isinstance(value, (list, tuple, Mapping)) and len(json.dumps(value, default=str)) > BULKY_CHARS
