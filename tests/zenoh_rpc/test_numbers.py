"""One rule for a whole number on the wire: the driver link and the learner service read
``"v"`` (and every other integer) alike, so no client is accepted by one and refused by
the other."""

from __future__ import annotations

import json

import numpy as np
import pytest
from hypothesis import given
from hypothesis import strategies as st

from hero_driver.zenoh_link import codec
from hero_driver.zenoh_link.codec import CodecError
from learner.service.protocol import ProtocolError, decode_changes_request
from zenoh_rpc.numbers import whole_number


@pytest.mark.parametrize(("value", "whole"), [
    (3, 3), (3.0, 3), (-2.0, -2), (np.int64(7), 7), (0, 0),
    (3.5, None), (True, None), (False, None), (np.bool_(True), None), ("3", None), (None, None), ([3], None),
])
def test_whole_numbers_by_hand(value: object, whole: int | None) -> None:
    assert whole_number(value) == whole


def _driver_accepts(v: object) -> bool:
    try:
        codec.decode_state(json.dumps({"v": v, "pose": {"x_in": 0, "y_in": 0, "heading_deg": 0}, "clock_s": 0,
                                       "battery": 1.0}).encode())
        return True
    except CodecError:
        return False


def _learner_accepts(v: object) -> bool:
    try:
        decode_changes_request(json.dumps({"v": v, "since": 0}).encode())
        return True
    except ProtocolError:
        return False


@given(st.one_of(st.integers(-3, 3), st.floats(-3, 3, allow_nan=False), st.booleans(), st.text(max_size=2)))
def test_the_driver_and_the_learner_read_v_alike(v: object) -> None:
    assert _driver_accepts(v) == _learner_accepts(v) == (whole_number(v) == 1)


def test_v_1_0_is_version_1_for_both() -> None:
    assert _driver_accepts(1.0) and _learner_accepts(1.0)
    assert not _driver_accepts(True) and not _learner_accepts(True)
    assert decode_changes_request(b'{"v": 1, "since": 4.0}') == 4
