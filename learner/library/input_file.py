"""Opening a file a person named for reading, refusing what is not a regular file.

``open(path).read()`` waits for ever on a FIFO with no writer and reads ``/dev/zero``
until memory runs out, and a name longer than the system allows is an ``OSError``
that no reader expected. Every such case here is one :class:`NotAFile` line, so the
library file and the episode log (``executive/episode_log.py``) refuse them alike.
"""

from __future__ import annotations

import io
import os
import stat
from pathlib import Path


class NotAFile(ValueError):
    """``path`` cannot be read as a file: the message says why, naming the path."""


def open_input(path: Path, what: str) -> io.BufferedReader:
    """``path`` opened for reading in binary, when it is a regular file; else
    :class:`NotAFile` naming ``path`` and ``what`` it was to be ("episode log").

    Opened without blocking (a FIFO's open would wait for a writer) and checked on
    the open descriptor, so the file checked is the file read.
    """
    try:
        fd = os.open(path, os.O_RDONLY | os.O_NONBLOCK)
    except FileNotFoundError:
        raise NotAFile(f"{path}: {what} not found") from None
    except OSError as exc:
        raise NotAFile(f"{path}: cannot open the {what}: {exc.strerror}") from None
    mode = os.fstat(fd).st_mode
    if not stat.S_ISREG(mode):
        os.close(fd)
        kind = "a folder" if stat.S_ISDIR(mode) else "a device or a pipe"
        raise NotAFile(f"{path}: is {kind}, not {_a(what)}")
    return os.fdopen(fd, "rb")


def read_input(stream: io.BufferedReader, path: Path, what: str, limit: int | None = None) -> bytes:
    """The rest of ``stream`` (from :func:`open_input`); :class:`NotAFile` when it holds
    more than ``limit`` bytes (read no further than one byte past it) or the read fails."""
    try:
        data = stream.read() if limit is None else stream.read(limit + 1)
    except OSError as exc:
        raise NotAFile(f"{path}: cannot read the {what}: {exc.strerror}") from None
    if limit is not None and len(data) > limit:
        raise NotAFile(f"{path}: more than {limit:,} bytes, too large for {_a(what)}")
    return data


def _a(noun: str) -> str:
    return f"{'an' if noun[:1] in 'aeiou' else 'a'} {noun}"
