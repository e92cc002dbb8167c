"""Study 7: the distance to the optimum — every criterion's expected cost as a ratio to
the optimal adaptive policy's, from several start poses.

Noise-free and on the learner alone (``learner.optimum``): the optimum is found by
dynamic programming over (still-consistent descriptions, robot position), each
criterion's policy walked over the same library with the same move model (the
profile's 2 s/in), on the shipped library and on a synthetic one. No policy can beat
the optimum, so a ratio below 1 is a bug in one of the two, and the test checks it.
"""

from __future__ import annotations

import math
from collections.abc import Mapping, Sequence
from dataclasses import dataclass
from pathlib import Path

from executive.defaults import EXAMPLE_LIBRARY
from experiments.ablations import MEASURED, criterion
from experiments.config import ExperimentConfig
from experiments.worker import installed_profile
from experiments.plots import bars
from experiments.study import Study
from experiments.table import ResultRow, StudyResult, num
from learner.choosing.criteria import DEFAULT_CRITERION
from learner.choosing.matrix import DescriptionMatrix
from learner.costs import ModelMoveCost
from learner.library.format import read_library_json
from learner.library.synthetic import synthetic_library
from learner.optimum import optimal_cost, policy_cost
from learner.position import Position

TITLE = "Distance to the optimum (noise-free)"
SHIPPED = "shipped"
SYNTHETIC = "synthetic"
SYNTHETIC_SEED = 0


def libraries() -> list[str]:
    """The libraries measured on: the shipped one and a synthetic one."""
    return [SHIPPED, SYNTHETIC]


@dataclass(frozen=True)
class OptimumRow:
    """One criterion's walk against the optimum; ``error`` when the walk itself failed
    (then ``policy_s`` is NaN and the page lists the failure instead of a ratio)."""

    library: str
    start: str
    criterion: str
    policy_s: float
    optimal_s: float
    error: str | None = None

    @property
    def ratio(self) -> float:
        return self.policy_s / self.optimal_s


@dataclass(frozen=True)
class OptimumJob:
    """The optimum and every criterion's policy cost on one library from one start."""

    library: str
    start: Position
    synthetic_objects: int
    shipped_descriptions: int | None = None  # the first n of the shipped library (None: all)
    study: str = "optimum"

    def run(self) -> list[OptimumRow]:
        knowledge = installed_profile().knowledge()
        shipped = read_library_json(EXAMPLE_LIBRARY)
        if self.library == SHIPPED:
            descriptions = shipped[:self.shipped_descriptions]
        else:
            descriptions = synthetic_library(knowledge, self.synthetic_objects, SYNTHETIC_SEED, base=shipped)
        matrix = DescriptionMatrix(descriptions, knowledge)
        estimator = ModelMoveCost(knowledge.move)
        best = optimal_cost(matrix, estimator, self.start)
        rows = []
        for name in MEASURED:
            try:
                cost, error = policy_cost(matrix, criterion(name), estimator, self.start, seed=0), None
            except RuntimeError as exc:  # one criterion's failed walk is a finding, not the end of the run
                cost, error = math.nan, str(exc).splitlines()[0]
            rows.append(OptimumRow(self.library, str(self.start), name, cost, best, error))
        return rows


Results = Mapping[object, Sequence[object]]  # every job's results; this study reads its own


def plan(config: ExperimentConfig) -> list[OptimumJob]:
    return [OptimumJob(lib, start, config.synthetic_objects, config.shipped_descriptions) for lib in libraries()
            for start in config.start_poses]


def summarise(config: ExperimentConfig, results: Results, out: Path) -> StudyResult:
    jobs = [job for job in results if isinstance(job, OptimumJob)]  # what ran, not what could run now
    every = [row for job in jobs for row in results[job] if isinstance(row, OptimumRow)]
    found = [row for row in every if row.error is None]
    failed = [row for row in every if row.error is not None]
    measured_on = list(dict.fromkeys(job.library for job in jobs))
    def ratios(name: str, lib: str | None = None) -> list[float]:
        return [r.ratio for r in found if r.criterion == name and lib in (None, r.library)]

    rows = []
    for lib in measured_on:
        for name in MEASURED:
            mine = ratios(name, lib)
            span = f"{min(mine):.3f} - {max(mine):.3f}" if mine else "-"
            rows.append(ResultRow(f"`{name}` / optimum, {lib} library ({len(mine)} starts)", "-", span,
                                  num(max(mine), 3) if mine else "-"))
    walked = [name for name in MEASURED if ratios(name)]
    if walked:
        best = min(walked, key=lambda n: max(ratios(n)))
        rows.append(ResultRow("best criterion by its worst ratio (every library)", "-", f"`{best}`"))
    detail = (("library", "start", "criterion", "policy s", "optimum s", "ratio"),
              tuple((r.library, r.start, r.criterion, num(r.policy_s), num(r.optimal_s),
                     f"{r.ratio:.3f}" if r.error is None else f"walk failed: {r.error}") for r in every))
    groups = {name: {lib: (max(ratios(name, lib)), 0.0) for lib in measured_on if ratios(name, lib)}
              for name in walked}
    bars(out / "optimum.png", "worst ratio to the optimum over the start poses", "policy cost / optimal cost",
         groups, reference=(1.0, "optimum"))
    synthetic = f"synthetic: {config.synthetic_objects} objects from `learner.library.synthetic` (seed {SYNTHETIC_SEED})"
    shipped = ("all of it" if config.shipped_descriptions is None
               else f"its first {config.shipped_descriptions} descriptions (quick)")
    notes = (f"Shipped: the example library (`{EXAMPLE_LIBRARY.name}`), {shipped}; {synthetic}. Uniform prior over "
             "descriptions, move cost by the profile's move model; each object charged until its own grasp is "
             "executed, wrong grasps and their recovery included (docs/optimum.md).",
             f"The ours / paper column holds the worst ratio over the start poses; `{DEFAULT_CRITERION}` is the "
             "executive's default criterion.")
    if failed:
        notes += (f"{len(failed)} policy walk(s) failed in `learner.optimum` and are left out of the ratios (listed in "
                  "the table above as 'walk failed').",)
    return StudyResult(TITLE, tuple(rows), notes, ("optimum.png",), details=(detail,))


STUDY = Study("optimum", plan, lambda context, results: summarise(context.config, results, context.plots))
