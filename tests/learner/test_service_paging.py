"""Start-up fetches the library page by page: each reply small enough to come inside a
client's timeout however large the library and however many robots start together
(once, 7 of 16 robots starting at once against a 2,716-description library timed
out on the whole-library reply)."""

from __future__ import annotations

import threading
from pathlib import Path

import pytest

from executive.defaults import EXAMPLE_LIBRARY, KNOWLEDGE
from learner.description import Descriptions
from learner.library.format import read_library_json, write_library_json
from learner.library.synthetic import synthetic_library
from learner.service import protocol
from learner.service.interface import LibraryPage, LibrarySnapshot
from learner.service import LocalLearner
from learner.service.protocol import LIBRARY
from learner.service.zenoh_client import ZenohLearner
from learner.service.zenoh_node import LearnerNode
from robot_profile import load_knowledge
from tests.learner.fixtures import four_objects
from tests.learner.test_service_zenoh import MUG, ServiceProcess
from tests.zenoh_rpc.support import free_endpoint
from zenoh_rpc.config import open_session


def test_a_library_request_asks_for_the_whole_library_or_one_page() -> None:
    assert protocol.decode_library_request(protocol.encode_library_request()) is None
    page = protocol.Page(4000, 2000)
    assert protocol.decode_library_request(protocol.encode_library_request(page)) == page


@pytest.mark.parametrize(("body", "message"), [
    (b'{"v": 1, "start": 0}', "start and limit: give both"),
    (b'{"v": 1, "limit": 10}', "start and limit: give both"),
    (b'{"v": 1, "start": 0, "limit": 0}', "limit: must be 1 to 5000, got 0"),
    (b'{"v": 1, "start": 0, "limit": 5001}', "limit: must be 1 to 5000, got 5001"),
    (b'{"v": 1, "start": -1, "limit": 10}', "start: must be a non-negative integer"),
    (b'{"v": 1, "start": 0, "limit": 10, "all": true}', "unknown field 'all'"),
])
def test_a_bad_page_request_is_refused_naming_the_field(body: bytes, message: str) -> None:
    with pytest.raises(protocol.ProtocolError, match=message):
        protocol.decode_library_request(body)


def test_a_page_reply_survives_the_wire() -> None:
    page = LibraryPage(9, 2, 6, tuple(four_objects()[2:]))
    assert protocol.decode_library_page_reply(protocol.encode_library_page_reply(page)) == page


def test_a_client_page_size_is_checked() -> None:
    with pytest.raises(ValueError, match="page_size must be 1 to 5000, got 0"):
        ZenohLearner("x", connect=["tcp/127.0.0.1:9"], page_size=0)


class LearnsBetweenPages(ZenohLearner):
    """A robot whose start-up fetch is interleaved with another robot's learn: after
    its first page, ``other`` learns MUG."""

    def __init__(self, *args: object, other: ZenohLearner, **kwargs: object) -> None:
        super().__init__(*args, **kwargs)  # type: ignore[arg-type]
        self.other, self.pages = other, 0

    def _page(self, start: int) -> LibraryPage:
        page = super()._page(start)
        self.pages += 1
        if self.pages == 1:
            self.other.learn(MUG)
        return page


@pytest.mark.zenoh
def test_pages_make_the_library_as_of_the_first_page_then_changes_bring_the_rest(tmp_path: Path) -> None:
    seed = tmp_path / "seed.json"
    write_library_json(seed, four_objects())
    service = ServiceProcess(tmp_path / "lib.sqlite", free_endpoint(), seed)
    try:
        service.ready()
        with ZenohLearner(service.name, connect=[service.endpoint], timeout_s=3.0) as writer, \
                LearnsBetweenPages(service.name, connect=[service.endpoint], timeout_s=3.0, page_size=3,
                                   other=writer) as reader:
            first = reader.library()
            # four descriptions in pages of 3: two pages; MUG was learned between them,
            # and the snapshot is the library as the first page found it (version 1)
            assert reader.pages == 2
            assert first == LibrarySnapshot(1, tuple(four_objects()))
            after = reader.library()  # one changes round trip, not a refetch
            assert reader.pages == 2 and after.version == 2 and after.descriptions == (*four_objects(), MUG)
            assert isinstance(after.descriptions, Descriptions) and after.descriptions.extends(first.descriptions)
    finally:
        service.close()


@pytest.mark.zenoh
@pytest.mark.slow
def test_robots_starting_together_all_get_the_whole_library(tmp_path: Path) -> None:
    """Six robots start at once against 3,000 descriptions with a 5 s bound per request:
    every one gets the same library as the service's own file (the bench does ten
    against 100,000, BENCHMARKS.md "A fleet starting together")."""
    library = synthetic_library(load_knowledge(KNOWLEDGE), 3000, seed=5, base=read_library_json(EXAMPLE_LIBRARY))
    seed = tmp_path / "seed.json"
    write_library_json(seed, library)
    service = ServiceProcess(tmp_path / "lib.sqlite", free_endpoint(), seed)
    got: dict[int, object] = {}

    def start(i: int) -> None:
        try:
            with ZenohLearner(service.name, connect=[service.endpoint], timeout_s=5.0, page_size=500) as robot:
                got[i] = robot.library()
        except Exception as exc:  # noqa: BLE001 - recorded, asserted below
            got[i] = exc

    try:
        service.ready()
        threads = [threading.Thread(target=start, args=(i,)) for i in range(6)]
        for t in threads:
            t.start()
        for t in threads:
            t.join(120)
        assert sorted(got) == list(range(6))
        failed = {i: r for i, r in got.items() if not isinstance(r, LibrarySnapshot)}
        assert not failed
        assert all(s.descriptions == tuple(library) for s in got.values())  # type: ignore[union-attr]
    finally:
        service.close()


class BeforePages(LearnerNode):
    """A learner node as it was before pages: ``library`` takes no fields."""

    def _answer(self, verb: str, payload: bytes, robot: str | None = None) -> bytes:
        if verb == LIBRARY:
            protocol.decode_empty_request(payload)
        return super()._answer(verb, payload, robot)


@pytest.mark.zenoh
def test_a_service_from_before_pages_is_fetched_whole(tmp_path: Path) -> None:
    endpoint = free_endpoint()
    with LocalLearner(tmp_path / "lib.sqlite", seed_library=four_objects()) as service, \
            open_session(listen=[endpoint]) as session, BeforePages(service, session, "old"), \
            ZenohLearner("old", connect=[endpoint], timeout_s=3.0, page_size=2) as robot:
        assert robot.library() == LibrarySnapshot(1, tuple(four_objects()))
        assert not robot._paged  # refused once, then asked whole: not a refusal per start
