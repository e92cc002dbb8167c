"""The criterion registry: every entry's formula on hand-worked values, its help, and
the checks on its parameters."""

from __future__ import annotations

import dataclasses
import math

import pytest

from learner.choosing.criteria import (CRITERIA, DEFAULT_CRITERION, CriterionSpec, Traits, criterion, with_joint_gain,
                                       with_grasp_paid_on_failure, with_leaf_every_row, with_lookahead, with_rollout,
                                       with_exact_search, with_walk_rollout, with_walk_search)

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
    # a rollout ranks its rule's best few by expected cost; the formula is its rule's
    ("cs-id3-rollout", 2.0, 8.0, 0.5),
    ("idx-rollout", 2.0, 8.0, 0.25),
    # the failure-priced forms keep I^2 / C; what changes is the C a grasp test is given
    ("cs-id3-failure", 2.0, 8.0, 0.5),
    ("cs-id3-failure-search-every-row", 2.0, 8.0, 0.5),
    ("cs-id3-failure-exact", 2.0, 8.0, 0.5),
]

PRODUCT = ["cs-id3", "id3", "id3-cost-ties", "idx", "eg2", "cs-id3-rollout", "idx-rollout", "cs-id3-failure",
           "cs-id3-failure-search-every-row", "cs-id3-failure-exact"]
"""The paper's baselines, the rollouts (cheapest robot time in the execution study), the
default and its opt-in (docs/optimum.md, "Which criteria the product offers")."""


def test_every_entry_is_hand_worked_and_documented() -> None:
    assert list(CRITERIA) == PRODUCT
    assert {name for name, *_ in HAND_WORKED} == set(CRITERIA)
    assert DEFAULT_CRITERION == "cs-id3-failure" and DEFAULT_CRITERION in CRITERIA  # chosen from the noisy data
    for name, spec in CRITERIA.items():
        assert spec.name == name and spec.formula and spec.help and "\n" not in spec.help
        assert all(p.help and p.check(p.default) == p.default for p in spec.parameters)


@pytest.mark.parametrize(("name", "gain", "cost", "expected"), HAND_WORKED)
def test_scores_match_the_formula(name: str, gain: float, cost: float, expected: float) -> None:
    assert criterion(name).score(gain, cost) == pytest.approx(expected)
    assert CRITERIA[name].build().score(gain, cost) == pytest.approx(expected)


@pytest.mark.parametrize(("form", "suffix"), [(with_joint_gain, "-joint"), (with_lookahead, "-lookahead"),
                                              (with_rollout, "-rollout"), (with_grasp_paid_on_failure, "-failure")])
@pytest.mark.parametrize(("base", "gain", "cost", "expected"), [("cs-id3", 2.0, 8.0, 0.5), ("idx", 2.0, 8.0, 0.25),
                                                                ("eg2", 2.0, 3.0, 3 / 4)])
def test_a_built_form_keeps_its_base_formula(form, suffix: str, base: str, gain: float, cost: float,  # noqa: ANN001
                                             expected: float) -> None:
    # what a trait changes is the (I, C) the formula is given, not the formula
    spec = form(CRITERIA[base])
    assert spec.name == base + suffix and spec.formula.startswith(CRITERIA[base].formula + ", ")
    assert spec.help and "\n" not in spec.help and spec.parameters == CRITERIA[base].parameters
    assert spec.build().score(gain, cost) == pytest.approx(expected)


def test_cost_sensitivity_flags() -> None:
    assert {n for n, s in CRITERIA.items() if not s.cost_sensitive} == {"id3", "id3-cost-ties"}
    assert criterion("id3").cost_sensitive is False and criterion("cs-id3").cost_sensitive is True


def _traits(spec: CriterionSpec) -> set[str]:
    return {f.name for f in dataclasses.fields(Traits) if getattr(spec, f.name)}


def test_how_each_entry_chooses_besides_its_formula() -> None:
    """Only id3 leaves ties and * slots to chance; cs-id3 and idx have a rollout; the
    default is the plain I^2 / C with grasps priced by their failure, and its opt-in
    adds the walk's search and the leaf every row decides."""
    assert {n: _traits(s) for n, s in CRITERIA.items()} == {
        "cs-id3": set(), "id3": {"cost_blind_choices"}, "id3-cost-ties": set(), "idx": set(), "eg2": set(),
        # a rollout finishes with its base rule itself: plain gain, no lookahead inside
        "cs-id3-rollout": {"rollout"}, "idx-rollout": {"rollout"},
        "cs-id3-failure": {"grasp_paid_on_failure"},
        "cs-id3-failure-search-every-row": {"grasp_paid_on_failure", "rollout", "rollout_follows_walk",
                                            "rollout_searches", "leaf_every_row"},
        # exact below a few descriptions, the walk rollout above; it stops where the search does
        "cs-id3-failure-exact": {"grasp_paid_on_failure", "rollout", "rollout_follows_walk", "leaf_every_row",
                                 "exact_search"},
    }


def test_each_builder_adds_its_traits_and_no_other() -> None:
    base, priced = CRITERIA["cs-id3"], CRITERIA["cs-id3-failure"]
    assert _traits(with_joint_gain(base)) == {"joint_gain"}
    assert _traits(with_lookahead(base)) == {"joint_gain", "lookahead"}  # the lookahead scores by joint gain too
    assert _traits(with_rollout(base)) == {"rollout"}
    assert _traits(with_grasp_paid_on_failure(base)) == {"grasp_paid_on_failure"}
    walked, searched = with_walk_rollout(priced), with_walk_search(priced)
    assert (walked.name, _traits(walked)) == ("cs-id3-failure-rollout",
                                              {"grasp_paid_on_failure", "rollout", "rollout_follows_walk"})
    assert (searched.name, _traits(searched)) == ("cs-id3-failure-search", _traits(walked) | {"rollout_searches"})
    # the product's opt-in is exactly these builders composed
    assert with_leaf_every_row(searched) == CRITERIA["cs-id3-failure-search-every-row"]
    assert with_exact_search(priced) == CRITERIA["cs-id3-failure-exact"]
    assert with_grasp_paid_on_failure(base) == priced
    built = with_lookahead(CRITERIA["eg2"]).build(w=2.0)
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
                       r"cs-id3-rollout, idx-rollout, cs-id3-failure, cs-id3-failure-search-every-row, "
                       r"cs-id3-failure-exact\)"):
        criterion("c4.5")
    with pytest.raises(ValueError, match=r"unknown criterion 'cs-id3-joint' \(choose from: cs-id3, "):
        criterion("cs-id3-joint")  # an ablation: the experiments' (experiments/ablations.py), not the product's
