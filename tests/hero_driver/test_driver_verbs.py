"""The driver's verb table (``hero_driver.interface.DRIVER_VERBS``) is the one list of
verbs: it holds every method of the ``Driver`` protocol and of the optional features'
protocols with the arguments they take, and the zenoh link's table carries exactly its
verbs that take the robot's time."""

from __future__ import annotations

import inspect

from hero_driver.interface import DRIVER_VERBS, BlockedMoves, Charger, Driver
from hero_driver.zenoh_link.verbs import VERBS

PROTOCOLS = {None: Driver, "battery": Charger, "blocked_moves": BlockedMoves}


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
