"""The whole ``csl experiment paper`` run: train, run every study's jobs in one pool,
summarise each study, and write ``results.md``, its plots and the raw CSV.

Every study plans its jobs first and summarises after, so all episodes of all studies
share one pool of worker processes (the machine stays busy until the last job) and
jobs two studies share run once.
"""

from __future__ import annotations

import datetime
import os
import platform
import resource
import time
from collections.abc import Sequence
from dataclasses import dataclass
from pathlib import Path

from rich.console import Console

from robot_profile import load_profile

from experiments import (study_appearance, study_execution, study_grasp_costs, study_incremental, study_noise,
                                  study_optimum, study_trends)
from experiments.config import ExperimentConfig
from experiments.csvfile import write_episodes
from experiments.episodes import EpisodeRow, EpisodeSpec, install_worker
from experiments.runner import run_all
from experiments.study_training import run_training
from experiments.table import StudyResult, section

RESULTS_DIR = "results"
CSV_NAME = "episodes.csv"


@dataclass(frozen=True)
class PaperRun:
    """What a run wrote and did: the studies' results, the page, and its counts."""

    studies: tuple[StudyResult, ...]
    page: Path
    csv: Path
    episodes: int
    object_rows: int
    wall_s: float
    cpu_s: float


def perform(job: EpisodeSpec | study_optimum.OptimumJob | study_grasp_costs.GraspCostJob) -> list[object]:
    """A worker's entry point: run one job (module level, so spawned workers can import it)."""
    return list(job.run())


def _study_of(job: EpisodeSpec | study_optimum.OptimumJob | study_grasp_costs.GraspCostJob) -> str:
    return job.study


def run_paper(config: ExperimentConfig, console: Console | None = None) -> PaperRun:
    console = console or Console(stderr=True)
    began = time.perf_counter()
    plots = config.out / RESULTS_DIR
    plots.mkdir(parents=True, exist_ok=True)
    profile = load_profile()
    with console.status("training on the Table 3 objects (and exhaustively, for the baseline)..."):
        trained = run_training(profile)
    libraries = {"trained": trained.descriptions, "exhaustive": trained.exhaustive}
    episodes: list[EpisodeSpec] = [*study_execution.plan(config), *study_trends.plan(config),
                                   *study_incremental.plan(config), *study_noise.plan(config),
                                   *study_appearance.plan(config)]
    optimum_jobs = study_optimum.plan(config)
    # the longest jobs first (the optimum's, then chains of episodes), so no long one
    # starts last and leaves a worker idle at the end
    jobs = [*optimum_jobs, *study_grasp_costs.plan(config), *sorted(episodes, key=lambda spec: -spec.episodes)]
    results = run_all(jobs, perform, workers=config.jobs, group=_study_of,
                      initializer=install_worker, initargs=(libraries, profile), console=console)
    with console.status("summarising and plotting..."):
        studies = (
            trained.study,
            study_execution.summarise_execution(config, results),
            study_execution.summarise_baselines(config, results, trained.log, trained.knowledge, plots),
            study_trends.summarise(config, results, plots, trained.descriptions, trained.knowledge),
            study_incremental.summarise(config, results, plots),
            study_noise.summarise(config, results, plots),
            study_appearance.summarise(config, results),
            study_optimum.summarise(config, results, plots),
            study_grasp_costs.summarise(config, results),
        )
        ran = list(dict.fromkeys(episodes))
        rows: list[EpisodeRow] = [row for spec in ran for row in results[spec]]
        csv_path = plots / CSV_NAME
        count = write_episodes(csv_path, rows)
        wall_s = time.perf_counter() - began
        cpu_s = _cpu_s()
        n_episodes = sum(spec.episodes for spec in ran)
        page = config.out / "results.md"
        page.write_text("\n".join(_page(config, studies, n_episodes, count, wall_s, cpu_s)), encoding="utf-8")
    return PaperRun(studies, page, csv_path, n_episodes, count, wall_s, cpu_s)


def _cpu_s() -> float:
    """CPU seconds of this process and its finished workers: the run's size on any
    machine, where wall time also depends on what else the machine is doing."""
    own = resource.getrusage(resource.RUSAGE_SELF)
    workers = resource.getrusage(resource.RUSAGE_CHILDREN)
    return own.ru_utime + own.ru_stime + workers.ru_utime + workers.ru_stime


def _page(config: ExperimentConfig, studies: Sequence[StudyResult], episodes: int, rows: int,
          wall_s: float, cpu_s: float) -> list[str]:
    now = datetime.datetime.now(datetime.timezone.utc).strftime("%Y-%m-%d %H:%M UTC")
    machine = f"{platform.system()} {platform.machine()}, {os.cpu_count()} CPUs, Python {platform.python_version()}"
    lines = [
        "# Results: the paper's experiment in the simulator",
        "",
        f"*Generated by `{config.command}`; do not edit by hand, re-run the command instead.*",
        "",
        f"- command: `{config.command}`{' (quick: fewer seeds and sweep points)' if config.quick else ''}",
        f"- seeds: {config.seeds} (0 to {config.seeds - 1}); each seed lays the floor out anew",
        f"- machine: {machine}; {config.jobs} worker process(es)",
        f"- date: {now}; wall time {wall_s:.0f} s, {cpu_s:.0f} CPU seconds",
        f"- episodes: {episodes}, {rows} object rows in [`{RESULTS_DIR}/{CSV_NAME}`]({RESULTS_DIR}/{CSV_NAME}) "
        "(one row per object per episode, every condition in its columns)",
        "",
        "Every row: what is measured, the paper's figure (Tan & Schlimmer 1991, as docs/method.md restates "
        "it), ours, and ours / paper. Robot time is simulated seconds of the HERO 2000 profile.",
        "",
    ]
    for number, study in enumerate(studies, 1):
        lines += section(study, number)
    return lines
