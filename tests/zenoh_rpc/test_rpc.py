"""The server base and the client on two sessions over 127.0.0.1, with a toy
protocol: ``echo`` answers its payload, ``hold`` keeps its query until the test
lets go, errors are ``code:message`` bytes so every body can be compared whole."""

from __future__ import annotations

import threading
from collections.abc import Iterator

import pytest
import zenoh

from tests.zenoh_rpc.support import free_endpoint, wait_until
from zenoh_rpc.client import Answer, Reply, RpcClient
from zenoh_rpc.config import open_session
from zenoh_rpc.keys import KeySpace
from zenoh_rpc.server import RpcServer, payload_of, reply

pytestmark = pytest.mark.zenoh

KEYS = KeySpace("test", "toy")
START_S = 5.0


class Toy:
    """A server whose verbs the test watches: which ran, and the held queries."""

    def __init__(self, session: zenoh.Session) -> None:
        self.ran: list[str] = []
        self.held: list[zenoh.Query] = []
        self.server = RpcServer(session, KEYS, ("echo", "hold"), self.handle,
                                lambda code, message: f"{code}:{message}".encode(),
                                bad_request="bad", unknown_verb="what")

    def handle(self, verb: str, query: zenoh.Query) -> None:
        self.ran.append(verb)
        if verb == "hold":
            self.held.append(query)
        else:
            reply(query, payload_of(query))


@pytest.fixture
def sessions() -> Iterator[tuple[zenoh.Session, zenoh.Session]]:
    endpoint = free_endpoint()
    with open_session(listen=[endpoint]) as server, open_session(connect=[endpoint]) as client:
        yield server, client


@pytest.fixture
def toy(sessions: tuple[zenoh.Session, zenoh.Session]) -> Iterator[tuple[Toy, RpcClient]]:
    server, client = sessions
    toy = Toy(server)
    rpc = RpcClient(client, KEYS)
    assert rpc.wait_alive(START_S)
    yield toy, rpc
    toy.server.close()


def test_a_verb_is_answered_on_its_exact_key(toy: tuple[Toy, RpcClient]) -> None:
    server, rpc = toy
    assert rpc.ask("echo", b'{"hi": 1}', 2.0) == Answer((Reply(ok=b'{"hi": 1}'),))
    assert server.ran == ["echo"]


def test_a_wildcard_runs_no_verb_and_gets_one_refusal(toy: tuple[Toy, RpcClient]) -> None:
    server, rpc = toy
    answer = rpc.ask("*", b"", 2.0)
    assert answer == Answer((Reply(err=b"bad:test/toy/rpc/*: verbs must be addressed by their exact key"),))
    assert server.ran == []


def test_an_unknown_verb_is_refused_listing_the_verbs(toy: tuple[Toy, RpcClient]) -> None:
    server, rpc = toy
    assert rpc.ask("fly", b"", 2.0).first == Reply(err=b"what:'fly' is not a verb (known: echo, hold)")
    assert rpc.ask("echo/now", b"", 2.0).first == Reply(err=b"what:'echo/now' is not a verb (known: echo, hold)")
    assert server.ran == []


def test_an_unanswered_query_ends_late_at_its_timeout(toy: tuple[Toy, RpcClient]) -> None:
    server, rpc = toy
    ended: list[bool] = []
    finished = threading.Event()
    rpc.send("hold", b"", 0.3, lambda _reply: None, lambda late: (ended.append(late), finished.set()))
    assert finished.wait(2.0) and ended == [True]
    answer = rpc.ask("hold", b"", 0.3)
    assert answer == Answer((Reply(err=b"Timeout", late=True),), late=True)  # zenoh's own marker
    for query in server.held:
        query.drop()


def test_nobody_serving_ends_at_once_without_a_reply(sessions: tuple[zenoh.Session, zenoh.Session]) -> None:
    rpc = RpcClient(sessions[1], KEYS)
    assert rpc.ask("echo", b"", 5.0) == Answer()
    assert not rpc.wait_alive(0.2)


def test_the_token_follows_the_server(sessions: tuple[zenoh.Session, zenoh.Session]) -> None:
    server_session, client_session = sessions
    rpc = RpcClient(client_session, KEYS)
    changes: list[bool] = []
    watch = rpc.watch_alive(changes.append)
    try:
        toy = Toy(server_session)
        assert wait_until(lambda: changes == [True], START_S)
        found = threading.Event()
        finished = threading.Event()
        rpc.query_alive(found.set, finished.set, 2.0)
        assert finished.wait(3.0) and found.is_set()
        toy.server.close()
        toy.server.close()  # closing twice is harmless
        assert wait_until(lambda: changes == [True, False], START_S)
        assert rpc.ask("echo", b"", 2.0) == Answer()
    finally:
        watch.undeclare()


def test_every_answered_query_is_one_info_line_with_its_outcome(toy: tuple[Toy, RpcClient],
                                                                 caplog: pytest.LogCaptureFixture) -> None:
    server_toy, rpc = toy
    with caplog.at_level("INFO", logger="zenoh_rpc.server"):
        assert rpc.ask("echo", b"hi", START_S).first == Reply(ok=b"hi")
        rpc.ask("nope", b"", START_S)
        rpc.ask("hold", b"", 0.3)  # held, never answered: no line until it is
        assert wait_until(lambda: len(server_toy.held) == 1, START_S)
        server_toy.server.reply_error(server_toy.held[0], "late", "let go")
    # the server logs after it replies, on its own thread: under load the client can ask
    # the next query before the line of the last is written, so lines are matched by key
    lines = sorted(r.getMessage() for r in caplog.records if r.name == "zenoh_rpc.server")
    assert len(lines) == 3
    echo, hold, nope = lines
    assert echo.startswith("test/toy/rpc/echo: ok in ") and echo.endswith(" ms")
    assert nope.startswith("test/toy/rpc/nope: what in ")
    assert hold.startswith("test/toy/rpc/hold: late in ")
    assert all(r.levelname == "INFO" for r in caplog.records if r.name == "zenoh_rpc.server")
