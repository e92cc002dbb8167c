"""What the changing-world studies share (``csl experiment disturbance | battery |
obstacles | clutter``): one study run through :func:`~experiments.study.run_studies`
and its section for BENCHMARKS.md, headed by the command that reproduces it.

Each study module keeps what is its own (the sweep, the floor, what one object's row
records, the summary) and declares it as a ``STUDY``; this module is why they print
and run alike.
"""

from __future__ import annotations

from pathlib import Path

from experiments.config import ExperimentConfig, parse_seeds
from experiments.study import Study, run_studies
from experiments.table import StudyResult, markdown_table


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


def report(study: Study, quick: bool, seeds: str | None, jobs: int) -> str:
    """Train on the Table 3 objects, run ``study``'s jobs on the floors ``seeds`` names
    (:func:`~experiments.config.parse_seeds`; default: the first of its ``floors``,
    quick or full) in ``jobs`` worker processes, and give its section."""
    command = f"csl experiment {study.name}" + "".join(
        [" --quick" if quick else "", f" --seeds {seeds}" if seeds else "", f" --jobs {jobs}"])
    floors = parse_seeds(seeds) if seeds else tuple(range(study.floors[0 if quick else 1]))
    ran = run_studies([study], ExperimentConfig(quick, floors, jobs, Path("."), command))
    return markdown(ran.sections[0], command, ran.wall_s)
