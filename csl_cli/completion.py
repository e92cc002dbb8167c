"""Shell completion of robot names and library description ids (argcomplete's
``completer`` hooks, set on the arguments in ``csl_cli/main.py`` and
``csl_cli/commands/library.py``).

A completer runs while the user waits at the prompt, so each one is quick and quiet:
the robots alive on the driver endpoint are asked for once, for at most
:data:`LIVE_QUERY_S` seconds, and a library is read, not opened as a store (no
check, no upgrade, no write). Anything that goes wrong completes the fallback, never
an error on the user's terminal.
"""

from __future__ import annotations

import argparse
import sqlite3
import time
from contextlib import closing
from pathlib import Path

from hero_driver.zenoh_link.keys import PREFIX
from zenoh_rpc.endpoints import DRIVER_ENDPOINT

LIVE_QUERY_S = 0.5
"""The longest the robot completer waits for the driver endpoint's answer, session
opening included: longer, and a Tab press feels broken."""
DEFAULT_ROBOT = "r1"
"""The name every command's ``--robot`` defaults to, and ``csl driver sim`` serves
unless told otherwise: offered when no live robot answers (the shipped worlds and
profiles name no robot: a world places *the* robot, a profile describes its kind)."""


def live_robots(endpoint: str = DRIVER_ENDPOINT, timeout_s: float = LIVE_QUERY_S) -> list[str]:
    """The robot names whose driver liveliness token (``hero/<robot>/alive``) is
    visible through ``endpoint``, sorted; [] when nothing answers within ``timeout_s``
    (no driver, no such endpoint, zenoh unable to start)."""
    import zenoh

    from zenoh_rpc.config import close_session, open_session

    deadline = time.monotonic() + timeout_s
    try:
        session = open_session(connect=[endpoint], connect_timeout_s=timeout_s / 2)
    except (OSError, ValueError, zenoh.ZError):
        return []
    try:
        left = max(deadline - time.monotonic(), 0.05)
        replies = session.liveliness().get(f"{PREFIX}/*/alive", timeout=left)
        names = set()
        for reply in replies:
            if reply.ok is None:
                continue
            parts = str(reply.ok.key_expr).split("/")
            if len(parts) == 3 and parts[0] == PREFIX and parts[2] == "alive":
                names.add(parts[1])
        return sorted(names)
    except zenoh.ZError:
        return []
    finally:
        close_session(session)


def complete_robot(prefix: str, parsed_args: argparse.Namespace | None = None, **_kwargs: object) -> list[str]:
    """Robot names for ``--robot`` (and ``csl driver state/call ROBOT``): those alive on
    the command's ``--connect`` endpoint (default the driver's), else
    :data:`DEFAULT_ROBOT`."""
    endpoint = getattr(parsed_args, "connect", None) or DRIVER_ENDPOINT
    names = live_robots(endpoint, LIVE_QUERY_S) or [DEFAULT_ROBOT]
    return [n for n in names if n.startswith(prefix)]


def description_ids(path: Path) -> list[str]:
    """The description ids of the library database at ``path``, in the order they were
    added; [] when it is missing or unreadable. Read-only through SQLite's URI, so that
    completing never creates, upgrades or locks a library; the table is
    ``learner/library/store.py``'s ``descriptions``."""
    if not path.is_file():
        return []
    try:
        with closing(sqlite3.connect(f"{path.resolve().as_uri()}?mode=ro", uri=True, timeout=0.2)) as db:
            return [row[0] for row in db.execute("SELECT id FROM descriptions ORDER BY seq")]
    except sqlite3.Error:
        return []


def completed_library(parsed_args: argparse.Namespace | None) -> Path | None:
    """The library ``csl library`` would read (``--db``, else the robot's while it
    exists, else the last demo's: csl_cli/library_choice.py), without saying so."""
    from executive import defaults

    given = getattr(parsed_args, "db", None)
    if given is not None:
        return Path(given).expanduser()
    if defaults.library_db().exists():
        return defaults.library_db()
    from csl_cli.library_choice import last_demo

    return last_demo().library


def complete_library_id(prefix: str, parsed_args: argparse.Namespace | None = None,
                        **_kwargs: object) -> list[str]:
    """Description ids for ``csl library show ID``, from the library it would read."""
    path = completed_library(parsed_args)
    return [] if path is None else [i for i in description_ids(path) if i.startswith(prefix)]
