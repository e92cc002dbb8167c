"""The episode log inside a recording: the ``/csl/events`` channel read back with the
``mcap`` library's own reader, for ``csl log`` (which reads an ``episode.jsonl`` too,
through :func:`read_events`). No Foxglove import."""

from __future__ import annotations

import struct
from pathlib import Path

from mcap.exceptions import McapError
from mcap.reader import make_reader
from zstandard import ZstdError

from executive.episode_log import IsRecording, read_log
from recording.topics import EVENTS
from learner.library.json_text import NotJson, parse_json


def read_events(path: Path) -> list[dict[str, object]]:
    """An episode's events, from its ``episode.jsonl`` or its ``--record`` MCAP file."""
    try:
        return read_log(path)
    except IsRecording:
        return read_recorded_events(path)


def read_recorded_events(path: Path) -> list[dict[str, object]]:
    """The events of a recording in the order they were logged; a file that is not a
    recording of ours is a one-line error."""
    events: list[dict[str, object]] = []
    try:
        with path.open("rb") as f:
            for _, channel, message in make_reader(f).iter_messages(topics=[EVENTS.name], log_time_order=True):
                try:
                    events.append(parse_json(message.data))
                except NotJson:
                    raise ValueError(f"{path}: message {message.sequence} on {channel.topic} is not a JSON "
                                     "event") from None
    except (McapError, EOFError, ValueError, struct.error, OSError, OverflowError, KeyError, IndexError,
            ZstdError, RuntimeError, MemoryError) as exc:  # a file cut short or damaged: the mcap reader and
        # its decompressors (zstd, lz4) say so in their own ways
        if str(exc).startswith(str(path)):
            raise
        reason = (str(exc).strip().splitlines() or [type(exc).__name__])[0]
        raise ValueError(f"{path}: not a readable MCAP recording ({reason})") from None
    if not events:
        raise ValueError(f"{path}: the recording has no {EVENTS.name} channel (not recorded by csl --record?)")
    return events
