"""Study: the camera's appearance as free features — candidates ruled out by what the
overhead camera already measured (round or not, footprint area, elongation) against the
same floors without it.

The paper's CSL sensed every feature with the arm; our robot also has the camera image it
located the object in. ``Params.use_appearance`` lets the session drop every candidate
whose recorded appearance is unlike the object's (docs/method.md §5.8), at no robot time.
On by default since this study favoured it (and a grasp the appearance alone chose,
failing, is now remembered: ``Discriminate``); the study keeps the data behind that
default: the execution runs of study 2 (appearance on) against the same seeds with it off.
"""

from __future__ import annotations

import math
from collections.abc import Sequence

from experiments.conditions import EXECUTION_NOISE, Control
from experiments.config import ExperimentConfig
from learner.choosing.criteria import DEFAULT_CRITERION
from experiments.episodes import EpisodeRow, EpisodeSpec, Results, robot_minutes, success_rate
from experiments.study import Study
from experiments.table import ResultRow, StudyResult, mean, num, paired_difference, percent

TITLE = "The camera's appearance as free features"
OBJECT_SETS = ("test", "training")
SETTINGS = (Control(appearance=False), Control())  # off, on



def _spec(objects: str, control: Control, seed: int) -> EpisodeSpec:
    # with the appearance on (the default) this is study 2's execution run: the pool runs it once
    return EpisodeSpec("appearance", f"{objects} objects, {control.label}", seed, objects, noise=EXECUTION_NOISE,
                       control=control)


def plan(config: ExperimentConfig) -> list[EpisodeSpec]:
    return [_spec(objects, c, s) for objects in OBJECT_SETS for c in SETTINGS for s in config.seed_list]


def _rows(results: Results, objects: str, control: Control, seeds: Sequence[int]) -> list[EpisodeRow]:
    return [r for s in seeds for r in results[_spec(objects, control, s)]]


def verdict(saving: float, error: float, success_off: float, success_on: float) -> str:
    """Which setting the data favours: on only when it is cheaper by more than twice the
    standard error and no less successful; off when it is dearer by that much; else none."""
    if math.isnan(saving) or math.isnan(error):
        return "too few seeds to tell"
    if saving > 2 * error and success_on >= success_off:
        return "on"
    if saving < -2 * error:
        return "off"
    return "no difference beyond noise"


def _per_seed_minutes(results: Results, objects: str, control: Control, seeds: Sequence[int]) -> list[float]:
    return [robot_minutes(results[_spec(objects, control, s)]) for s in seeds]


def summarise(config: ExperimentConfig, results: Results) -> StudyResult:
    seeds = config.seed_list
    off, on = SETTINGS
    table: list[ResultRow] = []
    for objects in OBJECT_SETS:
        cells = []
        for control in SETTINGS:
            rows = _rows(results, objects, control, seeds)
            wrong = mean(float(r.wrong_grasps) for r in rows)
            cells.append((success_rate(rows), robot_minutes(rows),
                          mean(float(r.tests) for r in rows), wrong))
        for control, (success, minutes, tests, wrong) in zip(SETTINGS, cells):
            table.append(ResultRow(f"{objects} objects, appearance {'on' if control.appearance else 'off'}", "-",
                                   f"{percent(success)}, {num(minutes)} min, {num(tests)} tests, "
                                   f"{num(wrong, 2)} wrong grasps per object"))
        saving, error = paired_difference(_per_seed_minutes(results, objects, off, seeds),
                                      _per_seed_minutes(results, objects, on, seeds))
        table.append(ResultRow(f"{objects} objects: robot min saved per object by the appearance (paired by seed)",
                               "-", f"{num(saving, 2)} ± {num(error, 2)}; favours: "
                               f"{verdict(saving, error, cells[0][0], cells[1][0])}"))
    notes = (f"Noise `{EXECUTION_NOISE}`, criterion `{DEFAULT_CRITERION}`, the library trained in study 1 (it records each "
             f"description's appearance), {len(seeds)} seeds; the appearance-on runs are study 2's.",
             "Favours 'on' only when it saves more than twice the standard error of the paired difference and "
             "loses no success; the executive's default is on (`--no-appearance` turns it off).")
    return StudyResult(TITLE, tuple(table), notes)


STUDY = Study("appearance", plan, lambda context, results: summarise(context.config, results))
