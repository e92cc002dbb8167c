"""``csl log``: read an episode log back as the story of each object."""

from __future__ import annotations

import argparse
from pathlib import Path

from behaviours.events import Event

EVENT_KINDS = tuple(e.value for e in Event)

_SKIP = {"tick", "event", "object", "behaviour"}


def register(sub: argparse._SubParsersAction) -> None:
    p = sub.add_parser(
        "log", help="replay an episode log: what was decided, measured and paid, object by object",
        description=("Read an episode log (episode.jsonl, written by csl demo and csl run, or a recording "
                     "made with --record FILE.mcap) back as a narrative: each object's tests with their costs, "
                     "the values measured and the branches followed, every recovery, the grasp and what was "
                     "learned."))
    p.add_argument("file", type=Path, help="an episode.jsonl, or a .mcap recording (docs/recording.md)")
    p.add_argument("--object", type=int, metavar="N", help="only object N")
    p.add_argument("--events", metavar="KINDS",
                   help=f"only these event kinds, comma-separated; one of: {', '.join(EVENT_KINDS)}")
    p.set_defaults(handler=run_log)


def run_log(args: argparse.Namespace) -> int:
    from recording.reader import read_events  # the mcap library: loaded by csl log alone

    events = read_events(args.file)
    if not events:
        raise ValueError(f"{args.file}: the episode log is empty")
    for n, e in enumerate(events, 1):
        _check_event(e, f"{args.file}: event {n}")
    kinds = set(args.events.split(",")) if args.events else None
    unknown = sorted((kinds or set()) - set(EVENT_KINDS))
    if unknown:
        raise ValueError(f"--events: unknown kind {unknown[0]!r} (one of: {', '.join(EVENT_KINDS)})")
    objects = {e.get("object") for e in events if isinstance(e, dict)}
    if args.object is not None and args.object not in objects:
        known = sorted(o for o in objects if isinstance(o, int))
        raise ValueError(f"--object: no object {args.object} in {args.file} (objects: {known})")
    current = None
    for e in events:
        if args.object is not None and e.get("object") != args.object:
            continue
        if kinds is not None and e["event"] not in kinds:
            continue
        if e.get("object") is not None and e.get("object") != current:
            current = e.get("object")
            print(f"\nobject {current}")
        detail = ", ".join(_field(k, v) for k, v in e.items() if k not in _SKIP)
        print(f"  tick {e.get('tick', '?'):>4}  {e['event']:<18} {detail}")
    return 0


def _check_event(e: object, where: str) -> None:
    """An event has the shape the story prints: an ``event`` kind that is a string,
    and a ``tick`` and an ``object`` that are integers when present (``object`` may be
    null), as :class:`~executive.episode_log.EpisodeLog` writes them."""
    if not isinstance(e, dict) or "event" not in e:
        raise ValueError(f"{where}: not an episode event (no 'event')")
    if not isinstance(e["event"], str):
        raise ValueError(f"{where}: 'event' must be a string, got {type(e['event']).__name__}")
    for key, may_be_null in (("tick", False), ("object", True)):
        value = e.get(key, 0)
        if not (isinstance(value, int) and not isinstance(value, bool)) and not (may_be_null and value is None):
            raise ValueError(f"{where}: {key!r} must be an integer, got {type(value).__name__}")


def _field(key: str, value: object) -> str:
    """One field of an event as the story prints it; a move's planned waypoints (many
    numbers, drawn on the map and in a recording) are counted, not listed."""
    if key == "path" and isinstance(value, list):
        return f"waypoints={len(value)}"
    return f"{key}={value}"
