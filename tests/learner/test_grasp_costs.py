"""Grasp costs learned from what attempts cost (docs/method.md §5.7, issue 15 §6).

The HERO's file prices Front-Wrap at 60 s (+30 s side-effect penalty: 90 s a failure)
and Top-Pinch at 63 s (+40 s: 103 s). A grasp's learned cost is the Bayesian mean of
its attempts with the file's cost as a prior worth 3 attempts.
"""

from __future__ import annotations

import math
import sqlite3

import pytest
from hypothesis import given
from hypothesis import strategies as st

from learner.choosing.criteria import criterion
from learner.choosing.leaf import AmbiguousLeaf
from learner.choosing.matrix import DescriptionMatrix
from learner.choosing.node import Context, Node
from learner.choosing.selection import rank
from learner.costs import GraspCostRecord, ModelMoveCost, bayesian_mean, with_learned_grasp_costs
from learner.library.store import LibraryStore
from learner.runtime import RecognitionSession
from learner.service.local import LocalLearner
from tests.learner.fixtures import ANY, P, desc, hero


def test_the_bayesian_mean_counts_the_prior_as_weight_attempts() -> None:
    assert bayesian_mean(90.0, 0.0, 0) == 90.0  # no attempt: the file's cost
    assert bayesian_mean(90.0, 500.0, 2) == pytest.approx((3 * 90 + 500) / 5)  # 154
    assert bayesian_mean(90.0, 500.0, 2, weight=0) == pytest.approx(250.0)  # no prior: the plain mean


@given(st.floats(0, 1000), st.lists(st.floats(0, 1000), min_size=1, max_size=30))
def test_the_learned_cost_lies_between_the_prior_and_what_attempts_cost(prior: float, costs: list[float]) -> None:
    learned = bayesian_mean(prior, sum(costs), len(costs))
    mean = sum(costs) / len(costs)
    assert min(prior, mean) - 1e-6 <= learned <= max(prior, mean) + 1e-6


def test_a_record_adds_holds_and_failures_apart() -> None:
    r = GraspCostRecord("Front-Wrap").with_attempt(240, True).with_attempt(300, False).with_attempt(320, False)
    assert (r.successes, r.success_s, r.failures, r.failure_s, r.attempts) == (1, 240, 2, 620, 3)
    for bad in (math.nan, math.inf, -1.0):
        with pytest.raises(ValueError, match="Front-Wrap"):
            r.with_attempt(bad, True)


def test_learned_knowledge_prices_a_hold_and_a_failure_by_their_own_attempts() -> None:
    k = hero()
    wrap = GraspCostRecord("Front-Wrap", successes=1, success_s=240.0, failures=3, failure_s=900.0)
    cheap = GraspCostRecord("Top-Pinch", successes=0, success_s=0.0, failures=3, failure_s=30.0)
    learned = with_learned_grasp_costs(k, [wrap, cheap, GraspCostRecord("Not-A-Grasp", 1, 5.0)])
    # Front-Wrap: a hold (3 x 60 + 240) / 4 = 105 s; a failure (3 x 90 + 900) / 6 = 195 s
    assert learned.grasp("Front-Wrap").time_s == pytest.approx(105.0)
    assert learned.grasp("Front-Wrap").feature_cost_s == pytest.approx(195.0)
    # Top-Pinch: no hold, its time stays 63; a failure (3 x 103 + 30) / 6 = 56.5 s is under
    # its own time, so the penalty is 0 and a failure is priced 63 s
    assert learned.grasp("Top-Pinch").time_s == pytest.approx(63.0)
    assert learned.grasp("Top-Pinch").side_effect_penalty_s == 0.0
    assert learned.grasp("Top-Pinch").feature_cost_s == pytest.approx(63.0)
    assert learned.grasp("Front-Pinch") == k.grasp("Front-Pinch")  # no record: the file's
    assert with_learned_grasp_costs(k, []).grasping == k.grasping


def _three_wraps_and_a_tumbler() -> list:
    return [
        desc("cup", "Front-Wrap", ("Height-Degree-5°", P(6, ANY), 30)),
        desc("soda-can", "Front-Wrap", ("Height-Degree-5°", P(6, ANY), 40)),
        desc("tennis-can", "Front-Wrap", ("Height-Degree-5°", P(6, ANY), 70)),
        desc("tumbler", "Top-Pinch", ("Height-Degree-5°", P(6, ANY), 60)),
    ]


def test_a_grasp_learned_dear_is_no_longer_tried_as_a_feature() -> None:
    # cs-id3-failure with the file: Front-Wrap fails on the tumbler only, 1/4 x 90 = 22.5 s,
    # and beats the 42 s sweep (both gain all of H(3/4, 1/4)).
    lib = _three_wraps_and_a_tumbler()
    k = hero()
    filed = Context(DescriptionMatrix(lib, k), criterion("cs-id3-failure"), ModelMoveCost(k.move))
    assert str(rank(Node.root(4), P(6, 0), filed, {})[0].test) == "Front-Wrap(6,*)"
    # learned: four failures of 300 s each, (3 x 90 + 1200) / 7 = 210 s a failure, so
    # 1/4 x 210 = 52.5 s, dearer than the sweep
    learned = with_learned_grasp_costs(k, [GraspCostRecord("Front-Wrap", failures=4, failure_s=1200.0)])
    assert learned.grasp("Front-Wrap").feature_cost_s == pytest.approx(210.0)
    ctx = Context(DescriptionMatrix(lib, learned), criterion("cs-id3-failure"), ModelMoveCost(learned.move))
    ranked = rank(Node.root(4), P(6, 0), ctx, {})
    assert str(ranked[0].test) == "Height-Degree-5°(6,*)"
    wrap = next(s for s in ranked if str(s.test) == "Front-Wrap(6,*)")
    assert wrap.scored_on[1] == pytest.approx(52.5)


def test_an_ambiguous_leaf_tries_the_grasp_learned_cheaper_first() -> None:
    # the file: Front-Wrap 90 s before Top-Pinch 103 s; learned: Front-Wrap's failures
    # cost 400 s each, (3 x 90 + 2 x 400) / 5 = 214 s, so Top-Pinch goes first
    lib = [desc("a", "Front-Wrap", ("Width", P(6, 0), 3)), desc("b", "Top-Pinch", ("Width", P(6, 0), 3.2))]
    k = hero()
    learned = with_learned_grasp_costs(k, [GraspCostRecord("Front-Wrap", failures=2, failure_s=800.0)])
    order = []
    for knowledge in (k, learned):
        s = RecognitionSession.for_library(lib, knowledge, criterion("cs-id3"), ModelMoveCost(knowledge.move),
                                           P(6, 0), grasps_as_features=False)
        leaf = s.decide()
        assert isinstance(leaf, AmbiguousLeaf)
        order.append([o.grasp for o in leaf.options])
    assert order == [["Front-Wrap", "Top-Pinch"], ["Top-Pinch", "Front-Wrap"]]


def test_the_store_keeps_running_totals_and_an_old_store_opens_unchanged(tmp_path) -> None:  # noqa: ANN001
    path = tmp_path / "library.sqlite"
    with LibraryStore(path) as store:
        store.add([desc("cup", "Front-Wrap", ("Width", P(6, 0), 3))])
    with LibraryStore(path) as store:  # opened again, nothing recorded: no table is made
        assert store.grasp_cost_records() == []
    tables = {r[0] for r in sqlite3.connect(path).execute("SELECT name FROM sqlite_master WHERE type='table'")}
    assert "grasp_costs" not in tables
    with LibraryStore(path) as store:
        store.record_grasp_attempts([("Front-Wrap", 60.0, True), ("Front-Wrap", 150.0, False)])
        store.record_grasp_attempts([("Front-Wrap", 50.0, False), ("Top-Pinch", 63.0, True)])
    with LibraryStore(path) as store:
        assert store.grasp_cost_records() == [GraspCostRecord("Front-Wrap", 1, 60.0, 2, 200.0),
                                              GraspCostRecord("Top-Pinch", 1, 63.0, 0, 0.0)]
        assert [d.object_id for d in store.descriptions()] == ["cup"]


def test_the_local_learner_records_costs_without_a_new_library_version(tmp_path) -> None:  # noqa: ANN001
    with LocalLearner(tmp_path / "l.sqlite", [desc("cup", "Front-Wrap", ("Width", P(6, 0), 3))]) as learner:
        version = learner.version()
        learner.record_grasp_attempts([("Front-Wrap", 70.0, True)])
        assert learner.grasp_costs() == [GraspCostRecord("Front-Wrap", 1, 70.0)]
        assert learner.version() == version


def test_a_bad_attempt_writes_nothing_of_its_batch(tmp_path) -> None:  # noqa: ANN001
    with LibraryStore(tmp_path / "library.sqlite") as store:
        store.record_grasp_attempts([("Front-Wrap", 60.0, True)])
        with pytest.raises(ValueError, match="Front-Wrap"):
            store.record_grasp_attempts([("Top-Pinch", 63.0, True), ("Front-Wrap", math.nan, False)])
        assert store.grasp_cost_records() == [GraspCostRecord("Front-Wrap", 1, 60.0)]


@pytest.mark.parametrize(("attempt", "why"), [
    (("Top-Pinch", 6.3, True), None),  # 63 s / 10: the fastest believable
    (("Top-Pinch", 630.0, True), None),  # 63 s x 10
    (("Top-Pinch", 630.1, True), "630.1 s for a successful Top-Pinch is implausible: its time_s is 63 s, so 6.3 to 630 s"),
    (("Top-Pinch", 6.2, False), "6.2 s for a failed Top-Pinch is implausible"),
    # a failure may also cost the sensing a knock-over voided: at most the seven procedures
    # (100+45+76+42+70+105+84 = 522 s) ten times over: 630 + 5,220 = 5,850 s
    (("Top-Pinch", 5850.0, False), None),
    (("Top-Pinch", 86400.0, False), "86400 s for a failed Top-Pinch is implausible: its time_s is 63 s, so 6.3 to 5850 s"),
    (("Top-Pinch", 0.063, True), "0.063 s for a successful Top-Pinch is implausible"),  # milliseconds taken for seconds
])
def test_the_service_refuses_a_duration_no_grasp_of_this_robot_takes(
        tmp_path, attempt: tuple[str, float, bool], why: str | None) -> None:  # noqa: ANN001
    with LocalLearner(tmp_path / "l.sqlite", [desc("cup", "Front-Wrap", ("Width", P(6, 0), 3))],
                      knowledge=hero()) as learner:
        if why is None:
            learner.record_grasp_attempts([attempt])
            assert learner.grasp_costs()[0].attempts == 1
        else:
            with pytest.raises(ValueError, match=f"grasp costs not recorded: attempts\\[1\\]: {why}"):
                learner.record_grasp_attempts([("Front-Wrap", 60.0, True), attempt])
            assert learner.grasp_costs() == []  # the batch is refused whole
