"""One study framework: a study declares its jobs and how to read their results; training,
the worker pool, progress and the run's sections are written here once.

Every study of ``csl experiment`` is a :class:`Study`: ``plan(config)`` lists its jobs
(frozen values with a ``study`` label and a ``run()`` that plays them in a worker
process), ``summarise(context, results)`` turns their results into a
:class:`~experiments.table.StudyResult` (rows, details, notes, plots). The paper's page
(``experiments.paper``) and the changing-world sections for BENCHMARKS.md
(``experiments.situation``) are both :func:`run_studies` and a writer of sections, so a
new study is one module with a ``STUDY`` and its line in one of those lists.
"""

from __future__ import annotations

import time
from collections.abc import Callable, Hashable, Mapping, Sequence
from dataclasses import dataclass
from pathlib import Path
from typing import Any, Protocol

from rich.console import Console

from experiments.config import ExperimentConfig
from experiments.worker import install_worker
from experiments.runner import run_all
from experiments.study_training import Trained, run_training
from experiments.table import StudyResult
from robot_profile import load_profile

RESULTS_DIR = "results"  # beside the page: its plots and raw CSV

Results = Mapping[Any, Sequence[Any]]  # every job of the run and what it returned; a study reads its own


class Job(Hashable, Protocol):
    """One unit of work: equal jobs run once, whichever studies plan them."""

    @property
    def study(self) -> str:
        """The progress bar it counts under."""

    def run(self) -> Any:
        """Play it here (a worker process, given the run's libraries and profile)."""


@dataclass(frozen=True)
class Context:
    """What a summary may read beyond its jobs' results: the run's size and where it
    writes, and what training produced (the library, its log, the knowledge)."""

    config: ExperimentConfig
    trained: Trained

    @property
    def plots(self) -> Path:
        """The folder for the study's figures (the page's writer creates it)."""
        return self.config.out / RESULTS_DIR


@dataclass(frozen=True)
class Study:
    """A study: its name, its jobs for a run's size, its section from their results.
    ``floors``: floors per sweep point (quick, full) when the command line gives no
    ``--seeds`` (the changing-world studies; the paper's studies size by the config)."""

    name: str
    plan: Callable[[ExperimentConfig], Sequence[Job]]
    summarise: Callable[[Context, Results], StudyResult]
    floors: tuple[int, int] = (0, 0)


TRAINING = Study("training", lambda config: (), lambda context, results: context.trained.study)
"""Training's own section: it runs before every study (its library is where they start)."""


@dataclass(frozen=True)
class Ran:
    """A run of studies: what training produced, every job's results, one section per
    study in the order given, and the wall time."""

    trained: Trained
    results: dict[Any, Any]
    sections: tuple[StudyResult, ...]
    wall_s: float


def perform(job: Job) -> Any:
    """A worker's entry point (module level, so spawned workers can import it)."""
    return job.run()


def longest_first(jobs: Sequence[Job]) -> list[Job]:
    """Jobs without an episode count (the optimum's searches) first, then chains by
    length, so no long job starts last and leaves a worker idle at the end; stable."""
    return sorted(jobs, key=lambda job: (hasattr(job, "episodes"), -getattr(job, "episodes", 0)))


def run_studies(studies: Sequence[Study], config: ExperimentConfig, console: Console | None = None) -> Ran:
    """Train on the Table 3 objects (and exhaustively, for the baseline), run every
    study's jobs in one pool of ``config.jobs`` workers (jobs two studies share run
    once), and summarise each study."""
    console = console or Console(stderr=True)
    began = time.perf_counter()
    profile = load_profile()
    with console.status("training on the Table 3 objects (and exhaustively, for the baseline)..."):
        trained = run_training(profile)
    planned = list(dict.fromkeys(job for study in studies for job in study.plan(config)))
    libraries = {"trained": trained.descriptions, "exhaustive": trained.exhaustive}
    done = run_all(longest_first(planned), perform, workers=config.jobs, group=lambda job: job.study,
                   initializer=install_worker, initargs=(libraries, profile), console=console)
    results = {job: done[job] for job in planned}  # the studies' order, whatever order they ran in
    context = Context(config, trained)
    with console.status("summarising..."):
        sections = tuple(study.summarise(context, results) for study in studies)
    return Ran(trained, results, sections, time.perf_counter() - began)
