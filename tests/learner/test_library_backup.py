"""A damaged library is refused, not served, and a backup brings it back
(learner/library/backup.py; ``csl library check | backup | restore``).

The damage is made as a disk makes it: bytes of one page of a sound store overwritten,
on a page SQLite does not need to open the file, so that every ordinary read may still
work and only a check finds it (the kind of copy that used to be served)."""

from __future__ import annotations

import sqlite3
from pathlib import Path

import pytest

from csl_cli.main import main
from executive import defaults
from learner.library.backup import backup, check_file, restore
from learner.library.store import LibraryStore, load_library
from learner.library.synthetic import synthetic_library
from robot_profile import load_profile

PAGE = 4096


def _sound(path: Path, count: int = 150) -> list[str]:
    """A store of ``count`` descriptions, its log checkpointed into the file; their ids."""
    knowledge = load_profile().knowledge()
    descriptions = synthetic_library(knowledge, count, 1, base=load_library(defaults.EXAMPLE_LIBRARY))
    with LibraryStore(path) as store:
        store.add(descriptions)
    db = sqlite3.connect(path)
    db.execute("PRAGMA wal_checkpoint(TRUNCATE)")
    db.close()
    return sorted(d.object_id for d in descriptions)


def _damaged(sound: Path, out: Path) -> Path:
    """A copy of ``sound`` with one page's cell pointers overwritten, chosen so that the
    file still opens and its schema still reads (the damage lies deeper)."""
    data = sound.read_bytes()
    for page in range(2, len(data) // PAGE):
        copy = bytearray(data)
        for i in range(12, 40):
            copy[page * PAGE + i] ^= 0x5A
        out.write_bytes(bytes(copy))
        db = sqlite3.connect(out)
        try:
            db.execute("SELECT count(*) FROM sqlite_master").fetchone()
            damaged = db.execute("PRAGMA quick_check").fetchone()[0] != "ok"
        except sqlite3.DatabaseError:
            damaged = False  # too damaged to open: the store already refused those
        finally:
            db.close()
        if damaged:
            return out
    raise AssertionError("no page gave a copy that opens yet fails the check")


def _ids(path: Path) -> list[str]:
    with LibraryStore(path) as store:
        return sorted(d.object_id for d in store.descriptions())


def test_a_store_damaged_where_reads_still_work_is_refused_in_one_line(tmp_path: Path) -> None:
    _sound(tmp_path / "lib.sqlite")
    damaged = _damaged(tmp_path / "lib.sqlite", tmp_path / "damaged.sqlite")
    with pytest.raises(ValueError) as refused:
        LibraryStore(damaged)
    line = str(refused.value)
    assert "\n" not in line
    assert line.startswith(f"{damaged}: the library database is damaged (SQLite's check: ")
    assert line.endswith(f"restore a backup (csl library restore --db {damaged} BACKUP) or recover what is "
                         "left with sqlite3's .recover")


def test_csl_library_check_says_sound_or_damaged(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    sound = tmp_path / "lib.sqlite"
    _sound(sound, 20)
    assert main(["library", "--db", str(sound), "check"]) == 0
    assert capsys.readouterr().out == f"{sound}: ok (20 descriptions)\n"
    _sound(tmp_path / "big.sqlite")
    damaged = _damaged(tmp_path / "big.sqlite", tmp_path / "damaged.sqlite")
    assert main(["library", "--db", str(damaged), "check"]) == 1
    out = capsys.readouterr().out.splitlines()
    assert out[0].startswith(f"{damaged}: damaged: ") and out[-1].startswith("restore a backup")


def test_a_backup_taken_while_the_store_is_written_restores_every_description(tmp_path: Path) -> None:
    live, copy = tmp_path / "lib.sqlite", tmp_path / "backup.sqlite"
    ids = _sound(live, 30)
    writer = sqlite3.connect(live)  # a service's connection, mid-transaction on the live store
    writer.execute("BEGIN IMMEDIATE")
    writer.execute("INSERT INTO meta VALUES ('note', 'written while the backup ran')")
    backup(live, copy)
    writer.rollback()
    writer.close()
    assert check_file(copy) == [] and _ids(copy) == ids
    damaged = _damaged(live, tmp_path / "damaged.sqlite")
    assert restore(copy, damaged) is None  # a file that opens is written over in place, nothing moved aside
    assert _ids(damaged) == ids and check_file(damaged) == []


def test_restoring_over_an_unreadable_file_moves_it_aside(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    live, copy = tmp_path / "lib.sqlite", tmp_path / "backup.sqlite"
    ids = _sound(live, 10)
    assert main(["library", "--db", str(live), "backup", str(copy)]) == 0
    live.write_bytes(b"this is not a database at all" * 200)
    assert main(["library", "--db", str(live), "restore", str(copy)]) == 0
    out = capsys.readouterr().out
    aside = next(tmp_path.glob("lib.sqlite.damaged-*"))
    assert f"moved aside to {aside}" in out and aside.read_bytes().startswith(b"this is not")
    assert _ids(live) == ids


def test_a_damaged_backup_is_refused_and_nothing_changes(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    live = tmp_path / "lib.sqlite"
    ids = _sound(live, 10)
    _sound(tmp_path / "big.sqlite")
    bad = _damaged(tmp_path / "big.sqlite", tmp_path / "bad-backup.sqlite")
    assert main(["library", "--db", str(live), "restore", str(bad)]) == 2
    err = capsys.readouterr().err
    assert f"{bad}: the backup is damaged (" in err and err.count("\n") == 1
    assert _ids(live) == ids
