"""The outbox client and grasp costs: a learner service that cannot take them (from
before grasp costs, or unreachable) never stops the robot (docs/learner-protocol.md)."""

from __future__ import annotations

from collections.abc import Sequence
from pathlib import Path

from learner.costs import GraspCostRecord
from learner.service.interface import LearnerUnavailable, LibrarySnapshot
from learner.service.outbox import Outbox, OutboxLearner
from tests.learner.fixtures import four_objects


class OldService:
    """A service as one from before grasp costs answers over zenoh: the verbs refused
    (``bad_request``, a ValueError), or, ``unreachable``, no answer at all."""

    def __init__(self) -> None:
        self.unreachable = False
        self.records: list[GraspCostRecord] = [GraspCostRecord("Front-Wrap", 1, 240.0, 0, 0.0)]
        self.refuse = False

    def record_grasp_attempts(self, attempts: Sequence[tuple[str, float, bool]], key: str | None = None,
                              robot: str | None = None) -> None:
        self._answer()

    def grasp_costs(self) -> list[GraspCostRecord]:
        self._answer()
        return self.records

    def _answer(self) -> None:
        if self.unreachable:
            raise LearnerUnavailable("learner 'old': no service answered")
        if self.refuse:
            raise ValueError("learner 'old': bad_request: 'grasp_costs' is not a verb")

    def library(self) -> LibrarySnapshot:
        return LibrarySnapshot(1, tuple(four_objects()))

    def version(self) -> int:
        return 1

    def learn(self, description: object, key: str | None = None) -> str:
        raise AssertionError("not learning here")

    def close(self) -> None:
        pass


def test_a_record_the_service_cannot_take_is_counted_and_the_last_costs_kept(tmp_path: Path) -> None:
    service = OldService()
    with OutboxLearner(service, Outbox(tmp_path / "outbox.sqlite"), "old") as client:
        assert client.grasp_costs() == service.records
        client.record_grasp_attempts([("Front-Wrap", 60.0, True)], key="a")
        assert client.grasp_records_lost == 0
        service.refuse = True
        client.record_grasp_attempts([("Front-Wrap", 60.0, True)], key="b")
        assert client.grasp_costs() == [GraspCostRecord("Front-Wrap", 1, 240.0, 0, 0.0)]  # the last received
        service.refuse, service.unreachable = False, True
        client.record_grasp_attempts([("Front-Wrap", 60.0, True)], key="c")
        assert client.grasp_costs() == [GraspCostRecord("Front-Wrap", 1, 240.0, 0, 0.0)]
        assert client.grasp_records_lost == 2


def test_before_any_answer_the_costs_are_none_the_files_prices(tmp_path: Path) -> None:
    service = OldService()
    service.refuse = True
    with OutboxLearner(service, Outbox(tmp_path / "outbox.sqlite"), "old") as client:
        assert client.grasp_costs() == []
