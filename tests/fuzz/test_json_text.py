"""``learner.library.json_text.parse_json``: the one parser behind the library file, the
learner protocol and the episode log, so each refuses every kind of bad JSON the
same way (the fuzz findings ``*_nested_too_deep`` came from readers that each caught
only ``JSONDecodeError``)."""

from __future__ import annotations

import json

import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from learner.library.json_text import NotJson, parse_json
from tests.fuzz.mutation import bombs

finite_json = st.recursive(
    st.none() | st.booleans() | st.integers() | st.floats(allow_nan=False, allow_infinity=False) | st.text(),
    lambda inner: st.lists(inner, max_size=4) | st.dictionaries(st.text(max_size=8), inner, max_size=4),
    max_leaves=12)


@given(finite_json)
def test_what_json_dumps_writes_reads_back(value: object) -> None:
    text = json.dumps(value, ensure_ascii=False)
    assert parse_json(text) == value
    assert parse_json(text.encode("utf-8")) == value


@settings(max_examples=300)
@given(st.one_of(st.binary(max_size=60), st.text(max_size=60), st.sampled_from(bombs())))
def test_anything_else_is_one_line_of_not_json(data: bytes | str) -> None:
    try:
        parse_json(data)
    except NotJson as refused:
        assert str(refused).strip() and "\n" not in str(refused)
    # any other exception fails the test: that is the property


@pytest.mark.parametrize(("data", "reason"), [
    (b"[" * 30_000 + b"]" * 30_000, "nested too deeply (arrays or objects inside each other)"),
    (b'{"v": 1' + b"0" * 5000 + b"}", "holds an integer of more than 4300 digits"),
    (b'{"a": "\xff"}', "not UTF-8 text (invalid start byte at byte 7)"),  # 7 bytes before it
    ("{", "Expecting property name enclosed in double quotes: line 1 column 2 (char 1)"),
    ("", "Expecting value: line 1 column 1 (char 0)"),
])
def test_each_way_of_failing_has_its_reason(data: bytes | str, reason: str) -> None:
    with pytest.raises(NotJson) as refused:
        parse_json(data)
    assert str(refused.value) == reason
    assert isinstance(refused.value, ValueError)  # callers that catch ValueError still do
