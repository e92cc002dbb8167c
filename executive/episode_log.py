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
from executive.narration import tell
from learner.library.input_file import open_input, read_input
from learner.library.json_text import NotJson, parse_json


class EpisodeLog:
    """Collects events in memory and, given a path, writes them to a JSON-lines file;
    listeners (a recording) get each event as it is logged, and Python's ``logging``
    tells it (``csl -v``, :mod:`executive.narration`).

    The file is made at the first event, not before: a run that fails while it sets up
    leaves no empty log, and the log of the run before it as it was."""

    def __init__(self, path: str | Path | None = None) -> None:
        self.events: list[dict[str, object]] = []
        self.tick = 0
        self.listeners: list[Callable[[dict[str, object]], None]] = []
        self._path = None if path is None else Path(path)
        self._file: IO[str] | None = None

    def event(self, kind: Event | str, **data: object) -> None:
        """Log one event; a kind outside :class:`~behaviours.events.Event` is a bug in
        the caller, refused before anything is written."""
        try:
            kind = Event(kind)
        except ValueError:
            raise ValueError(f"unknown episode event kind {kind!r}") from None
        record = _json_safe({"tick": self.tick, "event": kind.value, **data})
        self.events.append(record)
        if self._file is None and self._path is not None:
            self._path.parent.mkdir(parents=True, exist_ok=True)
            self._file = self._path.open("w", encoding="utf-8")
        if self._file is not None:
            self._file.write(json.dumps(record, ensure_ascii=False, default=str, allow_nan=False) + "\n")
            self._file.flush()  # followable while the episode runs (tail -f), complete if it dies
        tell(record)
        for listener in self.listeners:
            listener(record)

    def close(self) -> None:
        self._path = None  # an event after the close is kept in memory only, as before
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


class IsRecording(ValueError):
    """The file is a ``--record`` MCAP recording, not an ``episode.jsonl``: the recording
    package reads it (:func:`recording.reader.read_events`), which the
    executive, below it, does not import."""


def read_log(path: str | Path) -> list[dict[str, object]]:
    """Read an ``episode.jsonl`` back (for replay and analysis); :class:`IsRecording`
    for an MCAP recording."""
    path = Path(path)
    data = _read_log_file(path)
    if data is None:
        raise IsRecording(f"{path}: an MCAP recording, not an episode.jsonl")
    try:
        text = data.decode("utf-8")
    except UnicodeDecodeError:
        raise ValueError(f"{path}: not an episode log (not text)") from None
    lines = text.split("\n")  # not splitlines: a string may hold U+2028 or U+0085 as it is (ensure_ascii=False)
    if lines[-1] == "":
        lines.pop()  # after the last line's newline
    events = []
    for n, line in enumerate(lines, 1):
        try:
            events.append(parse_json(line))
        except NotJson as exc:
            raise ValueError(f"{path}:{n}: not a JSON event: {exc}") from None
    return events


MAX_LOG_BYTES = 64 * 2**20
"""The largest episode.jsonl read back: a seven-object episode logs 20-80 kB, so this
is hundreds of episodes, and a file beyond it is not one episode's log."""


def _read_log_file(path: Path) -> bytes | None:
    """The bytes of the episode log at ``path``, or None when it is an MCAP recording
    (read by the mcap library instead).

    Only a regular file is read (a FIFO or ``/dev/zero`` is refused instead of
    waiting for a writer or reading for ever), and an episode.jsonl only up to
    :data:`MAX_LOG_BYTES`.
    """
    with open_input(path, "episode log") as stream:
        if stream.peek(len(_MCAP_MAGIC))[:len(_MCAP_MAGIC)] == _MCAP_MAGIC:
            return None
        return read_input(stream, path, "episode log", MAX_LOG_BYTES)


_MCAP_MAGIC = b"\x89MCAP"  # how every MCAP file begins
