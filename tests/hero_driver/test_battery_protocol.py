"""The ``battery`` protocol feature: the ``hello`` reply names the dock exactly when the
feature is listed, the ``charge`` verb, and a driver without the feature refusing it."""

from __future__ import annotations

import json

import pytest
import zenoh
from jsonschema import Draft202012Validator

from hero_driver.interface import OUT_OF_RANGE, UNKNOWN_VERB, DriverError, Hello, Pose, RobotState
from hero_driver.sim_driver import SimulatedHero
from hero_driver.zenoh_link import codec
from hero_driver.zenoh_link.codec import CodecError, EmptyRequest
from hero_driver.zenoh_link.keys import robot_keys
from hero_driver.zenoh_link.node import DriverNode
from hero_driver.zenoh_link.schemas import all_schemas
from hero_driver.zenoh_link.verbs import BY_NAME
from hero_driver.zenoh_link.versions import BATTERY, FEATURES, Greeting, agree, greeting
from tests.hero_driver.test_zenoh_node import ask
from tests.hero_driver.test_zenoh_support import FakeHero
from tests.zenoh_rpc.support import wait_until
from zenoh_rpc.config import open_session

DOCK = Pose(24.0, 85.0, 180.0)
HELLO = BY_NAME["hello"]


def test_a_node_lists_battery_exactly_when_its_driver_names_a_dock() -> None:
    assert greeting(None, DOCK) == Greeting(Hello((1,), (BATTERY,)), None, DOCK)
    assert greeting(None, None) == Greeting(Hello((1,), ()), None, None)
    assert BATTERY in FEATURES and agree(Hello((1,), (BATTERY,))).features == {BATTERY}


def test_the_hello_reply_carries_the_dock_and_round_trips() -> None:
    body = HELLO.encode_result(greeting(None, DOCK))
    assert json.loads(body) == {"v": 1, "versions": [1], "features": ["battery"],
                                "dock": {"x_in": 24.0, "y_in": 85.0, "heading_deg": 180.0}}
    assert HELLO.decode_result(body) == Greeting(Hello((1,), (BATTERY,)), None, DOCK)


@pytest.mark.parametrize(("reply", "message"), [
    ({"v": 1, "versions": [1], "features": [], "dock": {"x_in": 1, "y_in": 2, "heading_deg": 0}},
     "dock: sent without the 'battery' feature"),
    ({"v": 1, "versions": [1], "features": ["battery"]}, "dock: missing field (the 'battery' feature is listed)"),
    ({"v": 1, "versions": [1], "features": ["battery"], "dock": [1, 2, 0]}, "dock: expected an object"),
])
def test_a_dock_and_the_battery_feature_come_together_or_not_at_all(reply: dict[str, object], message: str) -> None:
    with pytest.raises(CodecError, match=message.replace("(", r"\(").replace(")", r"\)")):
        HELLO.decode_result(json.dumps(reply).encode())
    assert not Draft202012Validator(all_schemas()["hello.reply"]).is_valid(reply)


def test_the_schema_accepts_the_dock_with_the_feature_and_the_profile_beside_it() -> None:
    validator = Draft202012Validator(all_schemas()["hello.reply"])
    dock = {"x_in": 1, "y_in": 2, "heading_deg": 0}
    assert validator.is_valid({"v": 1, "versions": [1], "features": ["battery"], "dock": dock})
    assert validator.is_valid({"v": 1, "versions": [1], "features": ["profile", "battery"], "dock": dock,
                               "profile": {"name": "rover", "sha256": "ab" * 32}})
    assert not validator.is_valid({"v": 1, "versions": [1], "features": ["profile", "battery"], "dock": dock})


def test_the_error_schema_knows_battery_empty() -> None:
    assert Draft202012Validator(all_schemas()["error"]).is_valid({"v": 1, "code": "battery_empty", "message": "flat"})


def test_charge_on_a_driver_without_the_feature_is_an_unknown_verb() -> None:
    with pytest.raises(DriverError) as caught:
        BY_NAME["charge"].call(FakeHero(), EmptyRequest())
    assert caught.value.code == UNKNOWN_VERB and "no battery feature" in caught.value.message


def test_charge_answers_the_new_state(tmp_path) -> None:  # noqa: ANN001
    world = tmp_path / "docked.json"
    world.write_text(json.dumps({"room": {"width_in": 100, "depth_in": 100}, "battery": 0.5,
                                 "robot": {"x_in": 30, "y_in": 30, "heading_deg": 0},
                                 "dock": {"x_in": 30, "y_in": 30, "heading_deg": 0}}), encoding="utf-8")
    charge = BY_NAME["charge"]
    state = charge.call(SimulatedHero("r1", world=world), EmptyRequest()).result()
    assert state == RobotState(Pose(30.0, 30.0, 0.0), 900.0, 1.0)
    assert charge.decode_result(charge.encode_result(state)) == state


@pytest.mark.zenoh
def test_a_simulator_node_offers_the_feature_and_refuses_charging_away_from_the_dock(
        server: zenoh.Session, endpoint: str) -> None:
    keys = robot_keys("r1")
    with DriverNode(SimulatedHero("r1", world="lab"), server), open_session(connect=[endpoint]) as session:
        assert wait_until(lambda: bool(ask(session, keys.rpc("noop"), b'{"v":1}')), 5.0)
        [(kind, hello)] = ask(session, keys.rpc("hello"), b'{"v":1}')
        assert kind == "ok" and "battery" in hello["features"]
        assert hello["dock"] == {"x_in": 24.0, "y_in": 85.0, "heading_deg": 180.0}
        [(kind, refused)] = ask(session, keys.rpc("charge"), b'{"v":1}')  # the lab's robot starts at (30, 30)
        assert (kind, refused["code"]) == ("err", OUT_OF_RANGE)
        assert refused["message"] == "charge: the base is 55.3 in from the dock; the beacon guides it in from 24 in"


@pytest.mark.zenoh
def test_a_node_without_the_feature_answers_charge_unknown_verb(server: zenoh.Session, endpoint: str) -> None:
    keys = robot_keys("r1")
    with DriverNode(FakeHero(), server), open_session(connect=[endpoint]) as session:
        assert wait_until(lambda: bool(ask(session, keys.rpc("noop"), b'{"v":1}')), 5.0)
        [(kind, hello)] = ask(session, keys.rpc("hello"), b'{"v":1}')
        assert hello["features"] == [] and "dock" not in hello
        [(kind, refused)] = ask(session, keys.rpc("charge"), b'{"v":1}')
        assert (kind, refused["code"]) == ("err", UNKNOWN_VERB)


def test_codec_module_exports_nothing_new_for_the_state() -> None:
    """The state stays as it was: the dock is in hello, so an old client never meets
    an unknown field in a state publication."""
    assert set(json.loads(codec.encode_state(RobotState(DOCK, 0.0, 1.0)))) == {"v", "pose", "clock_s", "battery"}
