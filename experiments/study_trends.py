"""Study 4: cost trends — how the tree's choices follow the costs of moving and sensing.

The paper (docs/method.md §6): dearer moves push sensing to a distance, cheaper moves
bring it close; dearer sensing makes grasps serve as degenerate sensors. Here the robot
itself is made slower or faster (``CostScale``: the simulator and the learner see the
same robot), noise-free so only the costs change, and we read off where sensing tests
were made and how often a grasp was tried as a feature.

Where tests are made can only move if a test from afar tells nearly as much as one from
close by: ``I²/C`` takes the far test only when ``(I_far / I_near)² > C_far / C_near``,
and dearer moves bring that cost ratio down no lower than the ratio of the drives, which
the approach to the object keeps well above the gain ratio on a library whose distant
sweeps tell little (docs/method.md, "Findings"). So the study also reports, from the
library, the best root gain of a test made from each distance.
"""

from __future__ import annotations

from collections.abc import Callable, Sequence
from pathlib import Path

import numpy as np

from experiments.conditions import BOTH, NO_NOISE, OURS, Conditions, CostScale
from experiments.config import ExperimentConfig
from experiments.episodes import EpisodeSpec, Results, robot_minutes
from experiments.plots import Panel, curves
from experiments.study import Study
from experiments.table import ResultRow, StudyResult, both, mean, num
from learner.choosing.criteria import DEFAULT_CRITERION
from learner.choosing.gain import partition_columns
from learner.choosing.matrix import DescriptionMatrix
from learner.description import ObjectDescription
from learner.knowledge import Knowledge

TITLE = "Cost trends: move and sensing cost multipliers"


def _spec(scale: CostScale, seed: int, conditions: Conditions = OURS) -> EpisodeSpec:
    return EpisodeSpec("cost trends", f"move x{scale.move:g}, sense x{scale.sense:g}, {conditions.name}", seed,
                       noise=NO_NOISE, cost=scale, control=conditions.control())


def _scales(config: ExperimentConfig) -> tuple[list[CostScale], list[CostScale]]:
    multipliers = config.cost_multipliers
    return [CostScale(move=m) for m in multipliers], [CostScale(sense=m) for m in multipliers]


def plan(config: ExperimentConfig) -> list[EpisodeSpec]:
    moves, senses = _scales(config)
    return [_spec(scale, s, c) for c in BOTH for scale in moves + senses for s in config.few_seeds]


def _measure(results: Results, scale: CostScale, seeds: Sequence[int],
             conditions: Conditions) -> tuple[float, float, float]:
    """Mean sensing distance (in), grasps tried as features per object, robot min per object."""
    rows = [r for s in seeds for r in results[_spec(scale, s, conditions)]]
    distance = mean(r.sense_distance_in for r in rows if r.sense_distance_in is not None)
    return distance, mean(r.grasps_as_features for r in rows), robot_minutes(rows)


def root_gain_by_distance(descriptions: Sequence[ObjectDescription], knowledge: Knowledge) -> dict[float, float]:
    """The best information gain (bits) of a sensing test made from each distance, at the
    root of ``descriptions`` (every description a candidate, as when an object is first
    approached): how much a test from afar can tell against one from close by. Tests
    whose distance is ``*`` are left out: they are made from wherever the robot is."""
    if not descriptions:
        return {}
    matrix = DescriptionMatrix(list(descriptions), knowledge, grasps_as_features=False)
    found = partition_columns(list(range(len(descriptions))), matrix, np.arange(len(matrix.tests), dtype=np.int64))
    best: dict[float, float] = {}
    for test, gain in zip(matrix.tests, found.gains):
        distance = test.position.distance_in
        if distance is not None:
            best[distance] = max(best.get(distance, 0.0), float(gain))
    return dict(sorted(best.items()))


def summarise(config: ExperimentConfig, results: Results, out: Path,
              library: Sequence[ObjectDescription] = (), knowledge: Knowledge | None = None) -> StudyResult:
    """The study's rows; given the ``library`` the episodes started from (and its
    ``knowledge``), also the best root gain of a test from each distance, which says
    whether the sensing distance could move at all."""
    moves, senses = _scales(config)
    seeds = config.few_seeds
    by_move = {c: [_measure(results, s, seeds, c) for s in moves] for c in BOTH}
    by_sense = {c: [_measure(results, s, seeds, c) for s in senses] for c in BOTH}
    lo, hi = config.cost_multipliers[0], config.cost_multipliers[-1]

    def trend(by: dict[Conditions, list[tuple[float, float, float]]], k: int, digits: int,
              direction: bool) -> Callable[[Conditions], tuple[str, str]]:
        def cell(c: Conditions) -> tuple[str, str]:
            first, last = by[c][0][k], by[c][-1][k]
            return f"{num(first, digits)} -> {num(last, digits)}", _direction(first, last) if direction else "-"
        return cell

    rows: tuple[ResultRow, ...] = (
        both(f"mean distance of sensing tests (in), moves x{lo:g} -> x{hi:g}", "farther when moves are dearer",
             trend(by_move, 0, 1, True)),
        both(f"grasps tried as features per object, sensing x{lo:g} -> x{hi:g}", "more when sensing is dearer",
             trend(by_sense, 1, 2, True)),
        both(f"mean distance of sensing tests (in), sensing x{lo:g} -> x{hi:g}", "-", trend(by_sense, 0, 1, False)),
        both(f"robot min per object, moves x{lo:g} -> x{hi:g}", "-", trend(by_move, 2, 1, False)),
        both(f"robot min per object, sensing x{lo:g} -> x{hi:g}", "-", trend(by_sense, 2, 1, False)),
    )
    gains = root_gain_by_distance(library, knowledge) if knowledge is not None else {}
    if gains:
        rows += (ResultRow("best root gain of a sensing test, by its distance (bits)", "-",
                           ", ".join(f"{d:g} in: {num(g, 2)}" for d, g in gains.items())),)
    xs = config.cost_multipliers

    def series(k: int) -> dict[str, tuple[list[float], list[float]]]:
        return {f"{what}, {c.name}": (xs, [m[k] for m in by[c]])
                for c in BOTH for what, by in (("moves", by_move), ("sensing", by_sense))}
    curves(out / "cost-trends.png", [
        Panel("where sensing happens", "cost multiplier", "mean sensing distance (in)", series(0), logx=True),
        Panel("grasps as sensors", "cost multiplier", "grasps tried as features / object", series(1), logx=True),
        Panel("robot time", "cost multiplier", "robot min / object", series(2), logx=True),
    ])
    notes = (f"Test objects, noise off, criterion `{DEFAULT_CRITERION}`, {len(seeds)} seed(s) per point, in the "
             "paper's conditions (no appearance) and with our defaults; 'moves xk' makes driving, "
             "turning, vision and centring k times slower (and the learner's move model k times dearer), "
             "'sensing xk' every sensing procedure k times longer.",
             "The ratio column here gives the direction: 'up' when the second value is larger, as the paper's "
             "trend says it should be.",
             "A test from afar is chosen only when (its gain / the near test's)^2 exceeds (its cost / the near "
             "test's); the approach to each object is common to both, so even very dear moves bring that cost ratio "
             "no lower than the ratio of the drives: a far test must tell nearly as much as a near one (the gain "
             "row; docs/method.md, \"Findings\").")
    return StudyResult(TITLE, rows, notes, ("cost-trends.png",), both_conditions=True)


def _direction(before: float, after: float) -> str:
    if not (before == before and after == after):  # NaN: nothing measured
        return "-"
    if after > before:
        return "up"
    return "down" if after < before else "flat"


STUDY = Study("trends", plan, lambda context, results: summarise(
    context.config, results, context.plots, context.trained.descriptions, context.trained.knowledge))
