"""Studies 2 and 3: the paper's execution experiment, and its baselines in the same run.

Execution: the trained library meets the training objects and the unseen test objects,
each floor laid out at random per seed, under the execution noise (the simulator's
``paper`` preset). Baselines, on the same test floors and seeds: every measured
criterion, the product's and the ablations (``experiments.ablations``; the cost-blind
``id3`` among them), the control strategies switched off, and the library from
exhaustive training; and measuring every feature, priced from the knowledge.
"""

from __future__ import annotations

import math
import re
import statistics
from collections.abc import Callable, Sequence
from pathlib import Path

from experiments import figures
from experiments.ablations import MEASURED
from experiments.conditions import BOTH, EXECUTION_NOISE, OURS, STRATEGIES_OFF, Conditions
from experiments.config import ExperimentConfig
from experiments.episodes import EpisodeRow, EpisodeSpec, Results, robot_minutes, success_rate
from experiments.exhaustive import measure_everything_s
from experiments.plots import bars
from experiments.study import Study
from experiments.table import ResultRow, StudyResult, both, mean, num, paired, percent, ratio
from executive.training_sources import catalogue_objects
from learner.choosing.criteria import DEFAULT_CRITERION
from learner.knowledge import Knowledge
from learner.training.stage import TrainingLog

EXECUTION_TITLE = "Execution on training and unseen test objects"
BASELINES_TITLE = "Baselines in the same run"
COST_BLIND = "id3-cost-ties"  # the fair cost-blind baseline: information gain only, nothing left to chance
RANDOM_ID3 = "id3"  # the same gain with ties and * slots drawn at random: an extra row, not the baseline
OBJECT_SETS = ("test", "training")
PAPER_CRITERION = "cs-id3"  # the paper's own one-step rule, I^2 / C
PAPER_CRITERIA = (PAPER_CRITERION, COST_BLIND, RANDOM_ID3, "idx", "eg2")  # the rules the paper compared



def _execution(objects: str, seed: int, conditions: Conditions = OURS) -> EpisodeSpec:
    return EpisodeSpec("execution", f"{objects} objects, {conditions.name}", seed, objects, noise=EXECUTION_NOISE,
                       control=conditions.control())


def _criterion(name: str, seed: int, conditions: Conditions = OURS) -> EpisodeSpec:
    return EpisodeSpec("baselines", f"{name}, {conditions.name}", seed, criterion=name, noise=EXECUTION_NOISE,
                       control=conditions.control())


def _strategies_off(objects: str, seed: int, conditions: Conditions = OURS) -> EpisodeSpec:
    return EpisodeSpec("baselines", f"strategies off, {objects} objects, {conditions.name}", seed, objects,
                       control=conditions.control(STRATEGIES_OFF), noise=EXECUTION_NOISE)


def _exhaustive(seed: int, conditions: Conditions = OURS, criterion: str = DEFAULT_CRITERION) -> EpisodeSpec:
    return EpisodeSpec("baselines", f"exhaustive library, {criterion}, {conditions.name}", seed, library="exhaustive",
                       criterion=criterion, noise=EXECUTION_NOISE, control=conditions.control())


def criteria_seeds(config: ExperimentConfig) -> list[int]:
    """Seeds per criterion: there are many criteria, so as few as the sweeps use."""
    return config.few_seeds


def criteria_run(config: ExperimentConfig) -> list[str]:
    """Every measured criterion (the product's and the ablations); a quick run only the
    paper's (and its cost-blind baselines) and the default, each in both conditions."""
    if config.quick:
        return [name for name in MEASURED if name in PAPER_CRITERIA or name == DEFAULT_CRITERION]
    return list(MEASURED)


def plan_execution(config: ExperimentConfig) -> list[EpisodeSpec]:
    return [_execution(objects, s, c) for c in BOTH for objects in OBJECT_SETS for s in config.seed_list]


def plan_baselines(config: ExperimentConfig) -> list[EpisodeSpec]:
    """Every criterion on the test floors, the strategies off, the exhaustive library,
    each in both conditions; the default criterion's runs are the execution study's own
    (equal jobs run once)."""
    specs = [_criterion(name, s, c) for c in BOTH for name in criteria_run(config) for s in criteria_seeds(config)]
    specs += [_strategies_off(objects, s, c) for c in BOTH for objects in OBJECT_SETS for s in config.seed_list]
    specs += [_exhaustive(s, c) for c in BOTH for s in config.seed_list]
    # the paper's claim with the paper's one-step rule, on the criteria's floors
    specs += [_exhaustive(s, c, PAPER_CRITERION) for c in BOTH for s in criteria_seeds(config)]
    return specs


def plan(config: ExperimentConfig) -> list[EpisodeSpec]:
    """Both studies' jobs."""
    return [*plan_execution(config), *plan_baselines(config)]


def _rows(results: Results, specs: Sequence[EpisodeSpec]) -> list[EpisodeRow]:
    return [row for spec in specs for row in results[spec]]


def _stderr_min(rows: Sequence[EpisodeRow]) -> float:
    costs = [r.robot_s / 60.0 for r in rows]
    return statistics.stdev(costs) / math.sqrt(len(costs)) if len(costs) > 1 else 0.0


def first_grasp_right(row: EpisodeRow) -> bool:
    """Handled right with no grasp failing at a leaf: right without failed-grasp recovery
    (a grasp tried as a feature that failed is the tree's own test, not a recovery)."""
    return row.success and row.wrong_grasps == 0


def recoveries_per_object(rows: Sequence[EpisodeRow], kind: str) -> float:
    """How often per object the executive used the recovery ``kind`` (as the CSV's
    ``recoveries`` column names it, e.g. ``reselect`` or ``backtrack``)."""
    pattern = re.compile(rf"(?:^|, ){re.escape(kind)} ×(\d+)")
    return mean(sum(int(n) for n in pattern.findall(r.recoveries)) for r in rows)


def _strategies_rows(config: ExperimentConfig, results: Results, objects: str) -> list[ResultRow]:
    """Strategies on vs off on one object set, paired by seed: success, first grasp right,
    and how often the strategies acted when on; in both conditions."""
    seeds = config.seed_list
    out = []
    for what, rate, paper in (("success", lambda r: float(r.success), f"~{percent(figures.STRATEGIES_GAIN)}"),
                              ("first grasp right", lambda r: float(first_grasp_right(r)), "-")):
        def cell(c: Conditions, rate: Callable[[EpisodeRow], float] = rate, paper: str = paper) -> tuple[str, str]:
            on_specs = [_execution(objects, s, c) for s in seeds]
            off_specs = [_strategies_off(objects, s, c) for s in seeds]
            on, off = _rows(results, on_specs), _rows(results, off_specs)
            before, after = mean(rate(r) for r in off), mean(rate(r) for r in on)
            gain = after / before - 1.0 if before > 0 else math.nan
            difference = paired([100 * v for v in _per_seed(results, on_specs, rate)],
                                [100 * v for v in _per_seed(results, off_specs, rate)], 1, " points")
            return (f"{percent(gain)} ({percent(before)} -> {percent(after)}; {difference}; "
                    f"{num(robot_minutes(off))} -> {num(robot_minutes(on))} min)",
                    ratio(gain, figures.STRATEGIES_GAIN) if paper != "-" else "-")
        out.append(both(f"control strategies on vs off, {objects} objects: {what} gained", paper, cell))

    def acted(c: Conditions) -> tuple[str, str]:
        on = _rows(results, [_execution(objects, s, c) for s in seeds])
        return (f"{num(recoveries_per_object(on, 'reselect'), 2)}, {num(recoveries_per_object(on, 'backtrack'), 2)}",
                "-")
    out.append(both(f"control strategies on, {objects} objects: reselections, backtracks per object", "-", acted))
    return out


def _per_seed(results: Results, specs: Sequence[EpisodeSpec], rate: Callable[[EpisodeRow], float]) -> list[float]:
    return [mean(rate(r) for r in results[spec]) for spec in specs]


def _minutes(row: EpisodeRow) -> float:
    return row.robot_s / 60.0


def _sensing_minutes(rows: Sequence[EpisodeRow]) -> float:
    return mean(r.sensing_s for r in rows) / 60.0


def _per_object(rows: Sequence[EpisodeRow], column: str) -> float:
    return mean(float(getattr(r, column)) for r in rows)


def summarise_execution(config: ExperimentConfig, results: Results) -> StudyResult:
    seeds = config.seed_list

    def run(objects: str, c: Conditions) -> list[EpisodeRow]:
        return _rows(results, [_execution(objects, s, c) for s in seeds])

    def success(objects: str) -> Callable[[Conditions], tuple[str, str]]:
        return lambda c: (percent(success_rate(run(objects, c))), "-")

    def minutes(objects: str) -> Callable[[Conditions], tuple[str, str]]:
        def cell(c: Conditions) -> tuple[str, str]:
            value = robot_minutes(run(objects, c))
            return num(value), ratio(value, figures.EXECUTION_MINUTES_PER_OBJECT)
        return cell

    def misclassified(objects: str) -> Callable[[Conditions], tuple[str, str]]:
        return lambda c: (f"{percent(mean(float(r.misclassified) for r in run(objects, c)))} / "
                          f"{percent(mean(float(r.misclassified_strict) for r in run(objects, c)))}", "-")

    def computation(c: Conditions) -> tuple[str, str]:
        return num(mean(r.computing_ms for r in run("test", c) + run("training", c)) / 1000.0, 2), "-"

    paper_minutes = f"~{figures.EXECUTION_MINUTES_PER_OBJECT:g}"
    rows = (
        both("success, unseen test objects", f"> {percent(figures.SUCCESS_RATE)}", success("test")),
        both("success, training objects", f"> {percent(figures.SUCCESS_RATE)}", success("training")),
        both("robot minutes per object, test objects", paper_minutes, minutes("test")),
        both("robot minutes per object, training objects", paper_minutes, minutes("training")),
        both("computation per object (s; the paper's on a 1991 computer: not compared)", "~20", computation),
        both("objects misclassified, test objects: lenient / strict", "-", misclassified("test")),
        both("objects misclassified, training objects: lenient / strict", "-", misclassified("training")),
    )
    per_object: dict[str, dict[Conditions, list[EpisodeRow]]] = {}
    for c in BOTH:
        for r in run("test", c):
            per_object.setdefault(r.object, {p: [] for p in BOTH})[c].append(r)

    def pair(by: dict[Conditions, list[EpisodeRow]], value: Callable[[list[EpisodeRow]], str]) -> str:
        return " / ".join(value(by[c]) for c in BOTH)

    detail = (("test object (paper's conditions / our defaults)", "episodes", "success", "robot min (mean)",
               "grasps failed at a leaf", "grasps tried as features that failed", "knocked over"),
              tuple((name, str(len(by[OURS])), pair(by, lambda rs: percent(success_rate(rs))),
                     pair(by, lambda rs: num(robot_minutes(rs))), pair(by, lambda rs: str(sum(r.wrong_grasps for r in rs))),
                     pair(by, lambda rs: str(sum(r.failed_features for r in rs))),
                     pair(by, lambda rs: str(sum(r.knocked_over for r in rs))))
                    for name, by in sorted(per_object.items())))
    notes = (f"Noise: `{EXECUTION_NOISE}`; criterion `{DEFAULT_CRITERION}`; {len(seeds)} seeds, each a "
             f"floor with every object of the set at a random position and yaw; the library trained in study 1.",
             "The paper's conditions: the camera locates objects but does not tell them apart (no appearance), as "
             "the paper's did; our defaults add the appearance (its own study below). Both run the same floors.",
             "Success: the object was grasped with one of its correct grasps (or left, for No-Grab objects), judged "
             "by what it is at the end (a tumbler knocked over and then grasped as a lying one counts).",
             "Misclassified, lenient: a grasp executed at a leaf failed, or the object was not handled; strict: also "
             "a grasp tried as a feature that failed, or the object knocked over (the simulator's truth).",
             "Computation is the learner's and planner's wall time on this machine; the paper's ~20 s was a 1991 "
             "computer's.")
    return StudyResult(EXECUTION_TITLE, rows, notes, details=(detail,), both_conditions=True)


def summarise_baselines(config: ExperimentConfig, results: Results, log: TrainingLog, knowledge: Knowledge,
                        out: Path) -> StudyResult:
    objects = catalogue_objects("training")
    everything_h = mean(measure_everything_s(knowledge, log.distances, log.orientations, o.round, o.grasp)
                        for o in objects) / 3600.0
    # a round object is sensed from one orientation, the others from every training one
    # (the paper's figure does not say which it counted)
    round_h, other_h = (mean(measure_everything_s(knowledge, log.distances, log.orientations, o.round, o.grasp)
                             for o in objects if o.round == kind) / 3600.0 for kind in (True, False))
    seeds, names = criteria_seeds(config), criteria_run(config)

    def runs(name: str, c: Conditions) -> list[EpisodeRow]:
        return _rows(results, [_criterion(name, s, c) for s in seeds])

    rows = [ResultRow("measure every feature at every training position (h per object)",
                      f"> {figures.MEASURE_EVERYTHING_HOURS:g}", num(everything_h, 2),
                      ratio(everything_h, figures.MEASURE_EVERYTHING_HOURS)),
            ResultRow(f"the same, the {sum(o.round for o in objects)} round objects (one orientation) / the "
                      f"{sum(not o.round for o in objects)} others (every training orientation)",
                      f"> {figures.MEASURE_EVERYTHING_HOURS:g}", f"{num(round_h, 2)} / {num(other_h, 2)}",
                      ratio(other_h, figures.MEASURE_EVERYTHING_HOURS))]
    baseline = COST_BLIND in names
    for name in names:
        if not baseline or name == COST_BLIND:
            label = f"robot min per object, `{name}`" + (" (the cost-blind baseline)" if name == COST_BLIND else "")
            rows.append(both(label, "-", lambda c, name=name: (
                f"{num(robot_minutes(runs(name, c)))} ({percent(success_rate(runs(name, c)))} success)", "-")))
            continue
        cost_sensitive = MEASURED[name].cost_sensitive

        def saved(c: Conditions, name: str = name, cost_sensitive: bool = cost_sensitive) -> tuple[str, str]:
            crs, blind = runs(name, c), runs(COST_BLIND, c)
            saving = 1.0 - robot_minutes(crs) / robot_minutes(blind)
            classify = 1.0 - (mean(r.sensing_s + r.moving_s for r in crs)
                              / mean(r.sensing_s + r.moving_s for r in blind))
            difference = paired(_per_seed(results, [_criterion(name, s, c) for s in seeds], _minutes),
                                _per_seed(results, [_criterion(COST_BLIND, s, c) for s in seeds], _minutes),
                                unit=" min")
            return (f"{percent(saving)} ({percent(classify)}); {num(robot_minutes(crs))} min, "
                    f"{percent(success_rate(crs))} success; per object {difference}",
                    ratio(saving, figures.COST_SENSITIVE_SAVING) if cost_sensitive else "-")
        rows.append(both(f"`{name}` vs `{COST_BLIND}`: robot time saved (sensing + moving saved)"
                         + (" (random ties and * positions: not a baseline)" if name == RANDOM_ID3 else ""),
                         f">= {percent(figures.COST_SENSITIVE_SAVING)}" if cost_sensitive else "-", saved))
    for objects in OBJECT_SETS:
        rows += _strategies_rows(config, results, objects)

    def exhaustive_cheaper(c: Conditions, criterion: str, seeds: Sequence[int]) -> tuple[str, str]:
        trained_specs = [_criterion(criterion, s, c) for s in seeds]
        exhaustive_specs = [_exhaustive(s, c, criterion) for s in seeds]
        on, exhaustive = _rows(results, trained_specs), _rows(results, exhaustive_specs)
        saving = 1.0 - robot_minutes(exhaustive) / robot_minutes(on)
        difference = paired(_per_seed(results, exhaustive_specs, _minutes), _per_seed(results, trained_specs, _minutes),
                            unit=" min")
        return (f"{percent(saving)} ({num(robot_minutes(on))} -> {num(robot_minutes(exhaustive))} min, "
                f"{percent(success_rate(exhaustive))} success; per object {difference}; sensing "
                f"{num(_sensing_minutes(on))} -> {num(_sensing_minutes(exhaustive))} min, grasps tried as features "
                f"{num(_per_object(on, 'grasps_as_features'), 2)} -> "
                f"{num(_per_object(exhaustive, 'grasps_as_features'), 2)} per object)",
                ratio(saving, figures.EXHAUSTIVE_EXECUTION_SAVING))
    for criterion, seeds in ((DEFAULT_CRITERION, config.seed_list), (PAPER_CRITERION, criteria_seeds(config))):
        rows.append(both(f"exhaustive-training library vs chosen positions, `{criterion}`: execution cheaper by",
                         f"~{percent(figures.EXHAUSTIVE_EXECUTION_SAVING)}",
                         lambda c, criterion=criterion, seeds=seeds: exhaustive_cheaper(c, criterion, seeds)))

    def bar(rs: Sequence[EpisodeRow]) -> tuple[float, float]:
        return robot_minutes(rs), _stderr_min(rs)
    groups = {name: {c.name: bar(runs(name, c)) for c in BOTH} for name in names}
    groups["strategies off"] = {c.name: bar(_rows(results, [_strategies_off("test", s, c) for s in config.seed_list]))
                                for c in BOTH}
    groups["exhaustive lib."] = {c.name: bar(_rows(results, [_exhaustive(s, c) for s in config.seed_list]))
                                 for c in BOTH}
    bars(out / "baselines.png", f"robot minutes per test object (noise {EXECUTION_NOISE}, ± s.e.)", "minutes",
         groups)
    left_out = sorted(set(MEASURED) - set(names))
    notes = (f"Every criterion runs the same {len(seeds)} test floor(s) under noise `{EXECUTION_NOISE}`, in the "
             "paper's conditions (no appearance) and with our defaults"
             + (f" (quick: {', '.join(left_out)} left out)" if left_out else "") + "; "
             f"`{COST_BLIND}` is the cost-blind baseline: ID3's information gain alone, a tie between equally "
             "informative tests going to the nearer one and a test valid at any orientation (`*`) taken where the "
             f"robot stands, so nothing is left to chance; `{RANDOM_ID3}` is the same gain with ties and `*` positions "
             "drawn at random (a random distance and orientation), kept as a labelled extra row because no one would "
             f"call that ID3's behaviour. Saving = 1 - ours / `{COST_BLIND}`'s mean robot "
             "time per object (the paper's 30% counts classification alone: the parenthesis leaves out grasping); "
             "per object: the paired difference in robot minutes.",
             "Strategies off: nearest neighbour at once (no reselection, no backtracking, N = 1); a failed grasp "
             "is still recovered, as Table 7 requires. The paper's 'performance' is read two ways: the success "
             "rate, and the share of objects whose first grasp was right (handled with no grasp failing at a leaf, "
             "so no failed-grasp recovery needed); each gain is relative, with the paired difference in points "
             "(± its standard error over the seeds). Reselections and backtracks are counted per object with the "
             "strategies on.",
             "Exhaustive library: every procedure at every chosen training position, merged as training merges; "
             "its richer descriptions offer tests (scans) that tell more for more robot time, and the one-step "
             "rule buys them where the trained library's tree would try a grasp as a feature "
             "(docs/method.md, \"Findings\"). Measured with the default rule on every floor and with the paper's "
             f"`{PAPER_CRITERION}` on the criteria's floors, each against the trained library under the same rule; "
             "per object: the paired difference, exhaustive minus trained.",
             "Measure every feature: every sensing procedure in range at each training position (a round object: "
             "one orientation), the moves between them at 2 s/in, and the grasp; mean over the training objects "
             "(no camera: one value for both conditions). A round object needs one orientation, so the mean "
             "depends on how many of the training objects are round; the second row gives both kinds.")
    return StudyResult(BASELINES_TITLE, tuple(rows), notes, ("baselines.png",), both_conditions=True)


EXECUTION = Study("execution", plan_execution, lambda context, results: summarise_execution(context.config, results))
BASELINES = Study("baselines", plan_baselines, lambda context, results: summarise_baselines(
    context.config, results, context.trained.log, context.trained.knowledge, context.plots))
