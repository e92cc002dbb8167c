"""The learned-grasp-costs study: the simulated robot's truth, the learner's prices, and
a short chain (docs/method.md §5.7)."""

from __future__ import annotations

from pathlib import Path

import pytest

from behaviours.services import Params
from executive import defaults
from executive.executive import Executive
from experiments.config import ExperimentConfig
from experiments.worker import install_worker
from experiments.study_grasp_costs import GraspCostJob, GraspCostRow, plan, slowed, summarise
from experiments.worlds import set_members
from hero_driver.sim_driver import SimulatedHero
from learner.library.store import load_library
from learner.service.local import LocalLearner
from robot_profile import load_profile


def test_the_simulator_is_slowed_and_the_executive_priced_by_what_was_recorded(tmp_path: Path) -> None:
    profile = load_profile()
    truth = slowed(profile, "Front-Wrap", 4.0)
    assert truth.grasping_procedure("Front-Wrap").time_s == 240.0
    assert truth.grasping_procedure("Top-Pinch") == profile.grasping_procedure("Top-Pinch")
    file = profile.knowledge()
    with LocalLearner(tmp_path / "library.sqlite", load_library(defaults.EXAMPLE_LIBRARY)) as learner:
        learner.record_grasp_attempts([("Front-Wrap", 240.0, True), ("Front-Wrap", 240.0, True),
                                       ("Front-Wrap", 300.0, False)])
        hero = SimulatedHero("r1", world="lab", seed=0, profile=truth)
        try:
            on = Executive(hero, learner, profile=profile, params=Params(learned_grasp_costs=True))
            off = Executive(hero, learner, profile=profile, params=Params(learned_grasp_costs=False))
            priced = on.services.library.current().knowledge
            # two holds of 240 s and a failure of 300 s: a hold (3 x 60 + 480) / 5 = 132 s, a
            # failure (3 x 90 + 300) / 4 = 142.5 s, so the penalty the learner sees is 10.5 s
            wrap = priced.grasp("Front-Wrap")
            assert (wrap.time_s, wrap.side_effect_penalty_s) == pytest.approx((132.0, 10.5))
            assert priced.grasp("Top-Pinch") == file.grasp("Top-Pinch")
            assert off.services.library.current().knowledge.grasp("Front-Wrap") == file.grasp("Front-Wrap")
        finally:
            hero.close()


@pytest.mark.slow
def test_a_short_chain_runs_every_object_and_the_first_episode_is_the_files_in_both() -> None:
    install_worker({}, load_profile())
    config = ExperimentConfig(quick=True, seeds=(0,), jobs=1, out=Path("."), command="test")
    jobs = plan(config)
    assert [(j.learned, j.seed, j.episodes) for j in jobs] == [(False, 0, 3), (True, 0, 3)]
    off, on = (GraspCostJob(j.study, j.learned, j.seed, 2).run() for j in jobs)
    for rows in (off, on):
        assert [sum(r.episode == e for r in rows) for e in (0, 1)] == [len(set_members("test"))] * 2
    # the first object is priced by the file in both chains: the same floor, the same run
    assert [r.robot_s for r in off if r.episode == 0][0] == [r.robot_s for r in on if r.episode == 0][0]


def test_the_summary_by_hand() -> None:
    config = ExperimentConfig(quick=True, seeds=(0,), jobs=1, out=Path("."), command="test")
    off_job, on_job = plan(config)

    def chain(learned: bool, seconds: list[float]) -> list[GraspCostRow]:
        return [GraspCostRow(learned, 0, e, f"object {i}", i == 0, s, int(learned))
                for e, s in enumerate(seconds) for i in range(2)]

    study = summarise(config, {off_job: chain(False, [600, 600, 600]), on_job: chain(True, [600, 300, 300])})
    cells = [r.ours for r in study.rows]
    # 600 s = 10 min; after episode 1 the off chain costs 10 min per object, the on chain 5:
    # 5 min saved (one seed: no standard error)
    assert cells == ["10.0 -> 10.0 -> 10.0", "50%, 0.00", "10.0 -> 5.0 -> 5.0", "50%, 1.00", "5.00 ± -"]
