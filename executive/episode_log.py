"""The episode log: one JSON line per event, tagged with the tick it happened in.

Events are what a person replaying or analysing a run needs: objects located, tests
chosen and why (gain, move and sensing cost), values measured, branches followed,
recoveries, grasps, what was learned. No wall-clock times, so two runs of the same seed
give the same log.
"""

from __future__ import annotations

import json
import math
from collections.abc import Callable
from pathlib import Path
from typing import IO

from behaviours.events import Event


class EpisodeLog:
    """Collects events in memory and, given a path, appends them to a JSON-lines file;
    listeners (a recording) get each event as it is logged."""

    def __init__(self, path: str | Path | None = None) -> None:
        self.events: list[dict[str, object]] = []
        self.tick = 0
        self.listeners: list[Callable[[dict[str, object]], None]] = []
        self._file: IO[str] | None = None
        if path is not None:
            path = Path(path)
            path.parent.mkdir(parents=True, exist_ok=True)
            self._file = path.open("w", encoding="utf-8")

    def event(self, kind: Event | str, **data: object) -> None:
        """Log one event; a kind outside :class:`~behaviours.events.Event` is a bug in
        the caller, refused before anything is written."""
        try:
            kind = Event(kind)
        except ValueError:
            raise ValueError(f"unknown episode event kind {kind!r}") from None
        record = _json_safe({"tick": self.tick, "event": kind.value, **data})
        self.events.append(record)
        if self._file is not None:
            self._file.write(json.dumps(record, ensure_ascii=False, default=str, allow_nan=False) + "\n")
            self._file.flush()  # followable while the episode runs (tail -f), complete if it dies
        for listener in self.listeners:
            listener(record)

    def close(self) -> None:
        if self._file is not None:
            self._file.close()
            self._file = None


def _json_safe(value: object) -> object:
    """Strict JSON: an infinite or undefined number (a move with no path) becomes null."""
    if isinstance(value, float) and not math.isfinite(value):
        return None
    if isinstance(value, dict):
        return {k: _json_safe(v) for k, v in value.items()}
    if isinstance(value, (list, tuple)):
        return [_json_safe(v) for v in value]
    return value


def read_log(path: str | Path) -> list[dict[str, object]]:
    """Read an episode log back (for replay and analysis): an ``episode.jsonl``, or the
    events channel of a ``--record`` MCAP file."""
    path = Path(path)
    try:
        if _is_mcap(path):
            from executive.recording.reader import read_recorded_events  # the mcap library: only for a recording

            return read_recorded_events(path)
        text = path.read_text(encoding="utf-8")
    except FileNotFoundError:
        raise ValueError(f"{path}: episode log not found") from None
    except IsADirectoryError:
        raise ValueError(f"{path}: is a folder, not an episode log") from None
    except UnicodeDecodeError:
        raise ValueError(f"{path}: not an episode log (not text)") from None
    events = []
    for n, line in enumerate(text.splitlines(), 1):
        try:
            events.append(json.loads(line))
        except json.JSONDecodeError as exc:
            raise ValueError(f"{path}:{n}: not a JSON event: {exc.msg}") from None
    return events


def _is_mcap(path: Path) -> bool:
    with path.open("rb") as f:
        return f.read(len(_MCAP_MAGIC)) == _MCAP_MAGIC


_MCAP_MAGIC = b"\x89MCAP"  # how every MCAP file begins
