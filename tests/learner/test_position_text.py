"""A position as text is rounded for people; as JSON it stays exact."""

from __future__ import annotations

import pytest

from learner.position import Position


@pytest.mark.parametrize(("position", "text"), [
    (Position(6, 339.16071978233924), "(6,339.2)"),  # a bearing the robot reached
    (Position(6.26, 90.0), "(6.3,90)"),  # whole numbers without ".0", as the paper writes them
    (Position(23.96, None), "(24,*)"),
    (Position(None, 0.04), "(*,0)"),
    (Position(6, 359.97), "(6,0)"),  # rounds up to a full turn: the bearing it is, not 360
    (Position(60, 359.94), "(60,359.9)"),
])
def test_text_is_to_a_tenth(position: Position, text: str) -> None:
    assert str(position) == text


def test_json_keeps_the_exact_values() -> None:
    assert Position(6, 339.16071978233924).to_json() == [6, 339.16071978233924]
    assert Position(6, 359.97).to_json() == [6, 359.97]
