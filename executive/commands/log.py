"""``csl log``: read an episode log back as the story of each object."""

from __future__ import annotations

import argparse
from pathlib import Path

from executive.episode_log import read_log

_SKIP = {"tick", "event", "object", "behaviour"}


def register(sub: argparse._SubParsersAction) -> None:
    p = sub.add_parser(
        "log", help="replay an episode log: what was decided, measured and paid, object by object",
        description=("Read an episode log (episode.jsonl, written by csl demo and csl run) back as a "
                     "narrative: each object's tests with their costs, the values measured and the "
                     "branches followed, every recovery, the grasp and what was learned."))
    p.add_argument("file", type=Path, help="an episode.jsonl")
    p.add_argument("--object", type=int, metavar="N", help="only object N")
    p.add_argument("--events", help="only these event kinds, comma-separated (e.g. choose,unreliable)")
    p.set_defaults(handler=run_log)


def run_log(args: argparse.Namespace) -> int:
    if not args.file.exists():
        raise ValueError(f"{args.file}: episode log not found")
    events = read_log(args.file)
    kinds = set(args.events.split(",")) if args.events else None
    current = None
    for e in events:
        if not isinstance(e, dict) or "event" not in e:
            raise ValueError(f"{args.file}: not an episode log (an entry has no 'event')")
        if args.object is not None and e.get("object") != args.object:
            continue
        if kinds is not None and e["event"] not in kinds:
            continue
        if e.get("object") is not None and e.get("object") != current:
            current = e.get("object")
            print(f"\nobject {current}")
        detail = ", ".join(f"{k}={v}" for k, v in e.items() if k not in _SKIP)
        print(f"  tick {e.get('tick', '?'):>4}  {e['event']:<18} {detail}")
    return 0
