"""What the changing-world studies share (``csl experiment disturbance | battery |
obstacles | clutter``): the trained library handed to each worker process, the run from
training to the Markdown section for BENCHMARKS.md, and that section's layout.

Each study module keeps what is its own (the sweep, the floor, what one object's row
records, the summary); this module is why they print and run alike.
"""

from __future__ import annotations

import time
from collections.abc import Callable, Hashable, Mapping, Sequence
from typing import TypeVar

from experiments.runner import run_all
from experiments.table import StudyResult, markdown_table
from learner.description import ObjectDescription
from robot_profile import RobotProfile

Job = TypeVar("Job", bound=Hashable)

_INSTALLED: list[tuple[tuple[ObjectDescription, ...], RobotProfile]] = []


def install(descriptions: Sequence[ObjectDescription], profile: RobotProfile) -> None:
    """Give this process the trained library and the robot profile (the pool's initializer)."""
    _INSTALLED[:] = [(tuple(descriptions), profile)]


def installed() -> tuple[tuple[ObjectDescription, ...], RobotProfile]:
    """The library and profile :func:`install` gave this worker."""
    if not _INSTALLED:
        raise ValueError("no trained library was installed in this worker")
    return _INSTALLED[0]


def markdown(study: StudyResult, command: str, wall_s: float) -> str:
    """The study as a Markdown section for BENCHMARKS.md (its tables written as
    docs/results.md's are, :func:`~experiments.table.markdown_table`; no ratio column,
    since these studies go beyond the paper)."""
    lines = [f"### {study.title}", "", f"`{command}` ({wall_s:.0f} s wall)", ""]
    lines += markdown_table(("measured", "paper", "ours"), ((r.measured, r.paper, r.ours) for r in study.rows))
    for headers, body in study.details:
        lines += ["", *markdown_table(headers, body)]
    lines += ["", *study.notes]
    return "\n".join(lines)


def report(name: str, quick: bool, seeds: int | None, jobs: int, default_floors: tuple[int, int],
           plan: Callable[[Sequence[int]], Sequence[Job]], run_job: Callable[[Job], object],
           summarise: Callable[[Mapping[Job, object]], StudyResult]) -> str:
    """Train on the Table 3 objects, run ``plan(floors)``'s jobs (``run_job`` in ``jobs``
    worker processes, each given the library), and give ``summarise``'s section headed
    by the command that reproduces it. ``default_floors``: floors per cell (quick, full)
    when ``seeds`` is not given."""
    from experiments.study_training import run_training  # training: only when a study runs
    from robot_profile import load_profile

    began = time.perf_counter()
    profile = load_profile()
    trained = run_training(profile)
    floors = list(range(seeds or default_floors[0 if quick else 1]))
    results = run_all(list(plan(floors)), run_job, workers=jobs, group=lambda job: job.study,  # type: ignore[attr-defined]
                      initializer=install, initargs=(trained.descriptions, profile))
    command = f"csl experiment {name}" + "".join(
        [" --quick" if quick else "", f" --seeds {seeds}" if seeds else "", f" --jobs {jobs}"])
    return markdown(summarise(results), command, time.perf_counter() - began)
