"""Completion of robot names and library description ids, the completers called as
argcomplete calls them (``prefix``, ``parsed_args``), no shell involved."""

from __future__ import annotations

import argparse
from pathlib import Path

import pytest

import csl_cli.completion as completion
from csl_cli.completion import complete_library_id, complete_robot, description_ids
from executive import defaults
from learner.library.format import read_library_json
from learner.library.store import LibraryStore
from reporting.history import append_run, default_history, episode_run
from tests.zenoh_rpc.support import free_endpoint
from zenoh_rpc.config import open_session

EXAMPLE = read_library_json(defaults.EXAMPLE_LIBRARY)


@pytest.mark.zenoh
def test_robot_names_are_the_drivers_alive_on_the_endpoint(monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.setattr(completion, "LIVE_QUERY_S", 10.0)  # a loaded machine: the rule, not the bound
    endpoint = free_endpoint()
    with open_session(listen=[endpoint]) as drivers:
        tokens = [drivers.liveliness().declare_token(f"hero/{name}/alive") for name in ("r7", "arm-2")]
        other = drivers.liveliness().declare_token("library/shared/alive")  # a learner: not a robot
        asked = argparse.Namespace(connect=endpoint)
        assert complete_robot("", asked) == ["arm-2", "r7"]
        assert complete_robot("r", asked) == ["r7"]
        for token in [*tokens, other]:
            token.undeclare()


@pytest.mark.zenoh
def test_with_no_driver_answering_the_default_robot_is_offered() -> None:
    asked = argparse.Namespace(connect=free_endpoint())  # nothing listens there
    assert complete_robot("", asked) == ["r1"]
    assert complete_robot("x", asked) == []


def test_library_ids_from_the_db_asked_for(tmp_path: Path) -> None:
    db = tmp_path / "lib.sqlite"
    with LibraryStore(db) as store:
        store.add(EXAMPLE[:3])
    ids = [d.object_id for d in EXAMPLE[:3]]
    assert complete_library_id("", argparse.Namespace(db=db)) == ids
    first = ids[0][:3]
    assert complete_library_id(first, argparse.Namespace(db=db)) == [i for i in ids if i.startswith(first)]


def test_library_ids_from_the_robots_library_else_the_last_demos(tmp_path: Path) -> None:
    # CSL_HOME is a fresh folder per test (tests/conftest.py): no robot library yet
    assert complete_library_id("", argparse.Namespace(db=None)) == []
    assert not defaults.library_db().exists()  # completing created nothing
    demo = tmp_path / "demo.sqlite"
    with LibraryStore(demo) as store:
        store.add(EXAMPLE[:2])
    append_run(default_history(), episode_run(command="demo", robot="r1", world="lab", seed=0, criterion="c",
                                              outcomes=[], robot_s=0.0, events=[], library_size=2, library=demo))
    assert complete_library_id("", argparse.Namespace(db=None)) == [d.object_id for d in EXAMPLE[:2]]
    with LibraryStore(defaults.library_db()) as store:
        store.add(EXAMPLE[4:5])
    assert complete_library_id("", argparse.Namespace(db=None)) == [EXAMPLE[4].object_id]


def test_an_unreadable_library_completes_nothing(tmp_path: Path) -> None:
    junk = tmp_path / "junk.sqlite"
    junk.write_bytes(b"not a database at all" * 10)
    assert description_ids(junk) == [] and description_ids(tmp_path / "missing.sqlite") == []
    assert not (tmp_path / "missing.sqlite").exists()
