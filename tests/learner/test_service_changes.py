"""Deltas: a client holding version v gets only what changed since v, and what it
builds from them is the library the service serves."""

from __future__ import annotations

import dataclasses
from pathlib import Path

import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from learner.description import Descriptions
from learner.library.format import write_library_json
from learner.service import LocalLearner
from learner.service import protocol
from learner.service.interface import LibraryChanges
from tests.learner.fixtures import P, desc, four_objects
from tests.learner.test_service_zenoh import MUG, ServiceProcess, robot
from tests.zenoh_rpc.support import free_endpoint

JAR = desc("jar", "Front-Wrap", ("Width-Degree-1°", P(24, 0), 12))


def test_changes_since_a_version_are_the_descriptions_learned_after_it(tmp_path: Path) -> None:
    with LocalLearner(tmp_path / "lib.sqlite", seed_library=four_objects()) as learner:
        assert learner.changes(1) == LibraryChanges(1, 4, ())  # nothing new since the seed
        learner.learn(MUG)
        learner.learn(JAR)
        learner.learn(MUG)  # stored as mug#2
        assert learner.changes(3) == LibraryChanges(4, 6, (dataclasses.replace(MUG, object_id="mug#2"),))
        assert learner.changes(1).start == 4 and [d.object_id for d in learner.changes(1).added] == [
            "mug", "jar", "mug#2"]


@pytest.mark.parametrize("since", [0, 5, 99])
def test_a_version_it_cannot_account_for_gets_the_whole_library(tmp_path: Path, since: int) -> None:
    path = tmp_path / "lib.sqlite"
    with LocalLearner(path, seed_library=four_objects()) as learner:
        learner.learn(MUG)  # version 2
    with LocalLearner(path) as reopened:  # opened at version 2: 0 is from before, 5 and 99 not yet
        learner_now = reopened.library()
        assert reopened.changes(since) == LibraryChanges(2, 0, learner_now.descriptions)
        assert reopened.changes(2) == LibraryChanges(2, 5, ())  # the version it opened at is known


@pytest.mark.slow
@settings(max_examples=25, deadline=None)
@given(st.lists(st.sampled_from(["mug", "jar"]), max_size=6), st.data())
def test_held_descriptions_plus_changes_are_the_library(tmp_path_factory: pytest.TempPathFactory,
                                                        learned: list[str], data: st.DataObject) -> None:
    path = tmp_path_factory.mktemp("changes") / "lib.sqlite"
    with LocalLearner(path, seed_library=four_objects()) as learner:
        held = {learner.version(): learner.library()}
        for name in learned:
            learner.learn(MUG if name == "mug" else JAR)
            held[learner.version()] = learner.library()
        since = data.draw(st.sampled_from(sorted(held)))
        changes = learner.changes(since)
        rebuilt = tuple(held[since].descriptions[:changes.start]) + tuple(changes.added)
        assert changes.version == learner.version() and rebuilt == tuple(learner.library().descriptions)
        assert len(changes.added) == len(learned) - (since - 1)  # only the change travels


def test_a_changes_reply_survives_the_wire() -> None:
    changes = LibraryChanges(7, 4, (MUG, JAR))
    assert protocol.decode_changes_reply(protocol.encode_changes_reply(changes)) == changes
    assert protocol.decode_changes_request(protocol.encode_changes_request(3)) == 3
    with pytest.raises(protocol.ProtocolError, match="since: must be a non-negative integer"):
        protocol.decode_changes_request(b'{"v": 1, "since": -1}')


@pytest.mark.zenoh
def test_a_robot_fetches_the_library_once_then_only_what_others_learned(tmp_path: Path) -> None:
    seed = tmp_path / "seed.json"
    write_library_json(seed, four_objects())
    service = ServiceProcess(tmp_path / "lib.sqlite", free_endpoint(), seed)
    try:
        service.ready()
        with robot(service) as r1, robot(service) as r2:
            first = r2.library()
            assert first.version == 1 and first.descriptions == tuple(four_objects())
            assert r2.library() is first  # nothing changed: the snapshot held

            r1.learn(MUG)
            r1.learn(JAR)
            assert r2.changes(1) == LibraryChanges(3, 4, (MUG, JAR))
            after = r2.library()
            assert after.version == 3 and after.descriptions == (*four_objects(), MUG, JAR)
            # extended, not refetched: the held descriptions are the new snapshot's prefix
            assert isinstance(after.descriptions, Descriptions) and after.descriptions.extends(first.descriptions)
            assert r2.changes(0).start == 0  # a version from before the service opened: everything
    finally:
        service.close()
