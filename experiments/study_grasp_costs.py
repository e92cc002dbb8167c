"""Study: grasp costs learned from what grasps cost (docs/method.md §5.7).

The knowledge file prices each grasp once; the real robot may disagree. Here the
simulated robot's Front-Wrap takes :data:`FACTOR` times the file's 60 s (a slow wrap: the
simulator's profile is overridden, the learner's knowledge is not), and chains of
episodes on the test floors run with learned grasp costs off (the file's prices for
ever) and on (``Params.learned_grasp_costs``, ``csl run``'s default since this study: after
each object, its grasps' attempts, failures' recoveries included, are added to the
store's totals, and the objects that follow, in this episode and the next, are priced
by their Bayesian mean, ``learner.costs.with_learned_grasp_costs``). Front-Wrap is the
grasp the default criterion tries most as a feature on these floors, and most of those
tries fail, so what a failure costs steers how often it is tried. Compared: robot minutes per object,
episode by episode, and how many grasps were tried as features and failed.
"""

from __future__ import annotations

import tempfile
from collections.abc import Sequence
from dataclasses import dataclass, field, replace
from pathlib import Path

from behaviours.services import Params
from executive import defaults
from executive.executive import Executive
from experiments.conditions import EXECUTION_NOISE, noise_config
from experiments.config import ExperimentConfig
from experiments.worker import installed_profile
from experiments.floor import play
from experiments.study import Study
from experiments.table import ResultRow, StudyResult, mean, num, paired_difference, percent
from experiments.worlds import write_floor
from hero_driver.sim_driver import SimulatedHero
from learner.library.store import load_library
from learner.service.local import LocalLearner
from robot_profile import RobotProfile

TITLE = "Learned grasp costs: a grasp dearer than the knowledge file says"
GRASP = "Front-Wrap"
FACTOR = 4.0  # the simulated Front-Wrap takes 240 s where the file says 60 s
OBJECTS = "test"


@dataclass(frozen=True)
class GraspCostRow:
    """One object of one episode of a chain."""

    learned: bool
    seed: int
    episode: int
    object: str
    success: bool
    robot_s: float
    features_failed: int  # grasps tried as features that failed on it


@dataclass(frozen=True)
class GraspCostJob:
    """A chain of ``episodes`` test floors on one learner store, learned costs on or off;
    the simulated Front-Wrap takes ``factor`` times the file's time (1: the file right,
    the check that learning costs nothing there, docs/method.md §5.7)."""

    study: str = field(compare=False)
    learned: bool
    seed: int
    episodes: int
    factor: float = FACTOR

    def run(self) -> list[GraspCostRow]:
        truth = slowed(installed_profile(), GRASP, self.factor)
        out: list[GraspCostRow] = []
        with tempfile.TemporaryDirectory(prefix="csl-grasp-costs-") as tmp:
            folder = Path(tmp)
            with LocalLearner(folder / "library.sqlite", load_library(defaults.EXAMPLE_LIBRARY)) as learner:
                for episode in range(self.episodes):
                    out += self._episode(episode, truth, learner, folder)
        return out

    def _episode(self, episode: int, truth: RobotProfile, learner: LocalLearner, folder: Path) -> list[GraspCostRow]:
        seed = self.seed * 1000 + episode
        hero = SimulatedHero("experiment", world=write_floor(folder, OBJECTS, seed), seed=seed, profile=truth,
                             noise=noise_config(EXECUTION_NOISE))
        # the executive records each object's attempts and prices grasps by them, as csl run does
        executive = Executive(hero, learner, profile=installed_profile(),
                              params=Params(learned_grasp_costs=self.learned))
        played = play(hero, executive)
        failed = [e.get("object") for e in played.events if e.get("event") == "grasp_feature_failed"]
        return [GraspCostRow(self.learned, self.seed, episode, r.object, bool(r.correct), r.robot_s,
                             failed.count(record.index))
                for record, r in played.rows()]


def slowed(profile: RobotProfile, grasp: str, factor: float) -> RobotProfile:
    """``profile`` with ``grasp`` taking ``factor`` times its time (the simulated robot's
    truth; the learner's knowledge is not told)."""
    return replace(profile, grasping=tuple(replace(g, time_s=g.time_s * factor) if g.name == grasp else g
                                           for g in profile.grasping),
                   source=f"{profile.source} ({grasp} x{factor:g})")


def _job(config: ExperimentConfig, learned: bool, seed: int) -> GraspCostJob:
    return GraspCostJob("grasp costs", learned, seed, config.chain_length)


def plan(config: ExperimentConfig) -> list[GraspCostJob]:
    return [_job(config, learned, s) for learned in (False, True) for s in config.chain_seeds]


def summarise(config: ExperimentConfig, results: dict[object, Sequence[object]]) -> StudyResult:
    table: list[ResultRow] = []
    per_seed: dict[bool, list[float]] = {}
    for learned in (False, True):
        chains = [[r for r in results[_job(config, learned, s)] if isinstance(r, GraspCostRow)]
                  for s in config.chain_seeds]
        label = "on" if learned else "off"
        minutes = [mean(r.robot_s for c in chains for r in c if r.episode == e) / 60.0
                   for e in range(config.chain_length)]
        every = [r for c in chains for r in c]
        table.append(ResultRow(f"learned grasp costs {label}: robot min per object, episode 1 -> "
                               f"{config.chain_length}", "-", " -> ".join(num(m) for m in minutes)))
        table.append(ResultRow(f"learned grasp costs {label}: grasped right, grasp features failed per object",
                               "-", f"{percent(mean(float(r.success) for r in every))}, "
                                    f"{num(mean(float(r.features_failed) for r in every), 2)}"))
        per_seed[learned] = [mean(r.robot_s for r in c if r.episode > 0) / 60.0 for c in chains]
    saving, error = paired_difference(per_seed[False], per_seed[True])
    table.append(ResultRow("robot min saved per object by learned costs after episode 1 (paired by seed)", "-",
                           f"{num(saving, 2)} ± {num(error, 2)}"))
    notes = (f"{len(config.chain_seeds)} chain(s) of {config.chain_length} episodes on the {OBJECTS} objects, noise "
             f"`{EXECUTION_NOISE}`, the shipped library, the default criterion; the simulated {GRASP} takes "
             f"x{FACTOR:g} the knowledge file's time.",
             "Learned costs: each grasp priced by the Bayesian mean of its attempts (what a hold and what a failure "
             "cost, a knocked-over object's voided sensing included) with the file's cost as a prior worth 3 "
             "attempts, recorded after each object; the first object of both chains is priced by the file alone.")
    return StudyResult(TITLE, tuple(table), notes)


STUDY = Study("grasp costs", plan, lambda context, results: summarise(context.config, results))
