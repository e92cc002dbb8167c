"""A learner service that is there but slower than it was given: the error names the
request and the time it had, and how to give it longer (``csl run --learner-timeout``),
not "is one serving?"."""

from __future__ import annotations

import threading
from pathlib import Path

import pytest

from csl_cli.main import _error
from executive.exit_status import LOST
from learner.service import LocalLearner
from learner.service.interface import LearnerTimedOut, LibrarySnapshot
from learner.service.zenoh_client import ZenohLearner
from learner.service.zenoh_node import LearnerNode
from tests.learner.fixtures import four_objects
from tests.zenoh_rpc.support import free_endpoint
from zenoh_rpc.config import open_session

pytestmark = pytest.mark.zenoh


class SlowLearner(LocalLearner):
    """Answers ``library`` only once ``release`` is set (a service busy with a fleet)."""

    def __init__(self, path: Path) -> None:
        super().__init__(path, seed_library=four_objects())
        self.release = threading.Event()

    def library(self) -> LibrarySnapshot:
        self.release.wait(5.0)
        return super().library()


def test_a_slow_service_is_a_timeout_that_says_what_and_how_long(tmp_path: Path) -> None:
    endpoint = free_endpoint()
    service = SlowLearner(tmp_path / "lib.sqlite")
    with open_session(listen=[endpoint]) as session, LearnerNode(service, session, "slow"):
        client = ZenohLearner("slow", connect=[endpoint], timeout_s=0.5)
        try:
            with pytest.raises(LearnerTimedOut) as slow:  # the service holds its answer: the client's deadline
                client.library()
            service.release.set()
            assert len(client.library().descriptions) == 4  # given the time, it answers
        finally:
            client.close()
            service.close()
    line, status = _error(slow.value)
    assert line == ("csl: learner error: learner 'slow': library: no reply within 0.5 s (a busy service, or a large "
                    "library on a slow link: give it longer with --learner-timeout)")
    assert status == LOST
