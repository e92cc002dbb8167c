"""The criterion registry: every entry's formula on hand-worked values, its help, and
the checks on its parameters."""

from __future__ import annotations

import math

import pytest

from learner.choosing.criteria import CRITERIA, DEFAULT_CRITERION, criterion

# (name, gain in bits, cost in s, expected score), worked by hand from each formula.
HAND_WORKED = [
    ("cs-id3", 1.0, 10.0, 0.1),  # 1^2 / 10
    ("cs-id3", 2.0, 8.0, 0.5),  # 2^2 / 8
    ("id3", 0.7, 100.0, 0.7),  # the gain, whatever the cost
    ("id3-cost-ties", 0.7, 100.0, 0.7),  # the same formula; only its ties differ
    ("idx", 1.0, 10.0, 0.1),  # 1 / 10
    ("idx", 2.0, 8.0, 0.25),  # 2 / 8
    ("eg2", 1.0, 10.0, 1 / 11),  # (2^1 - 1) / (10 + 1)^1, the default w = 1
    ("eg2", 2.0, 3.0, 3 / 4),  # (2^2 - 1) / (3 + 1)^1
    # the refined forms keep their base's formula; what changes is the (I, C) it is given
    ("cs-id3-joint", 2.0, 8.0, 0.5),
    ("cs-id3-lookahead", 2.0, 8.0, 0.5),
    ("idx-joint", 2.0, 8.0, 0.25),
    ("idx-lookahead", 2.0, 8.0, 0.25),
    ("eg2-joint", 2.0, 3.0, 3 / 4),
    ("eg2-lookahead", 2.0, 3.0, 3 / 4),
    # a rollout ranks its rule's best few by expected cost; the formula is its rule's
    ("cs-id3-rollout", 2.0, 8.0, 0.5),
    ("idx-rollout", 2.0, 8.0, 0.25),
    # the failure-priced forms keep I^2 / C; what changes is the C a grasp test is given
    ("cs-id3-failure", 2.0, 8.0, 0.5),
    ("cs-id3-failure-rollout", 2.0, 8.0, 0.5),
    ("cs-id3-failure-search", 2.0, 8.0, 0.5),
    ("cs-id3-failure-search-every-row", 2.0, 8.0, 0.5),
]


def test_every_entry_is_hand_worked_and_documented() -> None:
    assert {name for name, *_ in HAND_WORKED} == set(CRITERIA)
    assert DEFAULT_CRITERION == "cs-id3-failure" and DEFAULT_CRITERION in CRITERIA  # chosen from the noisy data
    for name, spec in CRITERIA.items():
        assert spec.name == name and spec.formula and spec.help and "\n" not in spec.help
        assert all(p.help and p.check(p.default) == p.default for p in spec.parameters)


@pytest.mark.parametrize(("name", "gain", "cost", "expected"), HAND_WORKED)
def test_scores_match_the_formula(name: str, gain: float, cost: float, expected: float) -> None:
    assert criterion(name).score(gain, cost) == pytest.approx(expected)
    assert CRITERIA[name].build().score(gain, cost) == pytest.approx(expected)


def test_cost_sensitivity_flags() -> None:
    assert {n for n, s in CRITERIA.items() if not s.cost_sensitive} == {"id3", "id3-cost-ties"}
    assert criterion("id3").cost_sensitive is False and criterion("cs-id3").cost_sensitive is True


def test_how_each_entry_chooses_besides_its_formula() -> None:
    """Only id3 leaves ties and * slots to chance; every cost-sensitive base has a joint
    and a lookahead form (the lookahead one scores by joint gain too); cs-id3 and idx
    also have a rollout; the default is the plain I^2 / C."""
    chance = {n for n, s in CRITERIA.items() if s.cost_blind_choices}
    joint = {n for n, s in CRITERIA.items() if s.joint_gain}
    ahead = {n for n, s in CRITERIA.items() if s.lookahead}
    assert chance == {"id3"}
    assert joint == {"cs-id3-joint", "cs-id3-lookahead", "idx-joint", "idx-lookahead", "eg2-joint", "eg2-lookahead"}
    assert ahead == {"cs-id3-lookahead", "idx-lookahead", "eg2-lookahead"}
    # a rollout finishes with its base rule itself: plain gain, no lookahead inside
    assert {n for n, s in CRITERIA.items() if s.rollout} == {"cs-id3-rollout", "idx-rollout", "cs-id3-failure-rollout",
                                                             "cs-id3-failure-search",
                                                             "cs-id3-failure-search-every-row"}
    rolled = criterion("idx-rollout")
    assert rolled.rollout and not (rolled.joint_gain or rolled.lookahead or rolled.cost_blind_choices
                                   or rolled.grasp_paid_on_failure or rolled.rollout_follows_walk)
    # only the failure-priced forms price a grasp test by its failure, and only their
    # rollout follows the walk
    assert {n for n, s in CRITERIA.items() if s.grasp_paid_on_failure} == {"cs-id3-failure", "cs-id3-failure-rollout",
                                                                           "cs-id3-failure-search",
                                                                           "cs-id3-failure-search-every-row"}
    assert {n for n, s in CRITERIA.items() if s.rollout_follows_walk} == {"cs-id3-failure-rollout",
                                                                          "cs-id3-failure-search",
                                                                          "cs-id3-failure-search-every-row"}
    # only the searches' rollouts search the nodes below a candidate, and only the last
    # lets carried rows decide a leaf: every other criterion keeps the learner's leaf rule
    searching = {n for n, s in CRITERIA.items() if s.rollout_searches}
    assert searching == {"cs-id3-failure-search", "cs-id3-failure-search-every-row"}
    assert {n for n, s in CRITERIA.items() if s.leaf_every_row} == {"cs-id3-failure-search-every-row"}
    built = criterion("eg2-lookahead", w=2.0)
    assert (built.joint_gain, built.lookahead, built.cost_blind_choices) == (True, True, False)
    assert built.score(2.0, 3.0) == pytest.approx(3 / 16)  # eg2's w reaches its refined forms
    default = criterion(DEFAULT_CRITERION)
    # the default is cs-id3's formula with grasps tried as features priced by their failure share, and nothing else
    assert default.grasp_paid_on_failure and default.cost_sensitive
    assert not (default.cost_blind_choices or default.joint_gain or default.lookahead or default.rollout
                or default.rollout_follows_walk or default.leaf_every_row)


def test_a_free_test_beats_every_paid_one() -> None:
    for name in ("cs-id3", "idx"):
        assert criterion(name).score(0.5, 0.0) == math.inf
        assert criterion(name).score(0.0, 0.0) == 0.0


def test_eg2_w_weighs_the_cost() -> None:
    assert criterion("eg2", w=0.0).score(1.0, 10.0) == pytest.approx(1.0)  # (2 - 1) / 11^0: cost ignored
    assert criterion("eg2", w=1.0).score(1.0, 10.0) == pytest.approx(1 / 11)
    assert criterion("eg2", w=2.0).score(2.0, 3.0) == pytest.approx(3 / 16)
    assert criterion("eg2", 2.0).score(2.0, 3.0) == pytest.approx(3 / 16)  # by position, in declared order
    # w = 0 ranks like cost-blind gain: a costly good test beats a cheap weak one.
    cheap_weak, costly_good = (0.5, 1.0), (1.0, 500.0)
    assert criterion("eg2", w=0.0).score(*costly_good) > criterion("eg2", w=0.0).score(*cheap_weak)
    assert criterion("eg2", w=1.0).score(*costly_good) < criterion("eg2", w=1.0).score(*cheap_weak)


@pytest.mark.parametrize("w", [math.nan, math.inf, -math.inf, -0.5])
def test_eg2_w_must_be_finite_and_not_negative(w: float) -> None:
    with pytest.raises(ValueError, match="w must be a finite number >= 0"):
        criterion("eg2", w=w)


def test_parameters_are_checked_by_name() -> None:
    with pytest.raises(ValueError, match="eg2 has no parameter v"):
        criterion("eg2", v=1.0)
    with pytest.raises(ValueError, match="cs-id3 has no parameter w .*none"):
        criterion("cs-id3", w=1.0)
    with pytest.raises(ValueError, match="given twice"):
        criterion("eg2", 1.0, w=1.0)
    with pytest.raises(ValueError, match="takes 1 parameter"):
        criterion("eg2", 1.0, 2.0)
    with pytest.raises(ValueError, match=r"unknown criterion 'c4.5' \(choose from: cs-id3, id3, id3-cost-ties, idx, eg2, "
                       r"cs-id3-joint, cs-id3-lookahead, idx-joint, idx-lookahead, eg2-joint, eg2-lookahead, "
                       r"cs-id3-rollout, idx-rollout, cs-id3-failure, cs-id3-failure-rollout, cs-id3-failure-search, "
                       r"cs-id3-failure-search-every-row\)"):
        criterion("c4.5")
