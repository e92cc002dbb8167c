"""The exact search's accounting of noise: a sensing value lost with the chance ``lost``.

A lost value is paid for and tells nothing: the search stays at the node, the test taken
(the session's reselection). Worked by hand on a two-description library, checked for
the criterion's parameter, and, on random libraries, never below the noise-free search
and equal to it at ``lost = 0``."""

from __future__ import annotations

import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from learner.choosing.criteria import CRITERIA, criterion
from learner.choosing.exact import ExactSearch
from learner.choosing.node import Context
from learner.optimum import optimal_cost
from learner.position import Position
from learner.runtime import RecognitionSession
from tests.learner.fixtures import P
from tests.learner.test_optimum import EST, SLOTS, d, libraries, matrix

EXACT = "cs-id3-failure-exact"
# a and b part at the sweep W(20,0) (10 s, made where the robot stands) or by grasp A tried
# as a feature from (20,0): 14 in back to (6,0) at 2 s/in and A's 90 s, paid when it fails
# (for b, half the time): 1/2 * (28 + 90) = 59
TWO = [d("a", "A", ("W", P(20, 0), 10)), d("b", "B", ("W", P(20, 0), 30))]


def _searched(library: list, start: Position, lost: float, grasps: bool = True) -> float:
    m = matrix(library, grasps)
    search = ExactSearch(m, EST, Context(m, criterion(EXACT, lost=lost), EST), lost=lost)
    n = len(library)
    return search.expected(search.node_id(tuple(range(n))), (1.0 / n,) * n, search.place(start), 0, 0)


@pytest.mark.parametrize(("lost", "expected"), [
    (0.0, 10.0),  # the sweep, noise-free: the optimum
    (0.5, 10 + 0.5 * 59),  # the sweep; lost half the time, then A as a feature
    (0.9, 59.0),  # the sweep would cost 10 + 0.9 * 59 = 63.1: A as a feature first
])
def test_a_lost_value_is_paid_and_the_node_tested_again(lost: float, expected: float) -> None:
    assert _searched(TWO, P(20, 0), lost) == pytest.approx(expected)


def test_the_session_grasps_first_where_a_sweep_is_likely_lost() -> None:
    m = matrix(TWO)
    first = {}
    for lost in (0.0, 0.9):
        session = RecognitionSession(m, criterion(EXACT, lost=lost), EST, P(20, 0))
        first[lost] = str(session.decide().test)
    assert first == {0.0: "W(20,0)", 0.9: "A(6,0)"}


def test_lost_is_a_setting_of_the_exact_criterion_not_of_its_formula() -> None:
    spec = CRITERIA[EXACT]
    assert [p.name for p in spec.parameters] == ["lost"]
    assert criterion(EXACT).setting("lost") == 0.0
    built = criterion(EXACT, lost=0.25)
    assert built.setting("lost") == 0.25
    assert built.score(1.0, 2.0) == criterion("cs-id3-failure").score(1.0, 2.0)  # I^2 / C, lost not in it
    with pytest.raises(ValueError, match="lost must be a finite number >= 0 and < 1, got 1"):
        criterion(EXACT, lost=1.0)
    with pytest.raises(ValueError, match="lost must be"):
        criterion(EXACT, lost=-0.1)


def test_the_search_refuses_a_certain_loss() -> None:
    m = matrix(TWO)
    with pytest.raises(ValueError, match=r"lost must be in \[0, 1\), got 1.0"):
        ExactSearch(m, EST, Context(m, criterion(EXACT), EST), lost=1.0)


@settings(max_examples=30, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(libraries(SLOTS), st.booleans(), st.sampled_from([0.1, 0.4]))
def test_noise_never_makes_recognition_cheaper(library: list, grasps: bool, lost: float) -> None:
    start = P(20, 0)
    clean = _searched(library, start, 0.0, grasps)
    assert clean == pytest.approx(optimal_cost(matrix(library, grasps), EST, start))
    assert _searched(library, start, lost, grasps) >= clean - 1e-9
