"""Synthetic libraries stay close to the descriptions they are perturbed from."""

from __future__ import annotations

import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from learner.library.synthetic import synthetic_library
from tests.learner.fixtures import four_objects, hero

KNOWLEDGE = hero()
BASE = {d.object_id: d for d in four_objects()}


@settings(max_examples=25, deadline=None)
@given(st.integers(0, 2**32 - 1), st.integers(1, 40))
def test_each_description_is_its_template_moved_within_twice_the_error(seed: int, n: int) -> None:
    library = synthetic_library(KNOWLEDGE, n, seed, base=list(BASE.values()))
    assert len(library) == n and len({d.object_id for d in library}) == n
    for d in library:
        template = BASE[d.object_id.split("/", 1)[1]]
        assert d.grasp in {b.grasp for b in BASE.values()}
        assert d.grasp_position == template.grasp_position
        assert d.observations, "a description keeps at least one value"
        for o in d.observations:
            original = template.value_at(o.feature, o.position)
            spec = KNOWLEDGE.feature(o.feature)
            assert original is not None, "only the template's features, at its positions"
            assert spec.span[0] <= o.value <= spec.span[1]
            if spec.binary:
                assert o.value in (0.0, 1.0)
            else:
                assert abs(o.value - original) <= 2 * spec.error + 0.05  # rounded to 0.1


def test_repeatable_from_the_seed() -> None:
    base = list(BASE.values())
    assert synthetic_library(KNOWLEDGE, 30, 7, base=base) == synthetic_library(KNOWLEDGE, 30, 7, base=base)
    assert synthetic_library(KNOWLEDGE, 30, 7, base=base) != synthetic_library(KNOWLEDGE, 30, 8, base=base)


def test_bad_input_is_named() -> None:
    assert synthetic_library(KNOWLEDGE, 0, 0, base=list(BASE.values())) == []
    with pytest.raises(ValueError, match="n_objects"):
        synthetic_library(KNOWLEDGE, -1, 0, base=list(BASE.values()))
    with pytest.raises(ValueError, match="base descriptions"):
        synthetic_library(KNOWLEDGE, 3, 0, base=[])
