"""What a run makes before its first episode, taken back if it fails there.

``csl demo`` and ``csl run`` make their ``--out`` folder (and, for the demo, a library
in it) and open their ``--record`` file while they set up: the learner, the driver,
the camera check, the live view. A start that fails there (a library that is not one,
no driver, Ctrl-C while waiting for a viewer) used to leave an empty folder, an
empty ``episode.jsonl`` and an empty recording behind, which look like a run that
found nothing. The episode has started once its log holds its first event (the log
is made then: ``executive/episode_log.py``); until then, whatever the run made that
was not there before is removed again, and what was there is left as it was.
"""

from __future__ import annotations

import contextlib
import shutil
from collections.abc import Iterable, Iterator
from contextlib import contextmanager
from pathlib import Path

_Stamp = tuple[int, int, int]  # inode, modification time (ns), size: "written since" without reading the file


@contextmanager
def taken_back_unless_started(folder: Path, log: Path, files: Iterable[Path] = ()) -> Iterator[None]:
    """Run the body; if it raises before ``log`` is written, remove the entries of
    ``folder`` that are new since it began, ``folder`` itself (and the parents made
    for it) if they are new and now empty, and each of ``files`` that is new."""
    files = [f for f in files if not _exists(f)]
    made_from = _first_missing(folder)
    before = _entries(folder)
    log_before = _stamp(log)
    try:
        yield
    except BaseException:
        if _stamp(log) == log_before:  # the episode never began: nothing of it is worth keeping
            _take_back(folder, before, made_from, files)
        raise


def _take_back(folder: Path, before: dict[str, _Stamp], made_from: Path | None, files: list[Path]) -> None:
    """Remove what is new, as far as it can be: the error being raised is the one to
    report, not a file that could not be removed."""
    for path in files:
        with contextlib.suppress(OSError):  # never made (a name too long...)
            path.unlink(missing_ok=True)
    for name in _entries(folder).keys() - before.keys():
        entry = folder / name
        if entry.is_dir() and not entry.is_symlink():
            shutil.rmtree(entry, ignore_errors=True)
        else:
            with contextlib.suppress(OSError):
                entry.unlink(missing_ok=True)
    if made_from is None:
        return
    for made in (folder, *folder.parents):  # the folder, then each parent made for it, while empty
        try:
            made.rmdir()
        except OSError:
            return
        if made == made_from:
            return


def _first_missing(folder: Path) -> Path | None:
    """The outermost of ``folder`` and its parents that does not exist yet (what
    ``mkdir(parents=True)`` will make), or None when ``folder`` exists."""
    missing = None
    for path in (folder, *folder.parents):
        if _exists(path):
            break
        missing = path
    return missing


def _entries(folder: Path) -> dict[str, _Stamp]:
    try:
        return {entry.name: _stamp(entry) or (0, 0, 0) for entry in folder.iterdir()}
    except OSError:  # not there (yet), or not a folder: the run's own check says so
        return {}


def _stamp(path: Path) -> _Stamp | None:
    try:
        status = path.lstat()
    except OSError:
        return None
    return status.st_ino, status.st_mtime_ns, status.st_size


def _exists(path: Path) -> bool:
    return _stamp(path) is not None
