"""Grasp costs learned from what attempts cost (docs/method.md §5.7).

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
from tests.learner.fixtures import P, desc, hero, three_wraps_and_a_tumbler


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



def test_a_grasp_learned_dear_is_no_longer_tried_as_a_feature() -> None:
    # cs-id3-failure with the file: Front-Wrap fails on the tumbler only, 1/4 x 90 = 22.5 s,
    # and beats the 42 s sweep (both gain all of H(3/4, 1/4)).
    lib = three_wraps_and_a_tumbler()
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


def test_a_record_capped_keeps_each_kinds_mean_and_the_share_that_held() -> None:
    # 300 attempts, 240 held at 60 s each, 60 failed at 90 s each, capped at 200:
    # 160 held and 40 failed, at the same 60 s and 90 s means
    record = GraspCostRecord("Front-Wrap", 240, 240 * 60.0, 60, 60 * 90.0)
    capped = record.capped(200)
    assert (capped.successes, capped.failures) == (160, 40)
    assert capped.success_s == pytest.approx(160 * 60.0) and capped.failure_s == pytest.approx(40 * 90.0)
    assert record.capped(300) is record  # no heavier than the cap: unchanged


@given(st.integers(0, 5000), st.integers(0, 5000), st.floats(0, 86_400), st.floats(0, 86_400), st.integers(1, 500))
def test_a_capped_record_weighs_at_most_the_cap_and_keeps_its_means(
        successes: int, failures: int, success_mean: float, failure_mean: float, cap: int) -> None:
    record = GraspCostRecord("g", successes, successes * success_mean, failures, failures * failure_mean)
    capped = record.capped(cap)
    assert capped.attempts == min(record.attempts, cap)
    if capped.successes:
        assert capped.success_s / capped.successes == pytest.approx(success_mean)
    if capped.failures:
        assert capped.failure_s / capped.failures == pytest.approx(failure_mean)


def test_a_robot_that_floods_weighs_no_more_than_its_cap_in_the_fleets_price(tmp_path) -> None:  # noqa: ANN001
    """r1 records 1,000 Front-Wrap holds at 600 s (ten times the file's 60 s), r2 ten at
    60 s. Uncapped the fleet's mean would be (600,000 + 600) / 1,010 = 594.6 s; r1
    weighs ROBOT_WEIGHT = 200 attempts, so it is (200 x 600 + 10 x 60) / 210 = 574.3 s,
    and r2's next hold counts as 1 in 211, not 1 in 1,011. An unnamed record is one
    more robot ('')."""
    with LibraryStore(tmp_path / "library.sqlite") as store:
        for batch in range(10):
            store.record_grasp_attempts([("Front-Wrap", 600.0, True)] * 100, key=f"r1/{batch}", robot="r1")
        store.record_grasp_attempts([("Front-Wrap", 60.0, True)] * 10, key="r2/0", robot="r2")
        [fleet] = store.grasp_cost_records()
        assert (fleet.successes, fleet.failures) == (210, 0)
        assert fleet.success_s / fleet.successes == pytest.approx((200 * 600 + 10 * 60) / 210)
        store.record_grasp_attempts([("Front-Wrap", 60.0, True)] * 5)  # unnamed
        assert store.grasp_cost_records()[0].successes == 215
        by_robot = dict(((r, n) for r, n in store._db.execute(
            "SELECT robot, successes FROM grasp_costs_by_robot ORDER BY robot")))
        assert by_robot == {"": 5, "r1": 200, "r2": 10}


def test_a_store_with_totals_from_before_robots_keeps_them_as_the_unnamed_robots(tmp_path) -> None:  # noqa: ANN001
    path = tmp_path / "library.sqlite"
    with LibraryStore(path) as store:
        store.add([desc("cup", "Front-Wrap", ("Width", P(6, 0), 3))])
    db = sqlite3.connect(path)  # as a csl from before robots were named left it
    with db:
        db.execute("CREATE TABLE grasp_costs (grasp TEXT PRIMARY KEY, successes INTEGER NOT NULL, success_s REAL "
                   "NOT NULL, failures INTEGER NOT NULL, failure_s REAL NOT NULL)")
        db.execute("INSERT INTO grasp_costs VALUES ('Front-Wrap', 4, 240.0, 1, 90.0)")
    db.close()
    with LibraryStore(path) as store:
        assert store.grasp_cost_records() == [GraspCostRecord("Front-Wrap", 4, 240.0, 1, 90.0)]  # read as ever
        store.record_grasp_attempts([("Front-Wrap", 60.0, True)], robot="r1")
        assert store.grasp_cost_records() == [GraspCostRecord("Front-Wrap", 5, 300.0, 1, 90.0)]


def test_the_local_learner_refuses_a_robot_name_that_is_not_one_key_chunk(tmp_path) -> None:  # noqa: ANN001
    with LocalLearner(tmp_path / "l.sqlite", [desc("cup", "Front-Wrap", ("Width", P(6, 0), 3))]) as learner:
        with pytest.raises(ValueError, match=r"^robot: a robot name is 1 to 64 letters"):
            learner.record_grasp_attempts([("Front-Wrap", 70.0, True)], robot="r1/../r2")
        assert learner.grasp_costs() == []
