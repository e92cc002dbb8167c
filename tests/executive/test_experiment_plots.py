"""The experiment's curves: an axis of episodes is ticked at episodes."""

from __future__ import annotations

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

from experiments.plots import Panel, draw_panel  # noqa: E402


def _ticks(xs: list[float]) -> list[float]:
    """The x ticks matplotlib shows (within the axis) for one series at ``xs``."""
    fig, ax = plt.subplots()
    try:
        draw_panel(ax, Panel("t", "episode", "y", {"a": (xs, [1.0] * len(xs))}))
        fig.canvas.draw()
        low, high = ax.get_xlim()
        return [t for t in ax.get_xticks() if low <= t <= high]
    finally:
        plt.close(fig)


def test_three_episodes_are_ticked_1_2_3_not_at_halves() -> None:
    """Left to itself matplotlib ticks x = 1, 2, 3 every quarter (episode 1.25 does
    not exist); whole-number x values get whole-number ticks."""
    assert _ticks([1, 2, 3]) == [1.0, 2.0, 3.0]


def test_fractional_x_values_keep_fractional_ticks() -> None:
    """A noise factor of 0.5 is a value: its axis is not forced to whole numbers."""
    assert [t for t in _ticks([0.5, 1.0, 1.5]) if not t.is_integer()]
