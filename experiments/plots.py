"""The experiment's PNG figures: bars with error bars, and curves in side-by-side panels.

Deliberately generic (labels and numbers in, a file out): each study decides what to
draw, and a user re-plotting from the CSV can call the same two functions.
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from dataclasses import dataclass
from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
from matplotlib.axes import Axes  # noqa: E402
from matplotlib.ticker import MaxNLocator  # noqa: E402


@dataclass(frozen=True)
class Panel:
    """One panel of curves: ``series`` maps a legend label to (x values, y values)."""

    title: str
    xlabel: str
    ylabel: str
    series: Mapping[str, tuple[Sequence[float], Sequence[float]]]
    logx: bool = False


def bars(path: Path, title: str, ylabel: str, groups: Mapping[str, Mapping[str, tuple[float, float]]],
         reference: tuple[float, str] | None = None) -> None:
    """Grouped bars: ``groups[group][bar] = (value, error)``; an optional horizontal
    reference line (value, label), e.g. the optimum at 1.0."""
    names = list(groups)
    bar_names = list(dict.fromkeys(b for g in groups.values() for b in g))
    width = 0.8 / max(len(bar_names), 1)
    fig, ax = plt.subplots(figsize=(min(14.0, max(6.0, 0.9 * len(names) * len(bar_names) ** 0.5)), 4.2))
    for k, bar in enumerate(bar_names):
        xs = [i + (k - (len(bar_names) - 1) / 2) * width for i, g in enumerate(names) if bar in groups[g]]
        ys = [groups[g][bar][0] for g in names if bar in groups[g]]
        es = [groups[g][bar][1] for g in names if bar in groups[g]]
        ax.bar(xs, ys, width=width * 0.95, yerr=es, capsize=3, label=bar if len(bar_names) > 1 else None)
    if reference is not None:
        ax.axhline(reference[0], color="black", linestyle="--", linewidth=1, label=reference[1])
    ax.set_xticks(range(len(names)), names, rotation=30 if len(names) > 4 else 0, ha="right" if len(names) > 4
                  else "center", fontsize=8)
    ax.set_ylabel(ylabel)
    ax.set_title(title)
    if len(bar_names) > 1 or reference is not None:
        ax.legend(fontsize=8)
    fig.tight_layout()
    fig.savefig(path, dpi=110)
    plt.close(fig)


def curves(path: Path, panels: Sequence[Panel]) -> None:
    """Panels side by side, one line with markers per series."""
    fig, axes = plt.subplots(1, len(panels), figsize=(5.2 * len(panels), 4.0), squeeze=False)
    for ax, panel in zip(axes[0], panels):
        draw_panel(ax, panel)
    fig.tight_layout()
    fig.savefig(path, dpi=110)
    plt.close(fig)


def draw_panel(ax: Axes, panel: Panel) -> None:
    """One panel on ``ax``. An x axis of whole numbers only (episodes, runs) is ticked
    at whole numbers: matplotlib would put a tick at episode 1.5, which does not exist."""
    for label, (xs, ys) in panel.series.items():
        ax.plot(list(xs), list(ys), marker="o", label=label)
    if panel.logx:
        ax.set_xscale("log", base=2)
    elif all(float(x).is_integer() for xs, _ in panel.series.values() for x in xs):
        ax.xaxis.set_major_locator(MaxNLocator(integer=True))
    ax.set_title(panel.title, fontsize=10)
    ax.set_xlabel(panel.xlabel)
    ax.set_ylabel(panel.ylabel)
    ax.grid(alpha=0.3)
    if len(panel.series) > 1:
        ax.legend(fontsize=7)
