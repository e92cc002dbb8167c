"""The columnar JSON layout (format version 3): the same library as the row layout,
refused as strictly, entry and field named."""

from __future__ import annotations

import copy
import json

import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from executive.defaults import EXAMPLE_LIBRARY
from learner.appearance import Appearance
from learner.description import ObjectDescription
from learner.library.columnar import columnar_to_json
from learner.library.format import descriptions_from_json, descriptions_to_json, read_library_json, write_library_json
from learner.library.synthetic import synthetic_library
from tests.learner.fixtures import four_objects, hero

SHIPPED = read_library_json(EXAMPLE_LIBRARY)


def through_text(doc: object) -> object:
    return json.loads(json.dumps(doc))


def test_the_four_objects_as_columns() -> None:
    doc = columnar_to_json(four_objects(), "csl-library")
    assert doc["version"] == 3
    assert doc["features"] == ["Height", "Top-Hole?", "Width-Degree-1°"]
    assert doc["grasps"] == ["Front-Pinch", "Front-Wrap", "No-Grab", "Top-Pinch"]
    # the observations' and the grasps' positions, in the positions' order ("*" last)
    assert doc["positions"] == [[6, "*"], [24, 0], ["*", "*"]]
    columns = doc["descriptions"]
    assert columns["id"] == ["cup", "box", "tumbler", "closed"]
    assert [doc["grasps"][g] for g in columns["grasp"]] == ["Front-Wrap", "Front-Pinch", "Top-Pinch", "No-Grab"]
    assert "appearance" not in columns  # none recorded
    # the cup: Height(6,*) = 3.5 then Width-Degree-1°(24,0) = 8, indices ascending
    cup = [doc["observations"][i] for i in columns["observations"][0]]
    assert [(doc["features"][f], doc["positions"][p], v) for f, p, v in cup] == [
        ("Height", [6, "*"], 3.5), ("Width-Degree-1°", [24, 0], 8)]
    assert columns["observations"][0] == sorted(columns["observations"][0])
    assert descriptions_from_json(through_text(doc)) == four_objects()


@pytest.mark.slow
@settings(max_examples=30, deadline=None)
@given(st.integers(0, 80), st.integers(0, 10_000))
def test_both_layouts_read_back_the_same_library(n, seed) -> None:
    library = synthetic_library(hero(), n, seed, base=SHIPPED)
    rows = descriptions_from_json(through_text(descriptions_to_json(library)))
    columns = descriptions_from_json(through_text(columnar_to_json(library, "csl-library")))
    assert rows == columns == library


def test_files_of_both_layouts_hold_the_same_library(tmp_path) -> None:  # noqa: ANN001
    library = [*SHIPPED, ObjectDescription("seen", "Front-Wrap", SHIPPED[0].grasp_position, SHIPPED[0].observations,
                                           Appearance(True, 8.32, 1.0))]
    write_library_json(tmp_path / "rows.json", library)
    write_library_json(tmp_path / "columns.json", library, columnar=True)
    assert json.loads((tmp_path / "rows.json").read_text())["version"] == 2  # the default stays readable
    assert read_library_json(tmp_path / "columns.json") == read_library_json(tmp_path / "rows.json") == library
    assert (tmp_path / "columns.json").stat().st_size < (tmp_path / "rows.json").stat().st_size


def test_observations_out_of_order_are_put_in_the_librarys_order() -> None:
    doc = through_text(columnar_to_json(four_objects(), "csl-library"))
    doc["observations"].reverse()  # the table no longer in canonical order...
    last = len(doc["observations"]) - 1
    doc["descriptions"]["observations"] = [[last - i for i in codes][::-1] for codes in
                                           doc["descriptions"]["observations"]]  # ...nor each description's list
    assert descriptions_from_json(doc) == four_objects()


def broken(change) -> dict:  # noqa: ANN001
    doc = through_text(columnar_to_json(four_objects(), "csl-library"))
    change(doc)
    return doc


@pytest.mark.parametrize(
    ("change", "message"),
    [
        (lambda d: d.update(extra=1), "unknown key 'extra'"),
        (lambda d: d["descriptions"].update(colour=[]), "descriptions: unknown key 'colour'"),
        (lambda d: d["descriptions"]["grasp"].pop(), "descriptions.grasp must be a list as long as descriptions.id (4)"),
        (lambda d: d["descriptions"]["grasp"].__setitem__(1, True),
         "descriptions.grasp[1]: must be an index into 'grasps' (0 to 3), got True"),
        (lambda d: d["descriptions"]["grasp_position"].__setitem__(2, 9),
         "descriptions.grasp_position[2]: must be an index into 'positions'"),
        (lambda d: d["descriptions"]["observations"][2].append(-1),
         "descriptions.observations[2][3] (tumbler): must be an index into 'observations'"),
        (lambda d: d["descriptions"]["observations"][1].__setitem__(0, 1.0),
         "descriptions.observations[1][0] (box): must be an index into 'observations'"),
        (lambda d: d["descriptions"]["id"].__setitem__(1, "cup"), "description id 'cup' appears twice"),
        (lambda d: d["descriptions"]["id"].__setitem__(0, ""), "descriptions.id[0]: must be a non-empty string"),
        (lambda d: d["observations"][0].__setitem__(2, "tall"), "observations[0][2]: the value must be a finite number"),
        (lambda d: d["observations"][0].__setitem__(0, 7), "observations[0][0]: must be an index into 'features'"),
        (lambda d: d["positions"].__setitem__(0, [6, "near"]), "positions[0][1]: expected a number or \"*\""),
        (lambda d: d["descriptions"].update(appearance=[None, {"round": 1}, None, None]),
         "descriptions.appearance[1] (box): 'round' must be true or false"),
        (lambda d: d.update(grasps="Front-Wrap"), "'grasps' must be a list"),
    ],
)
def test_a_bad_columnar_library_names_the_field_and_entry(change, message) -> None:  # noqa: ANN001
    with pytest.raises(ValueError) as err:
        descriptions_from_json(broken(change), "lib.json")
    assert str(err.value).startswith("lib.json: ") and message in str(err.value)


def test_a_good_document_is_not_changed_by_reading_it() -> None:
    doc = through_text(columnar_to_json(SHIPPED, "csl-library"))
    kept = copy.deepcopy(doc)
    descriptions_from_json(doc)
    assert doc == kept
