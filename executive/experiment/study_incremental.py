"""Study 5: incremental learning — a learning curve over repeated episodes.

A chain is one learner store running several test floors in turn (each laid out anew),
so every episode starts from what the earlier ones learned (docs/method.md §5, step
3: a successful grasp saves the object's description). The paper's story to check:
the upside-down tumbler, misclassified once, is classified right the next time.
"""

from __future__ import annotations

from pathlib import Path

from executive.experiment.conditions import EXECUTION_NOISE
from executive.experiment.config import ExperimentConfig
from executive.experiment.episodes import EpisodeRow, EpisodeSpec, Results
from executive.experiment.plots import Panel, curves
from executive.experiment.table import ResultRow, StudyResult, mean, num, percent

TITLE = "Incremental learning: the learning curve"
TUMBLER = "tumbler-20oz/upside-down"



def _spec(config: ExperimentConfig, seed: int) -> EpisodeSpec:
    return EpisodeSpec("incremental", f"chain of {config.chain_length}", seed, noise=EXECUTION_NOISE,
                       episodes=config.chain_length)


def plan(config: ExperimentConfig) -> list[EpisodeSpec]:
    return [_spec(config, s) for s in config.chain_seeds]


def _misclassified(row: EpisodeRow) -> bool:
    """A wrong grasp at a leaf, or not handled at all."""
    return row.wrong_grasps > 0 or not row.success


def summarise(config: ExperimentConfig, results: Results, out: Path) -> StudyResult:
    chains = [results[_spec(config, s)] for s in config.chain_seeds]
    episodes = range(config.chain_length)
    errors = [mean(float(_misclassified(r)) for c in chains for r in c if r.episode == e) for e in episodes]
    minutes = [mean(r.robot_s for c in chains for r in c if r.episode == e) / 60.0 for e in episodes]
    sizes = [mean(float(r.library_size) for c in chains for r in c if r.episode == e) for e in episodes]
    first_wrong = 0
    then_right = 0
    for chain in chains:
        encounters = sorted((r for r in chain if r.object == TUMBLER), key=lambda r: r.episode)
        wrong_at = next((i for i, r in enumerate(encounters) if _misclassified(r)), None)
        if wrong_at is not None and wrong_at + 1 < len(encounters):
            first_wrong += 1
            then_right += not _misclassified(encounters[wrong_at + 1])
    last = config.chain_length
    rows = (
        ResultRow(f"objects misclassified, episode 1 -> {last}", "falls as the library grows",
                  f"{percent(errors[0])} -> {percent(errors[-1])}"),
        ResultRow(f"robot min per object, episode 1 -> {last}", "-", f"{num(minutes[0])} -> {num(minutes[-1])}"),
        ResultRow(f"library size, episode 1 -> {last}", "-", f"{num(sizes[0], 0)} -> {num(sizes[-1], 0)}"),
        ResultRow("upside-down tumbler: right at the encounter after a misclassification",
                  "right the next time",
                  f"{then_right} of {first_wrong} chains" if first_wrong else "never misclassified",
                  f"{then_right / first_wrong:.2f}" if first_wrong else "-"),
    )
    xs = [e + 1 for e in episodes]
    curves(out / "learning-curve.png", [
        Panel("errors", "episode", "objects misclassified", {"share": (xs, errors)}),
        Panel("cost", "episode", "robot min / object", {"mean": (xs, minutes)}),
        Panel("library", "episode", "descriptions at the start", {"mean": (xs, sizes)}),
    ])
    notes = (f"{len(chains)} chain(s) of {last} episodes on the test objects under noise `{EXECUTION_NOISE}`; "
             "every episode is a fresh random layout, the learner store is kept.",
             "Misclassified: a grasp executed at a leaf failed, or the object was not handled. The tumbler row "
             "counts chains where it was misclassified at some encounter with one more encounter after it.")
    return StudyResult(TITLE, rows, notes, ("learning-curve.png",))
