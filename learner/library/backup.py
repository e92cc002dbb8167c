"""A library store that is checked, and can be backed up and restored while it serves:
SQLite's own integrity checks and its online backup API, not a copy of the file.

Copying a live SQLite file in WAL mode can catch it between a write to the log and the
checkpoint, and copying the main file alone loses what the log holds; the backup API
copies a consistent snapshot page by page while writers go on. A damaged store must be
refused rather than served (it may answer most reads and take new writes for a long
time before the damaged page is read), so every opening runs SQLite's quick check.
"""

from __future__ import annotations

import logging
import os
import sqlite3
import threading
import time
from collections.abc import Callable
from pathlib import Path

log = logging.getLogger(__name__)

RESTORE_HINT = "restore a backup (csl library restore --db {path} BACKUP) or recover what is left with sqlite3's .recover"


def problems(db: sqlite3.Connection, *, full: bool = False) -> list[str]:
    """What SQLite's check finds wrong with ``db`` (empty: nothing). The quick check
    reads every page and checks the b-trees' structure (linear in the file's size);
    ``full`` also checks that every index matches its table."""
    rows = db.execute("PRAGMA integrity_check" if full else "PRAGMA quick_check").fetchall()
    lines = [line for (text,) in rows for line in str(text).splitlines()]
    if lines == ["ok"]:
        return []
    return [line for line in lines if line and not line.startswith("*** in database")]


def damage_line(path: Path, found: list[str]) -> str:
    """The one line a damaged store is refused with: the file, SQLite's first finding
    (and how many more), and how to recover."""
    more = f" (and {len(found) - 1} more)" if len(found) > 1 else ""
    return (f"{path}: the library database is damaged (SQLite's check: {found[0]}{more}); "
            + RESTORE_HINT.format(path=path))


def check_file(path: Path, *, full: bool = True) -> list[str]:
    """SQLite's check of the library file at ``path`` (what is wrong; empty: nothing)."""
    db = sqlite3.connect(path)
    try:
        return problems(db, full=full)
    except sqlite3.DatabaseError as exc:
        return [(str(exc).strip().splitlines() or ["not a database"])[0]]
    finally:
        db.close()


def backup(source: Path, target: Path) -> None:
    """Copy the library at ``source`` to ``target`` while it may be serving: a
    consistent snapshot through SQLite's backup API, written beside ``target``, checked,
    and renamed over it, so a crash or a damaged copy never replaces a good backup."""
    partial = target.with_name(f".{target.name}.partial")
    partial.unlink(missing_ok=True)
    src = sqlite3.connect(source, timeout=10.0)
    try:
        dst = sqlite3.connect(partial)
        try:
            src.backup(dst)
            copied = problems(dst, full=True)  # damage in the source is copied page for page: checked once, here
        finally:
            dst.close()
    finally:
        src.close()
    if copied:
        partial.unlink(missing_ok=True)
        raise ValueError(f"{target}: the copy of {source} did not check out ({copied[0]}); the previous backup "
                         "is kept")
    os.replace(partial, target)


def restore(backup_file: Path, target: Path) -> Path | None:
    """Make the library at ``target`` the backup's copy. The backup is checked first
    (a damaged backup is refused and nothing changes). The copy goes in through SQLite's
    backup API, so the store's write-ahead log stays consistent with it; a target too
    damaged to be written that way is moved aside (its name and ``.damaged-<time>``,
    returned) and a new file takes its place. Stop whatever serves the store first."""
    found = check_file(backup_file)
    if found:
        raise ValueError(f"{backup_file}: the backup is damaged ({found[0]}): nothing was restored")
    src = sqlite3.connect(backup_file)
    try:
        try:
            _copy_into(src, target)
            return None
        except sqlite3.DatabaseError:
            aside = target.with_name(f"{target.name}.damaged-{time.strftime('%Y%m%dT%H%M%S')}")
            for suffix in ("", "-wal", "-shm"):
                part = Path(f"{target}{suffix}")
                if part.exists():
                    os.replace(part, Path(f"{aside}{suffix}"))
            _copy_into(src, target)
            return aside
    finally:
        src.close()


def _copy_into(src: sqlite3.Connection, target: Path) -> None:
    dst = sqlite3.connect(target, timeout=10.0)
    try:
        src.backup(dst)
        found = problems(dst)
        if found:
            raise sqlite3.DatabaseError(found[0])
    finally:
        dst.close()


def keep_backed_up(source: Path, target: Path, every_s: float, stop: threading.Event,
                   said: Callable[[str], None] = log.warning) -> threading.Thread:
    """Back ``source`` up to ``target`` now, every ``every_s`` seconds, and once more when
    ``stop`` is set, on a thread of its own (returned, started; join it after setting
    ``stop``). A failed backup is one line through ``said`` and never stops the service:
    the previous backup stays whole (:func:`backup`)."""
    def one() -> None:
        try:
            backup(source, target)
        except (OSError, ValueError, sqlite3.Error) as exc:
            said(f"library backup to {target} failed: {str(exc).splitlines()[0] if str(exc) else type(exc).__name__}")

    def run() -> None:
        one()
        while not stop.wait(every_s):
            one()
        one()

    thread = threading.Thread(target=run, name=f"backup-{target.name}", daemon=True)
    thread.start()
    return thread
