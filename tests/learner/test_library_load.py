"""Loading a large library fast changes nothing a reader can see."""

from __future__ import annotations

import json

import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from executive.defaults import EXAMPLE_LIBRARY
from learner.description import Observation, in_order
from learner.library.format import descriptions_from_json, read_library_json, write_library_json
from learner.library.store import LibraryStore
from learner.library.synthetic import synthetic_library
from learner.position import Position, known_position_json, position_from_json
from tests.learner.fixtures import hero


def test_a_loaded_library_equals_the_written_one(tmp_path) -> None:  # noqa: ANN001
    library = synthetic_library(hero(), 300, 7, base=read_library_json(EXAMPLE_LIBRARY))
    write_library_json(tmp_path / "lib.json", library)
    assert read_library_json(tmp_path / "lib.json") == library
    with LibraryStore(tmp_path / "lib.sqlite") as store:
        store.add(library)
        assert store.descriptions() == library


def test_equal_positions_are_one_shared_object(tmp_path) -> None:  # noqa: ANN001
    library = synthetic_library(hero(), 50, 3, base=read_library_json(EXAMPLE_LIBRARY))
    write_library_json(tmp_path / "lib.json", library)
    loaded = read_library_json(tmp_path / "lib.json")
    by_value: dict[Position, set[int]] = {}
    for d in loaded:
        for o in d.observations:
            by_value.setdefault(o.position, set()).add(id(o.position))
    assert by_value and all(len(ids) == 1 for ids in by_value.values())


@pytest.mark.parametrize(("value", "message"), [
    ([True, 0], "p[0]: expected a number or \"*\", got True"),
    ([6, 10**400], "p[1]: expected a finite number"),
    ([-1, 0], "p: distance must not be negative"),
])
def test_a_known_position_does_not_let_a_lookalike_through(value, message) -> None:  # noqa: ANN001
    """``True == 1`` and hashes alike: once ``[1, 0]`` is known, the shared-position
    table must still never answer for a value that is not itself valid."""
    assert position_from_json([1, 0], "p") == Position(1.0, 0.0)
    assert known_position_json([1, 0]) == Position(1.0, 0.0)
    assert known_position_json(value) is None
    with pytest.raises(ValueError) as err:
        position_from_json(value, "p")
    assert message in str(err.value)


def test_a_bad_entry_after_good_ones_is_still_named() -> None:
    good = {"feature": "Height", "position": [6, "*"], "value": 3.5}
    doc = {"format": "csl-library", "version": 2, "descriptions": [
        {"id": "a", "grasp": "G", "grasp_position": [6, "*"], "features": [good]},
        {"id": "b", "grasp": "G", "grasp_position": [6, "*"], "features": [good, {**good, "value": 1e400}]},
        ]}
    with pytest.raises(ValueError) as err:
        descriptions_from_json(json.loads(json.dumps(doc).replace("Infinity", "1" + "0" * 400)), "lib.json")
    assert str(err.value) == ("lib.json: descriptions[1] (b): features[1]: 'value' must be a finite number, "
                              f"got {10**400!r}")


slot = st.one_of(st.none(), st.sampled_from([0.0, 6.0, 24.0, 90.0, 1.5]))
observation = st.builds(Observation, st.sampled_from(["Height", "Width", "Hole"]), st.builds(Position, slot, slot),
                        st.sampled_from([0.0, 1.0, -0.0, 3.5]))


@settings(max_examples=200, deadline=None)
@given(st.lists(observation, max_size=8))
def test_in_order_is_the_dataclass_order(observations: list[Observation]) -> None:
    assert in_order(observations) == tuple(sorted(observations))
