"""The experiments' criteria: the product's and the ablations, every rule the paper's
experiment measured before the product kept only some (docs/optimum.md, "Which criteria
the product offers"), found by name, in the results page's order, and run by the
studies."""

from __future__ import annotations

import dataclasses
from pathlib import Path

import pytest

from experiments import study_execution, worker
from experiments.ablations import ABLATIONS, MEASURED, criterion
from experiments.config import ExperimentConfig
from experiments.study_optimum import SHIPPED, OptimumJob
from learner.choosing.criteria import CRITERIA, Traits
from learner.position import Position
from robot_profile import DEFAULT_PROFILE, load_profile

# The registry's names before the ablations left it, and the one added since, in the order docs/results.md lists
# them; the traits each adds to its formula.
EVERY_OLD_NAME = {
    "cs-id3": set(), "id3": {"cost_blind_choices"}, "id3-cost-ties": set(), "idx": set(), "eg2": set(),
    "cs-id3-joint": {"joint_gain"}, "cs-id3-lookahead": {"joint_gain", "lookahead"},
    "idx-joint": {"joint_gain"}, "idx-lookahead": {"joint_gain", "lookahead"},
    "eg2-joint": {"joint_gain"}, "eg2-lookahead": {"joint_gain", "lookahead"},
    "cs-id3-rollout": {"rollout"}, "idx-rollout": {"rollout"},
    "cs-id3-failure": {"grasp_paid_on_failure"},
    "cs-id3-failure-rollout": {"grasp_paid_on_failure", "rollout", "rollout_follows_walk"},
    "cs-id3-failure-search": {"grasp_paid_on_failure", "rollout", "rollout_follows_walk", "rollout_searches"},
    "cs-id3-failure-search-every-row": {"grasp_paid_on_failure", "rollout", "rollout_follows_walk",
                                        "rollout_searches", "leaf_every_row"},
    "cs-id3-failure-exact": {"grasp_paid_on_failure", "rollout", "rollout_follows_walk", "leaf_every_row",
                             "exact_search"},
}


def test_every_old_name_is_measured_with_its_traits() -> None:
    assert list(MEASURED) == list(EVERY_OLD_NAME)
    for name, traits in EVERY_OLD_NAME.items():
        built = criterion(name)
        assert built.name == name
        assert {f.name for f in dataclasses.fields(Traits) if getattr(built, f.name)} == traits, name
    assert criterion("eg2-lookahead", w=2.0).score(2.0, 3.0) == pytest.approx(3 / 16)  # (2^2 - 1) / 4^2
    with pytest.raises(ValueError, match=r"unknown criterion 'c4.5' \(choose from: cs-id3, id3, "):
        criterion("c4.5")


def test_the_ablations_are_the_measured_rules_the_product_does_not_offer() -> None:
    assert set(ABLATIONS).isdisjoint(CRITERIA) and set(MEASURED) == set(ABLATIONS) | set(CRITERIA)
    assert all(MEASURED[name] is spec for name, spec in CRITERIA.items())


def test_the_baselines_run_every_measured_criterion() -> None:
    def config(quick: bool) -> ExperimentConfig:
        return ExperimentConfig(quick=quick, seeds=(0, 1), jobs=1, out=Path("."), command="test")

    assert study_execution.criteria_run(config(False)) == list(MEASURED)
    # a quick run: the paper's rules and the default
    assert study_execution.criteria_run(config(True)) == ["cs-id3", "id3", "id3-cost-ties", "idx", "eg2",
                                                          "cs-id3-failure"]
    planned = {spec.criterion for spec in study_execution.plan(config(False)) if spec.study == "baselines"}
    assert planned == set(MEASURED)


def test_the_optimum_study_walks_every_measured_criterion(monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.setattr(worker, "_PROFILE", [load_profile(DEFAULT_PROFILE)])  # as install_worker does
    # three shipped descriptions: a search small enough for a unit test
    rows = OptimumJob(SHIPPED, Position(24, 0), 8, shipped_descriptions=3).run()
    assert [r.criterion for r in rows] == list(MEASURED)
    assert all(r.error is None and r.ratio >= 1.0 - 1e-9 for r in rows)
