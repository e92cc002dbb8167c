"""The driver's verb table (``hero_driver.interface.DRIVER_VERBS``) is the one list of
verbs: it holds every method of the ``Driver`` protocol and of the optional features'
protocols with the arguments they take, and the zenoh link's table carries exactly its
verbs that take the robot's time, each sending the method's arguments by name and
answering the row's result, so the node and the client can be made from the rows."""

from __future__ import annotations

import inspect
from dataclasses import fields

from hero_driver.interface import DRIVER_VERBS, PROTOCOLS, VERB_BY_NAME, protocol_method
from hero_driver.zenoh_link.client import ZenohDriver
from hero_driver.zenoh_link.verbs import VERBS


def _methods(protocol: type) -> dict[str, tuple[str, ...]]:
    own = {name: value for name, value in vars(protocol).items()
           if inspect.isfunction(value) and not name.startswith("_")}
    return {name: tuple(inspect.signature(fn).parameters)[1:] for name, fn in own.items()}


def test_every_protocol_method_is_one_row_with_its_arguments_and_feature() -> None:
    declared = {(feature, name, args) for feature, protocol in PROTOCOLS.items()
                for name, args in _methods(protocol).items()}
    assert {(v.feature, v.name, v.args) for v in DRIVER_VERBS} == declared
    assert len({v.name for v in DRIVER_VERBS}) == len(DRIVER_VERBS)


def test_the_poses_a_row_names_are_its_arguments_and_its_result_fields() -> None:
    for verb in DRIVER_VERBS:
        assert set(verb.poses_in) <= set(verb.args), verb.name
        fields = {f for f in verb.poses_out if f}
        assert verb.result is not None or not verb.poses_out, verb.name
        assert all(f in getattr(verb.result, "__dataclass_fields__", {}) for f in fields), verb.name


def test_the_zenoh_link_carries_exactly_the_verbs_that_take_the_robots_time() -> None:
    on_the_wire = {v.name for v in VERBS if v.touches_robot}
    assert on_the_wire == {v.name for v in DRIVER_VERBS if v.robot_time}


def test_a_zenoh_request_carries_its_methods_arguments_and_its_reply_the_rows_result() -> None:
    for verb in VERBS:
        if verb.touches_robot:
            row = VERB_BY_NAME[verb.name]
            assert tuple(f.name for f in fields(verb.request.value)) == row.args, verb.name
            assert verb.reply.value is row.result, verb.name


def test_the_clients_robot_verbs_have_the_protocols_signatures_and_docs() -> None:
    for verb in VERBS:
        if verb.touches_robot:
            method, declared = getattr(ZenohDriver, verb.name), protocol_method(VERB_BY_NAME[verb.name])
            assert inspect.signature(method) == inspect.signature(declared), verb.name
            assert method.__doc__ == declared.__doc__ and method.__doc__, verb.name
