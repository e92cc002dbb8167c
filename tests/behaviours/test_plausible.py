"""``Plausible?`` (behaviours/plausible.py): a sensed value its feature cannot take, or
far beyond every library description, is implausible and the test is reselected.

The four-object library (tests/learner/fixtures.py) holds Width-Degree-1° from 8 to 30
(error 3°, span 0 to 180) and Height from 3.5 to 9 in (error 0.5 in, span 0 to 127): with
k = 20 errors, Width-Degree-1° is plausible up to 30 + 60 = 90 and Height up to
9 + 10 = 19 in (and down to 3.5 - 10, below its span's 0)."""

from __future__ import annotations

from py_trees.common import Status

from behaviours.plausible import LIBRARY_MARGIN_ERRORS, Plausible, implausibility, implausible_values, library_ranges
from learner.knowledge import FeatureSpec
from tests.behaviours.conftest import ROBOT, hero, run, start_object
from tests.learner.fixtures import four_objects

WIDTH_DEG = FeatureSpec(name="Width-Degree-1°", error=3.0, unit="deg", binary=False, span=(0.0, 180.0))


def test_the_library_range_of_each_feature() -> None:
    ranges = library_ranges(four_objects())
    assert ranges["Width-Degree-1°"] == (8, 30) and ranges["Height"] == (3.5, 9) and ranges["Top-Hole?"] == (1, 1)


def test_a_value_outside_its_span_or_twenty_errors_beyond_the_library_is_implausible() -> None:
    assert LIBRARY_MARGIN_ERRORS == 20.0
    held = (8.0, 30.0)
    assert implausibility(90.0, WIDTH_DEG, held) is None and implausibility(0.0, WIDTH_DEG, held) is None
    assert implausibility(90.5, WIDTH_DEG, held) == (
        "more than 20 x its error (3 deg) beyond every library description (8 to 30 deg)")
    assert implausibility(-1.0, WIDTH_DEG, held) == "outside the feature's span [0, 180] deg"
    assert implausibility(181.0, WIDTH_DEG, None) == "outside the feature's span [0, 180] deg"
    assert implausibility(170.0, WIDTH_DEG, None) is None  # a feature the library holds no value of: span only
    assert implausibility(float("nan"), WIDTH_DEG, held) == "nan is not a finite number"


def test_only_the_implausible_features_of_a_reading_are_named() -> None:
    ranges = library_ranges(four_objects())
    values = {"Height": 19.5, "Width": None, "Top-Hole?": 1.0, "Depth": 4.0, "Sparkle": 2.0}
    assert implausible_values(values, hero(), ranges) == {
        "Height": "more than 20 x its error (0.5 in) beyond every library description (3.5 to 9 in)",
        "Sparkle": "not a feature of the robot profile"}
    assert implausible_values({"Height": 19.0}, hero(), ranges) == {}


def test_an_implausible_value_makes_the_test_unusable_here_and_is_logged(services, log) -> None:  # noqa: ANN001
    record, step = start_object(services)
    step.test = record.session.decide()
    assert str(step.test.test) == "Width-Degree-1°(24,0)"
    step.values = {"Width-Degree-1°": 95.0}
    assert run(Plausible(ROBOT), services) == Status.FAILURE
    assert record.session.awaiting_reselection and record.session.measurements == {}
    assert log.events == [{"event": "implausible", "object": 0, "behaviour": "Plausible?",
                           "test": "Width-Degree-1°(24,0)", "feature": "Width-Degree-1°", "value": 95.0,
                           "why": "more than 20 x its error (3 deg) beyond every library description (8 to 30 deg)"}]


def test_a_plausible_reading_or_a_grasp_passes_untouched(services, log) -> None:  # noqa: ANN001
    record, step = start_object(services)
    step.test = record.session.decide()
    step.values = {"Width-Degree-1°": 90.0}  # beyond every description, but within 20 errors
    assert run(Plausible(ROBOT), services) == Status.SUCCESS
    step.values = None  # nothing sensed (a value already known, or a grasp tried as a feature)
    assert run(Plausible(ROBOT), services) == Status.SUCCESS
    assert not record.session.awaiting_reselection and log.events == []
