"""The learning history: one row per ``csl demo`` or ``csl run`` episode, appended to a
JSON-lines file, so that what the library learned shows over runs as the paper shows
it (docs/method.md): robot time and errors per object falling as descriptions
accumulate. ``csl library history`` reads it back as a table and the learning curve.

The episode log (``episode.jsonl``) is replaced by every run; this file only grows.
"""

from __future__ import annotations

import json
import math
from collections.abc import Mapping, Sequence
from dataclasses import asdict, dataclass
from datetime import datetime, timezone
from pathlib import Path

from executive import defaults
from executive.exit_status import HANDLED_OUTCOMES

HISTORY_NAME = "history.jsonl"


def default_history() -> Path:
    """``$CSL_HOME/history.jsonl``, beside the user's default library."""
    return defaults.library_db().with_name(HISTORY_NAME)


@dataclass(frozen=True)
class Run:
    """One episode's totals, as the learning curve needs them.

    ``failed`` counts every object not handled (failed, unfinished, or served by a verb
    the robot never answered); ``errors`` counts the grasps the robot executed at a leaf
    that did not hold: each is a wrong prediction the learner had to recover from (a
    grasp tried as a feature is a test, not an error). ``world`` and ``seed`` are the
    simulator's (None for a driver over zenoh); ``library`` is the local library's path
    (None for a learner service over zenoh) and ``library_size`` its descriptions after
    the run."""

    date: str  # ISO 8601, UTC, to the second
    command: str  # demo | run
    robot: str
    world: str | None
    seed: int | None
    criterion: str
    objects: int
    handled: int
    failed: int
    errors: int
    robot_min_per_object: float | None  # None when no object was seen
    library_size: int
    library: str | None


def wrong_grasps(events: Sequence[Mapping[str, object]]) -> int:
    """Grasps executed at a leaf that did not hold (episode-log ``grasp`` events)."""
    return sum(1 for e in events if e.get("event") == "grasp" and e.get("as_feature") is False
               and e.get("success") is False)


def episode_run(*, command: str, robot: str, world: str | None, seed: int | None, criterion: str,
                outcomes: Sequence[str | None], robot_s: float, events: Sequence[Mapping[str, object]],
                library_size: int, library: Path | None, now: datetime | None = None) -> Run:
    """The history row of one episode: ``outcomes`` per object as the exit status judges
    them, ``robot_s`` the robot seconds they took in all (moving, sensing, grasping)."""
    handled = sum(1 for o in outcomes if o in HANDLED_OUTCOMES)
    when = (now or datetime.now(timezone.utc)).astimezone(timezone.utc).replace(microsecond=0)
    return Run(date=when.isoformat(), command=command, robot=robot, world=world, seed=seed, criterion=criterion,
               objects=len(outcomes), handled=handled, failed=len(outcomes) - handled, errors=wrong_grasps(events),
               robot_min_per_object=robot_s / 60.0 / len(outcomes) if outcomes else None,
               library_size=library_size, library=None if library is None else str(library.resolve()))


def append_run(path: Path, run: Run) -> None:
    """Add one row at the end (one ``write`` of one line: two runs appending at once
    do not interleave within a row). The default file's folder, ``$CSL_HOME``, is made
    if missing, as the library's is."""
    path.parent.mkdir(parents=True, exist_ok=True)
    with path.open("a", encoding="utf-8") as f:
        f.write(json.dumps(asdict(run), allow_nan=False) + "\n")


_KINDS: dict[str, tuple[type, ...]] = {
    "date": (str,), "command": (str,), "robot": (str,), "world": (str, type(None)), "seed": (int, type(None)),
    "criterion": (str,), "objects": (int,), "handled": (int,), "failed": (int,), "errors": (int,),
    "robot_min_per_object": (int, float, type(None)), "library_size": (int,), "library": (str, type(None)),
}
"""What each field of a row may hold (the test holds these names equal to Run's)."""


def read_history(path: Path) -> list[Run]:
    """Every row of a history file, oldest first; a missing file or a bad row is a
    ValueError naming the file (and line and field)."""
    try:
        text = path.read_text(encoding="utf-8")
    except FileNotFoundError:
        raise ValueError(f"{path}: no history file there (csl demo and csl run append one row per run)") from None
    except IsADirectoryError:
        raise ValueError(f"{path}: is a folder, not a history file") from None
    except UnicodeDecodeError:
        raise ValueError(f"{path}: not a history file (not text)") from None
    return [_row(path, n, line) for n, line in enumerate(text.splitlines(), 1) if line.strip()]


def _row(path: Path, n: int, line: str) -> Run:
    where = f"{path}:{n}"
    try:
        document = json.loads(line)
    except json.JSONDecodeError as exc:
        raise ValueError(f"{where}: not a JSON row: {exc.msg}") from None
    if not isinstance(document, dict):
        raise ValueError(f"{where}: expected a JSON object, got {type(document).__name__}")
    for name, kinds in _KINDS.items():
        if name not in document:
            raise ValueError(f"{where}: field {name!r} missing")
        value = document[name]
        if isinstance(value, bool) or not isinstance(value, kinds):
            raise ValueError(f"{where}: field {name!r}: unexpected value {value!r}")
        if isinstance(value, (int, float)) and not (math.isfinite(value) and value >= 0):
            raise ValueError(f"{where}: field {name!r}: expected a number >= 0, got {value!r}")
    try:
        datetime.fromisoformat(document["date"])
    except ValueError:
        raise ValueError(f"{where}: field 'date': expected an ISO 8601 time, got {document['date']!r}") from None
    run = Run(**{name: document[name] for name in _KINDS})
    if run.handled + run.failed != run.objects:
        raise ValueError(f"{where}: handled + failed ({run.handled} + {run.failed}) is not objects ({run.objects})")
    return run


@dataclass(frozen=True)
class CurvePoint:
    """One run on the learning curve (runs with no objects have no point)."""

    run: int  # 1 for the oldest row of the history read
    minutes_per_object: float
    errors_per_object: float
    failed_per_object: float


def learning_curve(runs: Sequence[Run]) -> list[CurvePoint]:
    """Cost, errors and failures per object for every run that saw an object."""
    return [CurvePoint(n, run.robot_min_per_object or 0.0, run.errors / run.objects, run.failed / run.objects)
            for n, run in enumerate(runs, 1) if run.objects]
