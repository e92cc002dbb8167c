"""``csl view``: an episode as one HTML page to replay in a browser (recording/replay_page.py)."""

from __future__ import annotations

import argparse
from pathlib import Path


def register(sub: argparse._SubParsersAction) -> None:
    p = sub.add_parser(
        "view", help="replay an episode in a browser, from one HTML page",
        description=("Write one self-contained HTML page (no server, no network) that replays an episode "
                     "tick by tick: the behaviour tree coloured by status, the floor with the robot, its "
                     "paths and the objects, and each object's tests, grasps and outcome (docs/recording.md)."))
    p.add_argument("run", type=Path, metavar="RUN",
                   help="a recording made with --record FILE.mcap, or an out folder of csl run/demo")
    p.add_argument("--out", type=Path, default=None, metavar="FILE",
                   help="the page to write (default: replay.html in RUN's folder)")
    p.set_defaults(handler=run_view)


def run_view(args: argparse.Namespace) -> int:
    from recording.replay_page import load_replay, write_page

    out = args.out or (args.run if args.run.is_dir() else args.run.parent) / "replay.html"
    if not out.parent.is_dir():
        raise ValueError(f"--out {out}: no folder {out.parent}")
    replay = load_replay(args.run)
    try:
        write_page(replay, out)
    except OSError as exc:
        raise ValueError(f"--out {out}: cannot write ({exc.strerror or exc})") from None
    print(f"replay page: {out} ({replay.ticks} ticks, {len(replay.objects)} objects; open it in a browser)")
    return 0
