"""``hello`` and the version handshake: the node answers what it serves, the client
agrees on the highest common version (or refuses the driver in one line), a driver
that predates ``hello`` is served as version 1, and the conformance suite checks it."""

from __future__ import annotations


import pytest
import zenoh
from hypothesis import given
from hypothesis import strategies as st

from hero_driver.interface import BAD_REQUEST, UNAVAILABLE, UNKNOWN_VERB, DriverError, Hello, Pose
from hero_driver.zenoh_link import codec
from hero_driver.zenoh_link.client import ZenohDriver
from hero_driver.zenoh_link.checking import CheckFailed, Probe
from hero_driver.zenoh_link.conformance import Procedures, _Suite
from hero_driver.zenoh_link.keys import robot_keys
from hero_driver.zenoh_link.node import DriverNode
from hero_driver.zenoh_link.versions import Agreement, Greeting, NoCommonVersion, agree
from robot_profile import ProfileStamp
from tests.hero_driver.test_zenoh_node import error_of
from tests.hero_driver.test_zenoh_support import FakeHero, SlowHero
from tests.zenoh_rpc.support import wait_until
from zenoh_rpc.config import open_session
from zenoh_rpc.server import RpcServer, reply

pytestmark = pytest.mark.zenoh

REPLY_S = 5.0
V1 = Agreement(1, frozenset())
ROVER = ProfileStamp("rover", "ab" * 32)


# ------------------------------------------------------------------- the policy


@given(st.sets(st.integers(1, 6), min_size=1), st.sets(st.integers(1, 6), min_size=1),
       st.sets(st.sampled_from("abcd")), st.sets(st.sampled_from("abcd")))
def test_the_highest_common_version_and_the_shared_features_are_agreed(
        served: set[int], speaks: set[int], offered: set[str], known: set[str]) -> None:
    hello = Hello(tuple(sorted(served)), tuple(sorted(offered)))
    if served & speaks:
        agreement = agree(hello, speaks, known)
        assert agreement.version == max(served & speaks)
        assert agreement.features == offered & known
    else:
        with pytest.raises(NoCommonVersion):
            agree(hello, speaks, known)


def test_no_common_version_is_one_line_naming_both_sides() -> None:
    with pytest.raises(NoCommonVersion) as caught:
        agree(Hello((3, 2)), speaks=(1,))
    assert str(caught.value) == ("the driver serves protocol version 2, 3, this client speaks 1: "
                                 "upgrade the older side")


# ----------------------------------------------------------- zenoh, in process


def hand_written(session: zenoh.Session, robot: str, hello: bytes | None) -> RpcServer:
    """A driver in miniature, as another team might write one: ``noop``, and ``hello``
    answered with ``hello`` (None: it has no hello, so its catch-all answers
    ``unknown_verb``). Declares the liveliness token."""
    verbs = ["noop"] if hello is None else ["noop", "hello"]

    def handle(verb: str, query: zenoh.Query) -> None:
        reply(query, hello if verb == "hello" and hello is not None else b'{"v":1}')

    return RpcServer(session, robot_keys(robot), verbs, handle, codec.encode_error,
                     bad_request=BAD_REQUEST, unknown_verb=UNKNOWN_VERB)


def test_the_node_says_what_it_serves_and_the_client_agrees(server: zenoh.Session, endpoint: str) -> None:
    with DriverNode(FakeHero(), server), ZenohDriver("r1", connect=[endpoint], discover_s=5.0) as client:
        assert client.agreement == V1  # agreed before the constructor returned
        assert client.hello().result(REPLY_S) == Greeting(Hello((1,), ()))
        assert client.profile is None  # this node was given no profile to name


def test_a_node_names_its_profile_and_the_client_exposes_it(server: zenoh.Session, endpoint: str) -> None:
    with DriverNode(FakeHero(), server, profile=ROVER), \
            ZenohDriver("r1", connect=[endpoint], discover_s=5.0) as client:
        assert client.agreement == Agreement(1, frozenset({"profile"}))
        assert client.profile == ROVER
        assert client.hello().result(REPLY_S) == Greeting(Hello((1,), ("profile",)), ROVER)


def test_hello_is_answered_while_a_move_runs(server: zenoh.Session, endpoint: str) -> None:
    hero = SlowHero()
    with DriverNode(hero, server), ZenohDriver("r1", connect=[endpoint], discover_s=5.0) as client:
        moving = client.move([Pose(40, 30, 0)])
        assert wait_until(lambda: hero.moving is not None, 2.0)
        assert client.hello().result(REPLY_S).served.versions == (1,)
        hero.finish_move()
        assert moving.result(REPLY_S).pose == Pose(40, 30, 0)


def test_a_driver_without_hello_is_served_as_version_1(server: zenoh.Session, endpoint: str) -> None:
    legacy = hand_written(server, "old", hello=None)
    with ZenohDriver("old", connect=[endpoint], discover_s=5.0) as client:
        assert client.agreement == V1
        assert error_of(client.hello()).code == UNKNOWN_VERB
        assert client.noop().result(REPLY_S) is None
    legacy.close()


def test_a_driver_with_no_catch_all_is_served_as_version_1(server: zenoh.Session, endpoint: str) -> None:
    token = server.liveliness().declare_token(robot_keys("bare").alive)
    with ZenohDriver("bare", connect=[endpoint], discover_s=5.0) as client:
        assert client.agreement == V1  # hello went unanswered: nothing serves the key
    token.undeclare()


def test_a_driver_sharing_no_version_is_refused_at_open_in_one_line(server: zenoh.Session,
                                                                     endpoint: str) -> None:
    future = hand_written(server, "next", hello=b'{"v":1,"versions":[2,3],"features":["lidar"]}')
    with pytest.raises(DriverError) as caught:
        ZenohDriver("next", connect=[endpoint], discover_s=5.0)
    assert caught.value.code == UNAVAILABLE
    assert caught.value.message == ("robot next: the driver serves protocol version 2, 3, "
                                    "this client speaks 1: upgrade the older side")
    assert "\n" not in str(caught.value)
    future.close()


def test_a_driver_sharing_no_version_that_appears_later_is_refused(server: zenoh.Session,
                                                                   endpoint: str) -> None:
    with ZenohDriver("late", connect=[endpoint], discover_s=0.1) as client:
        assert client.agreement is None
        future = hand_written(server, "late", hello=b'{"v":1,"versions":[2],"features":[]}')
        with pytest.raises(DriverError, match="protocol version 2"):
            client.wait_ready(5.0)
        refused = error_of(client.noop())
        assert refused.code == UNAVAILABLE and "this client speaks 1" in refused.message
        future.close()  # gone: the refusal goes with it, and a v1 driver is welcome again
        assert client.wait_gone(2.0)
        with DriverNode(FakeHero("late"), server):
            assert client.wait_ready(5.0)
            assert client.agreement == V1
            assert client.noop().result(REPLY_S) is None


# ------------------------------------------------------------- conformance


def hello_check(session: zenoh.Session, robot: str) -> str:
    probe = Probe(session, robot, REPLY_S)
    try:
        assert probe.rpc.wait_alive(5.0)
        return _Suite(probe, Procedures("H-Sweep-5°", "S-Sweep-1°", "Front-Pinch")).hello()
    finally:
        probe.close()


@pytest.mark.parametrize(("body", "verdict"), [
    (None, "no hello: used as protocol version 1"),
    (b'{"v":1,"versions":[1,2],"features":["x"]}', "serves versions 1, 2 (using 1); features: x"),
    (b'{"v":1,"versions":[2],"features":[]}', "FAIL: the driver serves protocol version 2"),
    (b'{"v":1,"versions":[1],"features":[],"vendor":"acme"}', "FAIL: malformed reply: vendor: unknown field"),
    (b'{"v":1,"versions":[1],"features":["profile"],"profile":{"name":"rover","sha256":"' + b"ab" * 32 + b'"}}',
     "serves versions 1 (using 1); features: profile; profile: rover (sha256 abababababab)"),
    (b'{"v":1,"versions":[1],"features":[],"profile":{"name":"rover","sha256":"' + b"ab" * 32 + b'"}}',
     "FAIL: malformed reply: profile: sent without the 'profile' feature"),
    (b'{"v":1,"versions":[1],"features":["profile"]}',
     "FAIL: malformed reply: profile: missing field (the 'profile' feature is listed)"),
    (b'{"v":1,"versions":[1],"features":["profile"],"profile":{"name":"rover","sha256":"AB"}}',
     "FAIL: malformed reply: profile.sha256: expected 64 lowercase hex digits"),
    (b'{"v":1,"versions":[]}', "FAIL: malformed reply: features: missing field"),
    (b'{"v":1,"versions":"1","features":[]}', "FAIL: malformed reply: versions: expected an array"),
])
def test_the_hello_check(server: zenoh.Session, endpoint: str, body: bytes | None, verdict: str) -> None:
    driver = hand_written(server, "h", hello=body)
    with open_session(connect=[endpoint]) as session:
        try:
            outcome = hello_check(session, "h")
        except CheckFailed as exc:
            outcome = f"FAIL: {exc}"
    driver.close()
    assert outcome.startswith(verdict), outcome


def test_the_hello_check_passes_the_node(server: zenoh.Session, endpoint: str) -> None:
    with DriverNode(FakeHero("n"), server), open_session(connect=[endpoint]) as session:
        assert hello_check(session, "n") == "serves versions 1 (using 1); features: none"

