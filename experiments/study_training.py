"""Study 1: training on the Table 3 objects — positions found and robot time spent.

Runs in the main process (about a second): its descriptions are the library every
execution episode starts from, and its positions price the exhaustive baselines.
Training is noise-free, as ``csl demo`` trains: the paper trained once, carefully.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

from experiments import figures
from experiments.exhaustive import exhaustive_library
from experiments.table import ResultRow, StudyResult, num, ratio
from executive.sim_training import ground_truth, train_in_simulator
from learner.costs import ModelMoveCost
from learner.description import ObjectDescription
from learner.knowledge import Knowledge
from learner.training.stage import TrainingLog, train
from robot_profile import RobotProfile

TITLE = "Training on the Table 3 objects"
ORIENTATION_MATCH_DEG = 5.0


@dataclass(frozen=True)
class Trained:
    """What training produced, for the studies that build on it."""

    study: StudyResult
    descriptions: tuple[ObjectDescription, ...]
    exhaustive: tuple[ObjectDescription, ...]
    log: TrainingLog
    knowledge: Knowledge


def run_training(profile: RobotProfile) -> Trained:
    knowledge = profile.knowledge()
    trained = train_in_simulator(knowledge, profile)  # as `csl train --sim` (seed 0): footprints from the camera
    objects, source, result, summary = list(trained.seen.objects), trained.source, trained.result, trained.summary
    log = result.log
    fidelity = ground_truth(result.descriptions, trained.seen, knowledge, summary, profile)
    exhaustive, exhaustive_s = exhaustive_library(objects, knowledge, source, log.distances, log.orientations)
    at_papers = train(objects, knowledge, source, ModelMoveCost(knowledge.move),
                      distances=figures.TRAINING_DISTANCES_IN).log  # the what-if: the paper's distances
    hours = summary.robot_hours
    years = summary.exhaustive_years
    matched = sum(any(abs((o - p + 180) % 360 - 180) <= ORIENTATION_MATCH_DEG for o in log.orientations)
                  for p in figures.TRAINING_ORIENTATIONS_DEG)
    distance_ratios = ", ".join(f"{o / p:.2f}" for o, p in zip(log.distances, figures.TRAINING_DISTANCES_IN))
    rows = (
        ResultRow("training orientations (deg)", _list(figures.TRAINING_ORIENTATIONS_DEG), _list(log.orientations),
                  f"{matched}/{len(figures.TRAINING_ORIENTATIONS_DEG)} within {ORIENTATION_MATCH_DEG:g}°"),
        ResultRow("training distances (in)", _list(figures.TRAINING_DISTANCES_IN), _list(log.distances),
                  distance_ratios if len(log.distances) == len(figures.TRAINING_DISTANCES_IN) else "-"),
        ResultRow("training robot time (h)", f"~{figures.TRAINING_HOURS:g}", num(hours),
                  ratio(hours, figures.TRAINING_HOURS)),
        ResultRow("of it, sensing at (object, position) pairs no procedure usable there classifies (h; "
                  "phase 2 applies every usable procedure before it gives up)", "-",
                  f"{num(unresolved_hours(log, knowledge))} at {len(set(log.unresolved))} pairs"),
        ResultRow("training robot time at the paper's distances (h; a what-if)", f"~{figures.TRAINING_HOURS:g}",
                  f"{num(at_papers.total_s / 3600)} ({num(unresolved_hours(at_papers, knowledge))} at "
                  f"{len(set(at_papers.unresolved))} unclassifiable pairs)",
                  ratio(at_papers.total_s / 3600, figures.TRAINING_HOURS)),
        ResultRow("exhaustive training, every procedure on a 1 in x 1° grid (years, sensing only; arithmetic on "
                  "a grid the paper does not give, not a measurement)",
                  f"> {figures.EXHAUSTIVE_TRAINING_YEARS:g}", num(years)),
        ResultRow("exhaustive training at the chosen positions (h, sensing only)", "-", num(exhaustive_s / 3600)),
        ResultRow("library values off the simulator's exact value by more than the expected error", "-",
                  f"{len(fidelity.misfits)} of {fidelity.checked}"),
    )
    notes = (
        f"{len(objects)} training objects, {summary.descriptions} descriptions, {summary.observations} feature "
        f"values (exhaustive: {sum(len(d.observations) for d in exhaustive)}); {summary.applications} procedure "
        f"applications, {summary.sensing_s / 3600:.1f} h sensing and {summary.moving_s / 3600:.1f} h moving.",
        "Robot time counts every sensing procedure applied (phase 1's size scans included) and the "
        "moves between an object's training positions by the profile's move model (2 s/in).",
        distances_note(log),
    )
    study = StudyResult(TITLE, rows, notes)
    return Trained(study, tuple(result.descriptions), tuple(exhaustive), log, knowledge)


def unresolved_hours(log: TrainingLog, knowledge: Knowledge) -> float:
    """Hours of sensing spent on (object, position) pairs phase 2 could not classify."""
    unresolved = set(log.unresolved)
    time_s = {p.name: p.time_s for p in knowledge.sensing}
    return sum(time_s[proc] for oid, proc, at, _ in log.applied if (oid, at) in unresolved) / 3600.0


def distances_note(log: TrainingLog) -> str:
    """Where the training distances come from: the candidates (each the farthest a sweep
    still separates two similar-sized objects of different grasps) each chosen distance
    stands for, and the farthest candidate's reason."""
    candidates = sorted(r.distance_in for r in log.distance_reasons)
    bounds = [*log.distances[1:], math.inf]
    counts = [sum(1 for c in candidates if low <= c < high) for low, high in zip(log.distances, bounds)]
    below = sum(1 for c in candidates if c < log.distances[0]) if log.distances else 0
    far = max(log.distance_reasons, key=lambda r: r.distance_in, default=None)
    stands = ", ".join(f"{d:g} in: {n}" for d, n in zip(log.distances, counts))
    why = (f" The farthest, {far.distance_in:.1f} in ({far.feature} separating {far.object_a} from "
           f"{far.object_b}), keeps a distance of its own: clusters merge where neighbours are closest in ratio, "
           "so the candidates between the second and the farthest join the nearer cluster, whose distance still "
           "separates them." if far is not None else "")
    return (f"Training distances: {len(candidates)} candidates (each the farthest a sweep still separates two "
            f"similar-sized objects of different grasps), clustered to at most three, each represented by its "
            f"nearest candidate; the candidates each distance stands for: {stands}"
            + (f" ({below} nearer than the first)" if below else "") + "." + why)


def _list(values: tuple[float, ...] | list[float]) -> str:
    return ", ".join(f"{v:g}" for v in values)
