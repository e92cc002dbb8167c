"""The map a robot built from its own range scans, drawn beside the true one.

Without a ceiling camera there is no overhead image to draw a run on: what the robot
knows of the home is the occupancy grid its scans built (``mapping``). So an onboard
run's ``map.png`` is that grid in the map_server's shades (free light, unknown mid-grey,
occupied black: :func:`mapping.map_image`), with the route the robot drove (the scan
matcher's corrected pose at each scan, joined in order; and each move to an object as
the planner laid it, since a straight line between two scans far apart may cut through
a wall the robot went round) and the objects it found (their outlines as the scans saw
them, coloured by outcome); and, when the world is the simulator's, beside it
the true map (``hero_driver.sim.truth_map``) with where the objects really were, on the
same axes, so a wall the scans put in the wrong place or an object never found shows at
a glance. ``bench/bench_mapping_sim.py`` draws its maps with the same function.
"""

from __future__ import annotations

from collections.abc import Sequence
from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402
from matplotlib.axes import Axes  # noqa: E402
from matplotlib.lines import Line2D  # noqa: E402
from matplotlib.patches import Patch  # noqa: E402

from behaviours.records import ObjectRecord  # noqa: E402
from hero_driver.sim.truth_map import TruthMap  # noqa: E402
from mapping import OccupancyGrid, map_image  # noqa: E402
from reporting.plots import OUTCOME_COLOURS, Leg  # noqa: E402
from reporting.report import Truth  # noqa: E402

MARGIN_IN = 12.0
"""Floor shown around what the scans reached (the grid itself reaches far beyond the home)."""
PANEL_IN = 6.5
"""Width of one panel, inches; its height follows the floor's aspect."""


def shown_extent(grid: OccupancyGrid, truth: TruthMap | None = None) -> tuple[float, float, float, float]:
    """``(x_min, x_max, y_min, y_max)`` in inches: the cells the scans decided (free or
    occupied) and ``MARGIN_IN`` around them, and the whole true map when there is one;
    the whole grid when the scans decided nothing."""
    x0, x1, y0, y1 = grid.bounds
    known = np.argwhere(~grid.unknown)
    if known.size:
        cell = grid.inches_per_cell
        (top, left), (bottom, right) = known.min(axis=0), known.max(axis=0)
        x0, x1 = x0 + left * cell - MARGIN_IN, x0 + (right + 1) * cell + MARGIN_IN
        y0, y1 = y1 - (bottom + 1) * cell - MARGIN_IN, y1 - top * cell + MARGIN_IN  # row 0 is the high-y edge
    if truth is not None:
        tx0, ty0, tx1, ty1 = truth.extent
        if known.size:
            x0, x1, y0, y1 = min(x0, tx0), max(x1, tx1), min(y0, ty0), max(y1, ty1)
        else:
            x0, x1, y0, y1 = tx0, tx1, ty0, ty1
    return x0, x1, y0, y1


def plot_built_map(path: Path, grid: OccupancyGrid, truth: TruthMap | None = None, *,
                   route: Sequence[tuple[float, float]] = (), moves: Sequence[Leg] = (),
                   records: Sequence[ObjectRecord] = (), labels: Sequence[str] = (), present: Sequence[Truth] = (),
                   title: str | None = None) -> None:
    """Draw ``grid`` (and ``truth`` beside it, when given) to a PNG at ``path``.

    ``route``: where the robot stood at each scan, in order (the first is its start);
    ``moves``: the moves the episode log has, each as planned (``reporting.plots.legs``);
    ``records`` with their ``labels``: the objects found, each where it ended; ``present``:
    the objects as the simulator placed them, marked on the true map."""
    x0, x1, y0, y1 = shown_extent(grid, truth)
    panels = 1 if truth is None else 2
    height = min(max(PANEL_IN * (y1 - y0) / (x1 - x0), 3.0), 9.0) + 1.4
    fig, axes = plt.subplots(1, panels, figsize=(PANEL_IN * panels + 3.2, height), sharex=True, sharey=True,
                             squeeze=False)
    built_ax = axes[0][0]
    image = map_image(grid)
    rows, cols = image.pixels.shape
    built_ax.imshow(image.pixels, cmap="gray", vmin=0, vmax=255, interpolation="nearest", origin="upper",
                    extent=(image.origin_x_in, image.origin_x_in + cols * image.inches_per_pixel,
                            image.origin_y_in - rows * image.inches_per_pixel, image.origin_y_in))
    _draw_route(built_ax, route)
    for leg in moves:
        line = [*leg.waypoints, leg.stop[:2]]  # a path starts where the robot stood when it was planned
        built_ax.plot([q[0] for q in line], [q[1] for q in line], "-", color="tab:red" if leg.collided else "tab:brown",
                      linewidth=1.1, alpha=0.8, zorder=3)
    for record, label in zip(records, labels):
        _draw_found(built_ax, record, label)
    built_ax.set_title(title or f"The map built from the robot's {len(route) or 'own'} scans", fontsize=10,
                       loc="left")
    if truth is not None:
        truth_ax = axes[0][1]
        tx0, ty0, tx1, ty1 = truth.extent
        truth_ax.imshow(np.where(truth.occupied, 0, 254).astype(np.uint8), cmap="gray", vmin=0, vmax=255,
                        interpolation="nearest", origin="lower", extent=(tx0, tx1, ty0, ty1))
        for each in present:
            truth_ax.plot(each.x_in, each.y_in, marker="x", color="tab:purple", markersize=7, mew=1.6, zorder=5)
            truth_ax.annotate(each.name, (each.x_in, each.y_in), xytext=(5, 5), textcoords="offset points",
                              fontsize=6.5, color="tab:purple", zorder=6,
                              bbox={"facecolor": "white", "alpha": 0.6, "edgecolor": "none"})
        truth_ax.set_title("The true map (the simulator's)", fontsize=10, loc="left")
    for ax in axes[0]:
        ax.set_xlim(x0, x1)
        ax.set_ylim(y0, y1)
        ax.set_aspect("equal")
        ax.set_xlabel("x (in)")
    built_ax.set_ylabel("y (in)")
    axes[0][-1].legend(handles=_legend(bool(route), bool(moves), bool(records), bool(present) and truth is not None),
                       loc="upper left", bbox_to_anchor=(1.02, 1.0), fontsize=7.5, framealpha=0.9)
    fig.tight_layout()
    fig.savefig(path, dpi=110)
    plt.close(fig)


def _draw_route(ax: Axes, route: Sequence[tuple[float, float]]) -> None:
    if not route:
        return
    xs, ys = [p[0] for p in route], [p[1] for p in route]
    ax.plot(xs, ys, ":", color="tab:orange", linewidth=1.2, alpha=0.9, zorder=3)
    ax.plot(xs, ys, ".", color="tab:orange", markersize=4, zorder=3)
    ax.plot(xs[0], ys[0], marker="*", color="tab:orange", markersize=14, markeredgecolor="black", zorder=6)


def _draw_found(ax: Axes, record: ObjectRecord, label: str) -> None:
    colour = OUTCOME_COLOURS.get(record.outcome, "tab:gray")
    xs, ys = zip(*record.region.polygon)
    ax.fill(xs, ys, facecolor="none", edgecolor=colour, linewidth=2, zorder=4)
    ax.annotate(f"{record.index}: {label}\n{record.grasp or '-'} ({record.outcome or 'unfinished'})",
                record.region.centroid, xytext=(6, 6), textcoords="offset points", fontsize=6.5, color=colour,
                zorder=7, bbox={"facecolor": "white", "alpha": 0.6, "edgecolor": "none"})


def _legend(route: bool, moves: bool, found: bool, present: bool) -> list[Line2D | Patch]:
    handles: list[Line2D | Patch] = [
        Patch(facecolor="white", edgecolor="black", linewidth=0.5, label="free"),
        Patch(facecolor="#cdcdcd", label="not seen (built map)"),
        Patch(facecolor="black", label="occupied: walls, furniture,\nobjects at the scan plane"),
    ]
    if route:
        handles += [Line2D([], [], color="tab:orange", marker=".", linestyle=":", linewidth=1.2,
                           label="the route: where each scan was taken\n(the scan matcher's corrected pose),\n"
                                 "dotted from one to the next"),
                    Line2D([], [], color="tab:orange", marker="*", markersize=10, linestyle="none",
                           markeredgecolor="black", label="robot start")]
    if moves:
        handles.append(Line2D([], [], color="tab:brown", linewidth=1.1,
                              label="each move to an object as planned\n(red: stopped on contact)"))
    if found:
        handles += [Line2D([], [], color=OUTCOME_COLOURS["grasped"], linewidth=2, label="found: grasped"),
                    Line2D([], [], color=OUTCOME_COLOURS["left"], linewidth=2, label="found: left (No-Grab)"),
                    Line2D([], [], color=OUTCOME_COLOURS["failed"], linewidth=2, label="found: failed")]
    if present:
        handles.append(Line2D([], [], color="tab:purple", marker="x", linestyle="none", mew=1.6,
                              label="where the simulator placed\neach object (true map)"))
    return handles
