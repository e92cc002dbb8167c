"""Training fidelity: every library value against an exact source, at every training
position it stands for; and the training figures (positions, robot time, exhaustive)."""

from __future__ import annotations

import pytest

from learner.costs import ModelMoveCost
from learner.description import ObjectDescription, Observation
from learner.position import Position
from learner.training.fidelity import check_fidelity, stands_for
from learner.training.inputs import TrainingObject
from learner.training.stage import train
from learner.training.summary import SECONDS_PER_YEAR, every_procedure_at_positions_s, exhaustive_training_s, summarise
from tests.learner.fixtures import P, hero
from tests.learner.test_training import Geometry, obj, rect

EVERY = [0.0, 90.0, 180.0, 270.0]


class Exact:
    """A lying tumbler 4.6 in long and 3.6 in across (its width depends on the side seen)
    and a round cup 3.5 in across; H-Scan-0.3 only."""

    def __init__(self) -> None:
        self.asked: list[tuple[str, str, Position]] = []

    def measure(self, object_id: str, procedure: str, position: Position) -> dict[str, float | None]:
        self.asked.append((object_id, procedure, position))
        assert procedure == "H-Scan-0.3" and position.orientation_deg is not None
        if object_id == "cup":
            return {"Width": 3.5, "Front-Hole?": 0.0}
        side = round(position.orientation_deg / 90) % 2 == 1
        return {"Width": 4.6 if side else 3.6, "Front-Hole?": 0.0}


TUMBLER = TrainingObject("tumbler", "Front-Pinch", P(6, None), rect(4.6, 3.6), False)
CUP = TrainingObject("cup", "Front-Wrap", P(6, None), (), True)


def _described(oid: str, grasp: str, *obs: Observation) -> ObjectDescription:
    return ObjectDescription(oid, grasp, P(6, None), tuple(obs))


def test_a_dont_care_value_is_checked_at_every_position_it_stands_for() -> None:
    k = hero()
    assert stands_for(TUMBLER, "Width", P(6, None), EVERY, [6, 16], k) == [P(6, o) for o in EVERY]
    assert stands_for(CUP, "Width", P(6, None), EVERY, [6, 16], k) == [P(6, 0)]  # round: sensed at 0° only
    # a sweep reaches 6-127 in, a scan only 6 in
    assert stands_for(TUMBLER, "Width-Degree-1°", P(None, 90), EVERY, [6, 16], k) == [P(6, 90), P(16, 90)]
    assert stands_for(TUMBLER, "Width", P(None, 90), EVERY, [6, 16], k) == [P(6, 90)]


def test_the_old_merge_of_two_ends_is_caught_at_the_sides_and_the_faithful_one_is_not() -> None:
    """Width(6,*) = 3.65 from 0° and 180° is 0.95 in off at 90° and 270° (error ±0.5)."""
    k = hero()
    generalised_from_two = [_described("tumbler", "Front-Pinch", Observation("Width", P(6, None), 3.65)),
                            _described("cup", "Front-Wrap", Observation("Width", P(6, None), 3.5))]
    report = check_fidelity(generalised_from_two, [TUMBLER, CUP], k, EVERY, [6], Exact())
    assert report.checked == 5  # four orientations for the tumbler, one for the cup
    assert [(m.checked_at, m.exact) for m in report.misfits] == [(P(6, 90), 4.6), (P(6, 270), 4.6)]
    assert str(report.misfits[0]) == ("tumbler: Width(6,*) = 3.65, exact at (6,90): 4.6 "
                                      "(expected error ±0.5)")

    kept_apart = [_described("tumbler", "Front-Pinch", Observation("Width", P(6, 0), 3.6),
                             Observation("Width", P(6, 180), 3.7))]
    source = Exact()
    assert check_fidelity(kept_apart, [TUMBLER], k, EVERY, [6], source).misfits == ()
    assert len(source.asked) == 2


def test_a_value_the_exact_source_cannot_give_is_a_misfit_and_an_unknown_object_an_error() -> None:
    class Silent(Exact):
        def measure(self, object_id: str, procedure: str, position: Position) -> dict[str, float | None]:
            return {"Width": None}

    k = hero()
    library = [_described("cup", "Front-Wrap", Observation("Width", P(6, None), 3.5))]
    (misfit,) = check_fidelity(library, [CUP], k, EVERY, [6], Silent()).misfits
    assert misfit.exact is None and "exact at (6,0): nothing" in str(misfit)
    with pytest.raises(ValueError, match="'cup' is not among the training objects"):
        check_fidelity(library, [TUMBLER], k, EVERY, [6], Exact())


def test_noise_free_training_is_faithful_to_its_source() -> None:
    k = hero()
    objects = [obj("cup", "Front-Wrap", round_=True), obj("box", "Front-Pinch", rect(9, 4)),
               obj("tumbler", "Top-Pinch", round_=True), obj("closed", "No-Grab", rect(11, 9))]
    shapes = {"cup": (3.5, 3.5, 3.5, True), "box": (9, 4, 5, True),
              "tumbler": (3.5, 3.5, 6, True), "closed": (11, 9, 12, False)}
    result = train(objects, k, Geometry(shapes), ModelMoveCost(k.move))
    report = check_fidelity(result.descriptions, objects, k, result.log.orientations, result.log.distances,
                            Geometry(shapes))
    assert report.checked >= sum(len(d.observations) for d in result.descriptions)
    assert report.misfits == ()


def test_exhaustive_training_of_table_3_takes_over_five_years() -> None:
    """Per orientation: the four sweeps (100 + 45 + 76 + 42 = 263 s) at each of the 122
    whole inches 6..127, the three 6 in procedures (70 + 105 + 84 = 259 s) once:
    32,345 s; times 360 orientations and 14 objects = 163,018,800 s = 5.17 years."""
    k = hero()
    assert exhaustive_training_s(14, k) == 14 * 360 * (122 * 263 + 259)
    assert exhaustive_training_s(14, k) / SECONDS_PER_YEAR == pytest.approx(5.166, abs=0.001)
    # a coarser grid: 5 in (6, 11, ..., 126: 25 distances) by 10° (36 orientations)
    assert exhaustive_training_s(1, k, 5.0, 10.0) == 36 * (25 * 263 + 259)
    with pytest.raises(ValueError, match="grid steps must be positive"):
        exhaustive_training_s(1, k, 0.0)


def test_every_procedure_at_the_chosen_positions_by_hand() -> None:
    """At 6 in all seven procedures (522 s), at 16 in the four sweeps (263 s): a round
    object once per distance (785 s), a box at each of four orientations (3,140 s)."""
    k = hero()
    objects = [obj("cup", "Front-Wrap", round_=True), obj("box", "Front-Pinch", rect(9, 4))]
    assert every_procedure_at_positions_s(objects, k, EVERY, [6, 16]) == 785 + 4 * 785


def test_summary_reports_what_training_found_and_spent() -> None:
    k = hero()
    objects = [obj("cup", "Front-Wrap", round_=True), obj("box", "Front-Pinch", rect(9, 4))]
    result = train(objects, k, Geometry({"cup": (3.5, 3.5, 3.5, True), "box": (9, 4, 5, True)}),
                   ModelMoveCost(k.move))
    summary = summarise(result, objects, k)
    log = result.log
    assert summary.orientations_deg == (0, 90, 180, 270) and summary.distances_in == tuple(log.distances)
    assert (summary.descriptions, summary.applications) == (2, len(log.applied))
    assert summary.observations == sum(len(d.observations) for d in result.descriptions)
    assert summary.total_s == log.sensing_s + log.moving_s and summary.robot_hours == summary.total_s / 3600
    assert summary.exhaustive_s == exhaustive_training_s(2, k)
    assert summary.every_procedure_at_positions_s == every_procedure_at_positions_s(
        objects, k, log.orientations, log.distances)
    assert summary.sensing_s < summary.every_procedure_at_positions_s  # only what was needed
