"""Which library a command reads when it is not told: the robot's, else the last demo's.

``csl run`` learns into the robot's library, ``$CSL_HOME/library.sqlite``, kept from run
to run. ``csl demo`` is a try-out: it makes its library anew in its ``--out`` folder
(``csl-out/library.sqlite``) each time, so that a seed gives the same demo whatever ran
before and a demo never writes over what a robot learned. Someone who has just run the
demo and asks ``csl library show`` (or ``stats``, ``export``, ``check``, ``backup``, or
``csl tree``) means the demo's library when no robot has learned anything yet; once one
has, they mean the robot's. So a command that reads a library and is given none reads
the robot's library when it exists, else the last demo's (the history file,
``$CSL_HOME/history.jsonl``, names it), saying so in one line on standard error. Commands
that write a library (``import``, ``restore``, ``csl learner serve``) write the robot's.
"""

from __future__ import annotations

import sys
from dataclasses import dataclass
from pathlib import Path

from csl_cli.args import library_path
from executive import defaults


@dataclass(frozen=True)
class LastDemo:
    """The library of the last ``csl demo`` the history holds (None: no demo ran, or
    the history could not be read: ``problem`` says why)."""

    library: Path | None
    problem: str | None = None


def last_demo() -> LastDemo:
    """The last demo's library as the history file records it (a path made absolute
    when it ran, so it is found from any folder)."""
    from reporting.history import default_history, read_history  # the history reader pulls numpy: not for --help

    history = default_history()
    if not history.exists():
        return LastDemo(None)
    try:
        runs = read_history(history)
    except ValueError as exc:
        return LastDemo(None, str(exc))
    demos = [r.library for r in runs if r.command == "demo" and r.library is not None]
    return LastDemo(Path(demos[-1]) if demos else None)


def library_to_read(given: Path | None, option: str, command: str) -> Path | None:
    """The library ``command`` reads: ``given`` (checked as ``option``), else the
    robot's when it exists, else the last demo's when it still exists (said on standard
    error), else None: the caller says what is missing (:func:`no_library`)."""
    if given is not None:
        return library_path(given, option)
    robot = defaults.library_db()
    if robot.exists():
        return robot
    demo = last_demo().library
    if demo is not None and demo.is_file():
        print(f"{command}: reading the last demo's library, {demo} (no robot library at {robot} yet: "
              f"'csl run' starts it; {option} to choose)", file=sys.stderr)
        return demo
    return None


def no_library(option: str) -> ValueError:
    """The one-line error when there is no library to read: where the robot's would be,
    and what became of the last demo's."""
    robot = defaults.library_db()
    found = last_demo()
    if found.problem is not None:
        demo = f"the last demo's could not be looked up ({found.problem})"
    elif found.library is None:
        demo = "no demo has run ('csl demo' keeps its own in its --out folder)"
    else:
        demo = f"the last demo's, {found.library}, is gone"
    return ValueError(f"{robot}: no library database there ('csl run' or 'csl library import' starts it), "
                      f"and {demo}; pass {option} to choose one")


def demo_library_line(path: Path) -> str:
    """What ``csl demo`` says of its library: where it is, and which commands read it."""
    robot = defaults.library_db()
    if robot.exists():
        return (f"library: {path} (this demo's own; 'csl library --db {path} show' reads it, 'csl library show' "
                f"your robot's, {robot})")
    return (f"library: {path} (this demo's own; 'csl library show' and 'csl tree' read the last demo's until "
            f"'csl run' starts your robot's, {robot})")
