"""What the camera already measured rules candidates out for free.

Axes are the footprint's equivalent ellipse: area = pi/4 * major * minor and
elongation = major / minor, so (pi, 1) is a 2 in disc and (2 pi, 2) a 4 x 2 in ellipse.
"""

from __future__ import annotations

import math

import pytest
from hypothesis import given
from hypothesis import strategies as st

from learner.appearance import AXIS_TOLERANCE_IN, Appearance, appearance_from_json
from learner.choosing.criteria import criterion
from learner.choosing.leaf import GraspLeaf
from learner.choosing.matrix import DescriptionMatrix
from learner.costs import ModelMoveCost
from learner.description import ObjectDescription, Observation
from learner.position import Position
from learner.runtime import RecognitionSession
from tests.learner.fixtures import P, hero

ROUND_CAN = Appearance(True, 5.76, 1.0)  # the upright soda can as training saw it: 2.71 in across
LYING_CAN = Appearance(False, 13.44, 2.333)  # the lying soda can: 6.32 x 2.71 in


def test_equivalent_axes_worked_by_hand() -> None:
    assert Appearance(True, math.pi, 1.0).axes_in == pytest.approx((2.0, 2.0))
    assert Appearance(False, 2 * math.pi, 2.0).axes_in == pytest.approx((4.0, 2.0))
    assert ROUND_CAN.axes_in == pytest.approx((2.708, 2.708), abs=1e-3)
    assert LYING_CAN.axes_in == pytest.approx((6.318, 2.708), abs=1e-3)  # 2 sqrt(13.44 * 2.333 / pi)


def test_agreement_is_within_the_tolerance_on_both_axes() -> None:
    disc = Appearance(True, math.pi, 1.0)  # 2 x 2
    assert disc.agrees(Appearance(False, math.pi * 3.6 * 2 / 4, 1.8))  # 3.6 x 2: 1.6 off
    assert not disc.agrees(Appearance(False, math.pi * 3.7 * 2 / 4, 1.85))  # 3.7 x 2: 1.7 off
    assert not ROUND_CAN.agrees(LYING_CAN)  # majors 2.71 and 6.32: 3.6 in apart


@given(st.floats(0.5, 500), st.floats(1.0, 6.0), st.floats(0.5, 500), st.floats(1.0, 6.0))
def test_agreement_is_symmetric(a1: float, e1: float, a2: float, e2: float) -> None:
    a, b = Appearance(False, a1, e1), Appearance(False, a2, e2)
    assert a.agrees(b) == b.agrees(a)
    assert a.agrees(a)


@pytest.mark.parametrize(("data", "message"), [
    ([], "must be an object"),
    ({"round": 1, "area_in2": 4, "elongation": 1}, "'round' must be true or false"),
    ({"round": True, "area_in2": "big", "elongation": 1}, "'area_in2' must be a number"),
    ({"round": True, "area_in2": 0, "elongation": 1}, "area must be a positive number"),
    ({"round": True, "area_in2": 4, "elongation": 0.5}, "elongation must be a number >= 1"),
    ({"round": True, "area_in2": 4, "elongation": 1, "colour": "red"}, "unknown key 'colour'"),
])
def test_bad_appearance_names_the_field(data: object, message: str) -> None:
    with pytest.raises(ValueError, match="lib: appearance: .*" + message.replace("(", r"\(").replace(")", r"\)")):
        appearance_from_json(data, "lib: appearance")


def _cans() -> list[ObjectDescription]:
    """An upright can (round), a lying can and a lying tumbler (both 6.32 x 2.71 in).

    V-Sweep (42 s) Height-Degree-5°(6,*): 60 | 25, 25 -> upright | lying ones;
    H-Sweep (45 s) Width-Degree-5°(6,*): 25, 25 | 45 -> can | tumbler.
    Over all three each test gains H(1/3,1/3,1/3) - 2/3 * 1 = 0.918 bits from (6,0) at no
    move: I^2/C prefers the cheaper V-Sweep. Over the two lying ones the V-Sweep gains 0.
    """
    def d(oid: str, grasp: str, height: float, width: float, look: Appearance) -> ObjectDescription:
        return ObjectDescription(oid, grasp, P(6, None), (Observation("Height-Degree-5°", P(6, None), height),
                                                          Observation("Width-Degree-5°", P(6, None), width)), look)
    return [d("can/upright", "Front-Wrap", 60, 25, ROUND_CAN),
            d("can/lying", "Top-Vert-Grip", 25, 25, LYING_CAN),
            d("tumbler/lying", "Front-Pinch", 25, 45, LYING_CAN)]


def _session(library: list[ObjectDescription], seen: Appearance | None, use: bool = True) -> RecognitionSession:
    knowledge = hero()
    return RecognitionSession(DescriptionMatrix(library, knowledge, grasps_as_features=False), criterion("cs-id3"),
                              ModelMoveCost(knowledge.move), Position(6, 0), appearance=seen, use_appearance=use)


def test_a_lying_can_is_not_offered_round_descriptions_nor_their_v_sweep() -> None:
    blind = _session(_cans(), LYING_CAN, use=False)
    assert blind.candidates == ("can/lying", "can/upright", "tumbler/lying")
    assert str(blind.decide().test) == "Height-Degree-5°(6,*)"  # the V-Sweep the upright can needs

    seeing = _session(_cans(), Appearance(False, 12.8, 2.3))  # as the camera sees it turned: 6.1 x 2.7
    assert seeing.candidates == ("can/lying", "tumbler/lying")
    assert seeing.unlike_rows() == [0] and not seeing.appearance_ignored
    first = seeing.decide()
    assert str(first.test) == "Width-Degree-5°(6,*)" and first.sense_cost == 45.0 and first.gain == pytest.approx(1.0)


def test_one_candidate_left_is_grasped_without_a_test() -> None:
    library = _cans()[:2]  # the upright and the lying can
    assert str(_session(library, None).decide().test) == "Height-Degree-5°(6,*)"
    decision = _session(library, LYING_CAN).decide()
    assert isinstance(decision, GraspLeaf) and decision.grasp == "Top-Vert-Grip"


def test_an_unseen_look_rules_out_everything_so_it_is_ignored() -> None:
    session = _session(_cans(), Appearance(False, 100.0, 1.0))  # an 11 in box
    assert session.appearance_ignored and len(session.unlike_rows()) == 3
    assert session.candidates == ("can/lying", "can/upright", "tumbler/lying")


def test_descriptions_without_appearance_are_never_ruled_out() -> None:
    old = [ObjectDescription(d.object_id, d.grasp, d.grasp_position, d.observations) for d in _cans()]
    with_look = _session(old, LYING_CAN)
    without = _session(old, None)
    assert with_look.candidates == without.candidates == ("can/lying", "can/upright", "tumbler/lying")
    assert with_look.decide() == without.decide()
    assert not with_look.appearance_ignored


def test_the_learned_description_keeps_the_appearance_until_the_object_changes() -> None:
    session = _session(_cans(), LYING_CAN)
    session.record({"Width-Degree-5°": 25.0}, P(6, 0))
    assert session.description("learned/x", "Top-Vert-Grip", P(6, 0)).appearance == LYING_CAN
    session.grasp_failed("Top-Vert-Grip", side_effects=True, changed=True)  # knocked over: looks different now
    assert session.appearance is None
    assert session.candidates == ("can/lying", "can/upright", "tumbler/lying")


def test_the_tolerance_is_two_pixels_of_the_shipped_camera() -> None:
    assert AXIS_TOLERANCE_IN == pytest.approx(2 * 0.8)
