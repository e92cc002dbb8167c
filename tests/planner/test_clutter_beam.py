"""The beam check (docs/planner.md "Clutter"): a neighbour in the sound's way, or within
an inch of it, makes a sensing position unusable; one beside or behind does not."""

from __future__ import annotations

import math

from hypothesis import given, strategies as st

from planner.positions import BEAM_MARGIN_IN, _convex_gap, _convex_hull, beam_blockers, beam_corridor, neighbours
from planner.vision import Region


def square(x: float, y: float, side: float) -> Region:
    h = side / 2
    polygon = ((x - h, y - h), (x + h, y - h), (x + h, y + h), (x - h, y + h))
    return Region(polygon, (x, y), int(side * side / 0.64), 0.0, False, side, side)


TARGET = square(0.0, 0.0, 4.0)  # faces at x = ±2, y = ±2


def test_corridor_spans_sonar_to_far_face() -> None:
    # position (10, 0): sonar at x = 2 + 10 = 12 on the +x ray, the corridor 4 in wide
    hull = beam_corridor(TARGET, 10.0, 0.0)
    assert math.isclose(hull[:, 0].max(), 12.0) and math.isclose(hull[:, 0].min(), -2.0)
    assert math.isclose(hull[:, 1].max(), 2.0) and math.isclose(hull[:, 1].min(), -2.0)


def test_neighbour_between_sonar_and_object_blocks() -> None:
    between = square(7.0, 0.0, 2.0)
    assert beam_blockers(TARGET, 10.0, 0.0, [TARGET, between]) == [between]


def test_neighbour_half_an_inch_beside_the_corridor_blocks() -> None:
    # its near edge at y = 2.5: 0.5 in from the corridor's side, within the 1 in margin
    beside = square(7.0, 3.5, 2.0)
    assert BEAM_MARGIN_IN == 1.0
    assert beam_blockers(TARGET, 10.0, 0.0, [beside]) == [beside]


def test_neighbour_two_inches_beside_or_behind_is_clear() -> None:
    beside = square(7.0, 5.0, 2.0)  # near edge at y = 4: 2 in from the corridor
    assert beam_blockers(TARGET, 10.0, 0.0, [beside]) == []
    # from the other side, (10, 180), the sonar is at x = -12: the neighbour at x 6..8 is behind
    assert beam_blockers(TARGET, 10.0, 180.0, [square(7.0, 0.0, 2.0)]) == []


@given(st.floats(0.0, 30.0), st.floats(0.0, 360.0, exclude_max=True), st.floats(5.0, 40.0))
def test_a_neighbour_farther_than_the_whole_beam_never_blocks(distance: float, orientation: float,
                                                               extra: float) -> None:
    # the corridor lies within (face + distance + half width) of the centroid: 2*sqrt(2) + d + 2
    reach = 2 * math.sqrt(2) + distance + 2.0 + BEAM_MARGIN_IN + 1.0 + extra
    far = square(reach + 1.0, 0.0, 2.0)
    assert beam_blockers(TARGET, distance, orientation, [far]) == []


def test_neighbours_leave_out_the_object_seen_anew() -> None:
    # 0.5 in off the centroid: the object itself in a newer image; 1.5 in off: another one
    anew, other = square(0.3, 0.4, 4.0), square(0.9, 1.2, 2.0)
    assert neighbours(TARGET, [TARGET, anew, other], 1.0) == [other]
    assert neighbours(TARGET, [TARGET, anew, other], 2.0) == []


def test_a_neighbour_off_the_corridors_corner_is_judged_by_its_gap_not_its_box() -> None:
    # the corridor from (10, 0) spans x -2..12, y -2..2; a 2 in square whose near corner
    # lies 0.8 in past the corridor's corner on both axes (its box 0.8 in off each side,
    # within the margin) is 0.8 * sqrt(2) = 1.13 in from it: beyond the margin, no blocker
    corner = square(13.0 + 0.8, 3.0 + 0.8, 2.0)
    assert beam_blockers(TARGET, 10.0, 0.0, [corner]) == []
    # its near corner 0.6 in past on both axes: 0.85 in away, a blocker
    assert beam_blockers(TARGET, 10.0, 0.0, [square(13.6, 3.6, 2.0)]) != []


@given(st.floats(0.0, 40.0), st.floats(0.0, 360.0, exclude_max=True),
       st.lists(st.tuples(st.floats(-50.0, 50.0), st.floats(-50.0, 50.0), st.floats(0.5, 8.0)), max_size=6))
def test_the_box_shortcut_never_changes_which_neighbours_block(distance: float, orientation: float,
                                                              squares: list[tuple[float, float, float]]) -> None:
    # every neighbour judged by its gap to the corridor alone, as before the shortcut
    others = [square(x, y, side) for x, y, side in squares]
    corridor = beam_corridor(TARGET, distance, orientation)
    by_gap = [o for o in others if o.centroid != TARGET.centroid
              and _convex_gap(corridor, _convex_hull(o.polygon_array())) <= BEAM_MARGIN_IN]
    assert beam_blockers(TARGET, distance, orientation, others) == by_gap
