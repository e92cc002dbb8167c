"""The store's observation codes: a store from before them opens with the same
content, rows an older csl adds are still read, and equal observations load as one
shared object."""

from __future__ import annotations

import sqlite3
from contextlib import closing
from pathlib import Path

from hypothesis import given, settings
from hypothesis import strategies as st
import pytest

from executive.defaults import EXAMPLE_LIBRARY
from learner.appearance import Appearance
from learner.description import ObjectDescription, Observation, in_order
from learner.library.format import read_library_json
from learner.library.store import LibraryStore
from learner.library.synthetic import synthetic_library
from tests.learner.fixtures import ANY, P, hero


def as_before_codes(path: Path) -> None:
    """Make ``path`` the store the previous csl wrote: no codes column, no codes table."""
    with closing(sqlite3.connect(path)) as db, db:
        db.execute("ALTER TABLE descriptions DROP COLUMN observation_codes")
        db.execute("DROP TABLE observation_codes")


def uncoded(path: Path) -> int:
    with closing(sqlite3.connect(path)) as db:
        return db.execute("SELECT count(*) FROM descriptions WHERE observation_codes IS NULL").fetchone()[0]


def test_a_store_from_before_codes_opens_with_identical_content(tmp_path: Path) -> None:
    library = synthetic_library(hero(), 200, 5, base=read_library_json(EXAMPLE_LIBRARY))
    path = tmp_path / "lib.sqlite"
    with LibraryStore(path) as store:
        store.add(library)
    as_before_codes(path)
    with LibraryStore(path) as store:  # migrated on open, in the opening transaction
        assert store.descriptions() == library
    assert uncoded(path) == 0
    with LibraryStore(path) as store:  # and read from the codes from now on
        assert store.descriptions() == library


def test_rows_an_older_csl_adds_are_read_and_coded_at_the_next_opening(tmp_path: Path) -> None:
    path = tmp_path / "lib.sqlite"
    cup = ObjectDescription("cup", "Front-Wrap", P(6, ANY), (Observation("Height", P(6, ANY), 3.5),))
    with LibraryStore(path) as store:
        store.add([cup])
        with closing(sqlite3.connect(path)) as older, older:  # it names its columns, codes left NULL
            older.execute("INSERT INTO descriptions (id, grasp, grasp_distance_in, grasp_orientation_deg)"
                          " VALUES ('box', 'Front-Pinch', 6, NULL)")
            older.executemany("INSERT INTO observations VALUES (2, ?, ?, ?, ?)",
                              [("Width-Degree-1°", 24, 0, 18), ("Height", 6, None, 3.5)])
        box = ObjectDescription("box", "Front-Pinch", P(6, ANY), in_order(
            [Observation("Width-Degree-1°", P(24, 0), 18.0), Observation("Height", P(6, ANY), 3.5)]))
        assert store.descriptions() == [cup, box]
    assert uncoded(path) == 1
    with LibraryStore(path) as store:
        assert store.descriptions() == [cup, box]
    assert uncoded(path) == 0


def test_equal_observations_load_as_one_object_and_in_order(tmp_path: Path) -> None:
    height, width = Observation("Height", P(6, ANY), 3.5), Observation("Width-Degree-1°", P(24, 0), 8.0)
    unsorted = ObjectDescription("a", "Front-Wrap", P(6, ANY), (width, height))  # not in in_order's order
    with LibraryStore(tmp_path / "lib.sqlite") as store:
        store.add([unsorted, ObjectDescription("b", "Front-Wrap", P(6, ANY), (height,))])
        a, b = store.descriptions()
    assert a.observations == (height, width)  # stored and read in in_order's order
    assert a.observations[0] is b.observations[0]


OBSERVATIONS = st.builds(Observation, st.sampled_from(["Height", "Width-Degree-1°", "Top-Hole?"]),
                         st.sampled_from([P(6, ANY), P(24, 0), P(ANY, ANY), P(24, 90)]),
                         st.sampled_from([0.0, 1.0, 3.5, -0.0, 8.25, 1e-300]))


@pytest.mark.slow
@settings(max_examples=40, deadline=None)
@given(st.lists(st.tuples(st.lists(OBSERVATIONS, max_size=5, unique_by=lambda o: (o.feature, o.position)),
                          st.none() | st.just(Appearance(True, 8.5, 1.0))), max_size=8),
       st.booleans())
def test_what_is_stored_is_what_is_read(tmp_path_factory, entries, from_before: bool) -> None:  # noqa: ANN001
    library = [ObjectDescription(f"d{i}", "Front-Wrap", P(6, ANY), in_order(obs), look)
               for i, (obs, look) in enumerate(entries)]
    path = tmp_path_factory.mktemp("codes") / "lib.sqlite"
    with LibraryStore(path) as store:
        store.add(library)
    if from_before:
        as_before_codes(path)
    with LibraryStore(path) as store:
        assert store.descriptions() == library
