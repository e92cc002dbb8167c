"""The outbox: learned descriptions wait on the robot while the learner service is
unreachable and are delivered, oldest first and once each, when it comes back."""

from __future__ import annotations

import sqlite3
from contextlib import closing
from dataclasses import replace
from pathlib import Path

import pytest

from learner.description import ObjectDescription
from learner.service import LibrarySnapshot, LocalLearner
from learner.service.interface import LearnerUnavailable
from learner.service.outbox import QUEUED_PREFIX, Outbox, OutboxLearner
from tests.learner.fixtures import P, desc, four_objects, hero

MUG = desc("mug", "Front-Wrap", ("Width-Degree-1°", P(24, 0), 10), ("Front-Hole?", P(6, None), 1))
BAD = desc("huge", "Front-Wrap", ("Width-Degree-1°", P(24, 0), 1e300))


class Flaky:
    """A LocalLearner behind a switch: ``down`` makes every call unreachable;
    ``lose_replies`` stores the learn and then loses its reply, as a service killed
    between its commit and its answer would."""

    def __init__(self, inner: LocalLearner) -> None:
        self.inner = inner
        self.down = False
        self.lose_replies = 0
        self.learn_calls = 0

    def library(self) -> LibrarySnapshot:
        self._reach()
        return self.inner.library()

    def version(self) -> int:
        self._reach()
        return self.inner.version()

    def learn(self, description: ObjectDescription, key: str | None = None) -> str:
        self._reach()
        self.learn_calls += 1
        object_id = self.inner.learn(description, key)
        if self.lose_replies:
            self.lose_replies -= 1
            raise LearnerUnavailable("the reply was lost")
        return object_id

    def close(self) -> None:
        self.inner.close()

    def _reach(self) -> None:
        if self.down:
            raise LearnerUnavailable("no service answered")


@pytest.fixture
def flaky(tmp_path: Path) -> Flaky:
    return Flaky(LocalLearner(tmp_path / "lib.sqlite", seed_library=four_objects(), knowledge=hero()))


def mug(n: int) -> ObjectDescription:
    return replace(MUG, object_id=f"mug-{n}")


def stored_ids(path: Path) -> list[str]:
    with closing(sqlite3.connect(path)) as db:
        return [r[0] for r in db.execute("SELECT id FROM descriptions ORDER BY seq")]


def test_a_reachable_service_gets_the_learn_at_once_and_the_outbox_stays_empty(flaky: Flaky, tmp_path: Path) -> None:
    with OutboxLearner(flaky, Outbox(tmp_path / "outbox.sqlite"), "default") as robot:
        assert robot.learn(MUG) == "mug"
        assert robot.outbox.count("default") == 0
        assert robot.library().descriptions[-1].object_id == "mug"
    assert robot.waiting_at_close == 0


def test_learns_during_an_outage_wait_and_arrive_oldest_first_once_each(flaky: Flaky, tmp_path: Path) -> None:
    robot = OutboxLearner(flaky, Outbox(tmp_path / "outbox.sqlite"), "default")
    before = robot.library()
    flaky.down = True
    answers = [robot.learn(mug(n)) for n in range(3)]
    assert all(a.startswith(QUEUED_PREFIX) for a in answers)
    assert robot.outbox.count("default") == 3
    assert robot.library() == before  # the robot goes on with the last library it had
    assert robot.version() == before.version
    flaky.down = False
    assert robot.version() == before.version + 3  # delivered on the next call
    assert [d.object_id for d in robot.library().descriptions][-3:] == ["mug-0", "mug-1", "mug-2"]
    assert robot.outbox.count("default") == 0 and robot.delivered == 3
    robot.close()
    assert stored_ids(tmp_path / "lib.sqlite")[-3:] == ["mug-0", "mug-1", "mug-2"]


def test_a_lost_reply_is_resent_under_its_key_and_stored_once(flaky: Flaky, tmp_path: Path) -> None:
    robot = OutboxLearner(flaky, Outbox(tmp_path / "outbox.sqlite"), "default")
    flaky.lose_replies = 1
    assert robot.learn(MUG).startswith(QUEUED_PREFIX)  # stored, but the robot was never told
    assert robot.learn(mug(1)) == "mug-1"  # the retry of MUG goes first and finds its key
    assert flaky.learn_calls == 3
    robot.close()
    assert stored_ids(tmp_path / "lib.sqlite") == ["cup", "box", "tumbler", "closed", "mug", "mug-1"]


def test_what_waits_survives_the_robot_and_the_next_run_delivers_it(flaky: Flaky, tmp_path: Path) -> None:
    outbox = tmp_path / "outbox.sqlite"
    first = OutboxLearner(flaky, Outbox(outbox), "default")
    flaky.down = True
    first.learn(MUG)
    first.close()  # the service is still away: the description waits on disk
    assert first.waiting_at_close == 1
    again = Flaky(LocalLearner(tmp_path / "lib.sqlite"))
    with OutboxLearner(again, Outbox(outbox), "default") as second:
        assert second.library().descriptions[-1].object_id == "mug"
    assert second.waiting_at_close == 0 and second.delivered == 1


def test_the_outbox_delivers_only_to_the_service_it_was_queued_for(flaky: Flaky, tmp_path: Path) -> None:
    outbox = Outbox(tmp_path / "outbox.sqlite")
    outbox.put("other", MUG, "k-other")
    with OutboxLearner(flaky, outbox, "default") as robot:
        robot.library()
        assert robot.delivered == 0
        assert outbox.count("other") == 1


def test_a_refused_description_is_kept_marked_and_does_not_block_the_rest(flaky: Flaky, tmp_path: Path) -> None:
    robot = OutboxLearner(flaky, Outbox(tmp_path / "outbox.sqlite"), "default")
    flaky.down = True
    robot.learn(BAD)
    robot.learn(MUG)
    flaky.down = False
    robot.library()
    assert robot.outbox.count("default") == 0
    assert robot.outbox.count("default", refused=True) == 1
    with pytest.raises(ValueError, match="outside"):  # refused now: the caller is told
        robot.learn(replace(BAD, object_id="huge-2"))
    robot.close()
    assert stored_ids(tmp_path / "lib.sqlite")[-1] == "mug"


def test_a_service_never_reached_has_no_library_to_offer(flaky: Flaky, tmp_path: Path) -> None:
    flaky.down = True
    with OutboxLearner(flaky, Outbox(tmp_path / "outbox.sqlite"), "default") as robot:
        with pytest.raises(LearnerUnavailable):
            robot.library()


def test_an_unusable_outbox_file_is_one_line(tmp_path: Path) -> None:
    bad = tmp_path / "outbox.sqlite"
    bad.write_text("not a database " * 100)
    with pytest.raises(ValueError, match=r"outbox.sqlite: not a usable outbox"):
        Outbox(bad)
