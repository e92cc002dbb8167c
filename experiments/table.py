"""Result rows (what is measured, the paper's figure, ours in the paper's conditions and
its ratio, ours with our defaults) and each study's section of ``results.md``.

Every number in a row is formatted here, so the table reads the same from study to
study; ratios are ours divided by the paper's, left as ``-`` where the paper gave a
direction or a bound rather than a number (``> 80%``), where its figure is not
comparable (a 1991 computer's time), and on rows that are arithmetic rather than
measurement (said so in the row).
"""

from __future__ import annotations

import math
import statistics
from collections.abc import Callable, Iterable, Sequence
from dataclasses import dataclass, field

from experiments.conditions import OURS, PAPERS, Conditions

HEADERS = ("measured", "paper", "ours", "ours / paper")
BOTH_HEADERS = ("measured", "paper", "ours, paper's conditions", "ours / paper", "ours, our defaults")
SAME = "same"  # the last column of a row the conditions do not touch


@dataclass(frozen=True)
class ResultRow:
    """One line of the results table: ``ours`` (with our defaults, in a study measured
    both ways) and ``ratio``, ours / the paper's; ``as_paper`` measured in the paper's
    conditions and its ratio (``experiments.conditions.Conditions``), None when the
    conditions do not touch what the row measures, so one value holds for both."""

    measured: str
    paper: str
    ours: str
    ratio: str = "-"
    as_paper: str | None = None
    as_paper_ratio: str = "-"

    def cells(self) -> tuple[str, str, str, str]:
        return (self.measured, self.paper, self.ours, self.ratio)

    def both_cells(self) -> tuple[str, str, str, str, str]:
        """The row in a study measured in both conditions (:data:`BOTH_HEADERS`)."""
        if self.as_paper is None:
            return (self.measured, self.paper, self.ours, self.ratio, SAME)
        defaults = self.ours if self.ratio == "-" else f"{self.ours} (ratio {self.ratio})"
        return (self.measured, self.paper, self.as_paper, self.as_paper_ratio, defaults)


@dataclass(frozen=True)
class StudyResult:
    """What a study reports: its rows, notes that say how to read them, its plots (file
    names beside ``results.md``)."""

    title: str
    rows: tuple[ResultRow, ...] = ()
    notes: tuple[str, ...] = ()
    plots: tuple[str, ...] = ()
    details: tuple[tuple[tuple[str, ...], tuple[tuple[str, ...], ...]], ...] = field(default=())
    # extra tables: (headers, rows) each
    both_conditions: bool = False  # its rows are measured in the paper's conditions and with our defaults




def both(measured: str, paper: str, cell: Callable[[Conditions], tuple[str, str]]) -> ResultRow:
    """A row measured in both conditions: ``cell(conditions)`` gives the value's text and
    its ratio to the paper's figure, in the paper's conditions and with our defaults."""
    as_paper, as_paper_ratio = cell(PAPERS)
    ours, ours_ratio = cell(OURS)
    return ResultRow(measured, paper, ours, ours_ratio, as_paper, as_paper_ratio)


def ratio(ours: float | None, paper: float) -> str:
    if ours is None or not math.isfinite(ours) or paper == 0:
        return "-"
    return f"{ours / paper:.2f}"


def mean(values: Iterable[float]) -> float:
    """The mean, NaN for no values (shown as ``-``): a study with nothing to average
    says so instead of failing."""
    data = list(values)
    return statistics.fmean(data) if data else math.nan


def paired_difference(a: Sequence[float], b: Sequence[float]) -> tuple[float, float]:
    """Mean of the paired differences ``a - b`` and its standard error: the same floors
    run both ways, so pairing by seed removes most of the floors' own spread."""
    differences = [x - y for x, y in zip(a, b, strict=True)]
    if not differences:
        return math.nan, math.nan
    spread = statistics.stdev(differences) / math.sqrt(len(differences)) if len(differences) > 1 else math.nan
    return statistics.fmean(differences), spread


def paired(a: Sequence[float], b: Sequence[float], digits: int = 2, unit: str = "") -> str:
    """``a - b`` paired by seed, as a row writes it: the mean difference ± its standard
    error and the number of seeds behind it; one seed is said to be a smoke value, so
    nobody reads it as a result."""
    difference, error = paired_difference(a, b)
    if len(a) < 2:
        return f"{num(difference, digits, unit)}, 1 seed: a smoke value, not a result"
    return f"{num(difference, digits)} ± {num(error, digits, unit)} over {len(a)} seeds"


def num(value: float | None, digits: int = 1, unit: str = "") -> str:
    if value is None or not math.isfinite(value):
        return "-"
    return f"{value:.{digits}f}{unit}"


def percent(value: float | None) -> str:
    if value is None or not math.isfinite(value):
        return "-"
    return f"{100 * value:.0f}%"


def markdown_table(headers: Sequence[str], rows: Iterable[Sequence[str]]) -> list[str]:
    """A GitHub markdown table; pipes inside cells are escaped."""
    def line(cells: Sequence[str]) -> str:
        return "| " + " | ".join(str(c).replace("|", "\\|") for c in cells) + " |"

    return [line(headers), line(["---"] * len(headers)), *(line(r) for r in rows)]


def section(result: StudyResult, number: int) -> list[str]:
    """The markdown of one study: heading, table, notes, plots."""
    lines = [f"## {number}. {result.title}", ""]
    if result.both_conditions:
        lines += markdown_table(BOTH_HEADERS, (r.both_cells() for r in result.rows))
    else:
        lines += markdown_table(HEADERS, (r.cells() for r in result.rows))
    lines.append("")
    for headers, rows in result.details:
        lines += [*markdown_table(headers, rows), ""]
    lines += [f"- {note}" for note in result.notes]
    if result.notes:
        lines.append("")
    lines += [f"![{name}](results/{name})" for name in result.plots]
    if result.plots:
        lines.append("")
    return lines
