"""Pictures of a run: the map with regions and paths, each object's run-time tree, and
the behaviour tree. PNG files, drawn with matplotlib (no display needed)."""

from __future__ import annotations

import math
import textwrap
from collections.abc import Sequence
from dataclasses import dataclass
from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
from matplotlib.axes import Axes  # noqa: E402
from matplotlib.lines import Line2D  # noqa: E402
from matplotlib.patches import Circle, Patch, Rectangle  # noqa: E402
import py_trees  # noqa: E402

from behaviours.records import ObjectRecord  # noqa: E402
from camera_model.image import CameraImage  # noqa: E402
from reporting.history import CurvePoint  # noqa: E402
from reporting.tree_figure import (BOX_PT, LABEL_H, LABEL_PT, LINE_H, PAD, Box, Link, TreeLayout,  # noqa: E402
                                   layout, object_figures)
from planner.image import undistorted  # noqa: E402

OUTCOME_COLOURS = {"grasped": "tab:green", "left": "tab:blue", "failed": "tab:red", None: "tab:gray"}
"""The colour of each object outcome on every map (None: not finished)."""


@dataclass(frozen=True)
class Leg:
    """One move as the map draws it: from where the previous move stopped (or the start)
    along the waypoints the planner gave, to where the base really stopped."""

    number: int  # move order, from 1
    origin: tuple[float, float] | None  # None when the episode's start is unknown
    waypoints: tuple[tuple[float, float], ...]
    stop: tuple[float, float, float]  # x_in, y_in, heading_deg
    collided: bool


def legs(events: Sequence[dict], start: tuple[float, float] | None) -> list[Leg]:
    """The moves of an episode log in order, each joined to the stop before it: the
    planner starts every path from the pose the last move reported."""
    out: list[Leg] = []
    origin = start
    for e in events:
        if e.get("event") != "move":
            continue
        stop = (float(e["pose"][0]), float(e["pose"][1]), float(e["pose"][2]))
        waypoints = tuple((float(p[0]), float(p[1])) for p in e["path"])
        out.append(Leg(len(out) + 1, origin, waypoints, stop, bool(e.get("collided"))))
        origin = stop[:2]
    return out


@dataclass(frozen=True)
class Ending:
    """Where one object was first seen and where the episode last saw it: the region the
    tree followed it to when a failed grasp pushed it or knocked it over (the side-effect
    check's new image), else where it was first seen."""

    index: int
    first: tuple[tuple[float, float], ...]  # polygon, world inches
    last: tuple[tuple[float, float], ...]
    shift_in: float  # between the two centroids
    change: str | None  # pushed | knocked over | lost from sight | None


def endings(records: Sequence[ObjectRecord], events: Sequence[dict]) -> list[Ending]:
    """Each object's first and last region, and what moved it: its worst side effect
    in the log (knocked over beats pushed; a region the camera lost is said so, as its
    last region is then where it was before)."""
    out = []
    for record in records:
        seen = {(e.get("effect"), e.get("reason")) for e in events
                if e.get("event") == "side_effect" and e.get("object") == record.index}
        change = next((word for (effect, reason), word in _CHANGES if (effect, reason) in seen), None)
        first, last = record.first_region, record.region
        out.append(Ending(record.index, tuple(first.polygon), tuple(last.polygon),
                          math.dist(first.centroid, last.centroid), change))
    return out


_CHANGES = ((("changed", None), "knocked over"), (("changed", "region lost"), "lost from sight"),
            (("pushed", None), "pushed"))
"""A side-effect event's (effect, reason) and how the map says it, worst first."""
_MOVED_IN = 0.5  # a shift the map draws as an arrow (vision's centroids jitter less)


def map_image(image: CameraImage) -> CameraImage:
    """The image the map is drawn on: a fish-eye image undistorted first (the planner's
    ``cv2.fisheye`` model with Knew = K, which keeps the pixel-to-world mapping), so
    that paths and regions drawn in world inches land on what they mark; the raw image
    is inches off towards its corners."""
    return undistorted(image)


def plot_map(path: Path, image: CameraImage, records: Sequence[ObjectRecord], events: Sequence[dict],
             labels: Sequence[str], start: tuple[float, float] | None = None, *, base_radius_in: float) -> None:
    """The overhead image at the start (undistorted), each object where it ended
    (coloured by outcome; dashed where it was first seen and an arrow when a failed
    grasp pushed it or knocked it over), and where the robot went: every move's
    planned path (a straight line between stops would cut through boxes the planner
    went round), its order number, and the base's footprint and heading where it
    stopped. Inches on both axes, equal aspect, so a footprint is a true circle."""
    image = map_image(image)
    h, w = image.pixels.shape
    extent = (image.origin_x_in, image.origin_x_in + w * image.inches_per_pixel,
              image.origin_y_in - h * image.inches_per_pixel, image.origin_y_in)
    fig, ax = plt.subplots(figsize=(13, 7.5))
    ax.imshow(image.pixels, cmap="gray", extent=extent, origin="upper", vmin=0, vmax=255)
    for record, label, ending in zip(records, labels, endings(records, events)):
        _draw_object(ax, record, label, ending)
    for leg in legs(events, start):
        _draw_leg(ax, leg, base_radius_in)
    if start:
        ax.plot(*start, marker="*", color="tab:orange", markersize=14, markeredgecolor="black", zorder=6)
    handles = [
        Line2D([], [], color="tab:green", linewidth=2, label="grasped (where it was picked up)"),
        Line2D([], [], color="tab:blue", linewidth=2, label="left (No-Grab)"),
        Line2D([], [], color="tab:red", linewidth=2, label="failed"),
        Line2D([], [], color="black", linestyle="--", linewidth=1,
               label="where first seen, when a failed grasp\npushed it or knocked it over (arrow)"),
        Line2D([], [], color="tab:orange", linewidth=1.2,
               label="each move's path as planned\n(number: move order; red: stopped on contact)"),
        Line2D([], [], color="tab:orange", linestyle=":", linewidth=1, label="last waypoint to where the base stopped"),
        Patch(facecolor="none", edgecolor="tab:orange", label="the base's footprint and heading at each stop"),
        Line2D([], [], color="tab:orange", marker="*", markersize=10, linestyle="none", markeredgecolor="black",
               label="robot start"),
        Patch(facecolor="#6e6e6e", label="walls, furniture (light grey: the robot's base)"),
    ]
    ax.legend(handles=handles, loc="upper left", bbox_to_anchor=(1.01, 1.0), fontsize=7.5, framealpha=0.9)
    ax.set_aspect("equal")
    ax.set_xlabel("x (in)")
    ax.set_ylabel("y (in)")
    ax.set_title("The lab from the overhead camera: objects where they ended, outcomes, the robot's moves as planned",
                 fontsize=10, loc="left")
    fig.tight_layout()
    fig.savefig(path, dpi=110)
    plt.close(fig)


def _draw_object(ax: Axes, record: ObjectRecord, label: str, ending: Ending) -> None:
    colour = OUTCOME_COLOURS.get(record.outcome, "tab:gray")
    moved = ending.shift_in > _MOVED_IN
    if moved or ending.change:
        xs, ys = zip(*ending.first)
        ax.fill(xs, ys, facecolor="none", edgecolor=colour, linewidth=1, linestyle="--", alpha=0.8)
    xs, ys = zip(*ending.last)
    ax.fill(xs, ys, facecolor="none", edgecolor=colour, linewidth=2)
    first, last = record.first_region.centroid, record.region.centroid
    if moved:
        ax.annotate("", last, xytext=first, arrowprops={"arrowstyle": "->", "color": colour, "linewidth": 1.2})
    how = {None: "", "pushed": f"\npushed {ending.shift_in:.1f} in"}.get(ending.change, f"\n{ending.change}")
    ax.annotate(f"{record.index}: {label}\n{record.grasp or '-'} ({record.outcome}){how}", last,
                xytext=(8, 8), textcoords="offset points", fontsize=7, color=colour, zorder=7,
                bbox={"facecolor": "white", "alpha": 0.6, "edgecolor": "none"})


def _draw_leg(ax: Axes, leg: Leg, base_radius_in: float) -> None:
    colour = "tab:red" if leg.collided else "tab:orange"
    line = ([leg.origin] if leg.origin else []) + list(leg.waypoints)
    if len(line) > 1:
        ax.plot([p[0] for p in line], [p[1] for p in line], "-", color=colour, linewidth=1.2, alpha=0.9, zorder=3)
    x, y, heading = leg.stop
    if line and math.dist(line[-1], (x, y)) > 0.05:  # odometry, centring or contact moved it off the path
        ax.plot([line[-1][0], x], [line[-1][1], y], ":", color=colour, linewidth=1, zorder=3)
    ax.add_patch(Circle((x, y), base_radius_in, facecolor="none", edgecolor=colour, linewidth=0.8, alpha=0.8,
                        zorder=4))
    h = math.radians(heading)
    ax.plot([x, x + base_radius_in * math.cos(h)], [y, y + base_radius_in * math.sin(h)], "-", color=colour,
            linewidth=1.2, zorder=4)
    ax.annotate(str(leg.number), (x, y), ha="center", va="center", fontsize=6, color="black", zorder=5,
                bbox={"boxstyle": "circle,pad=0.15", "facecolor": "white", "edgecolor": colour, "linewidth": 0.6})


def plot_object_tree(path: Path, record: ObjectRecord, label: str, events: Sequence[dict]) -> None:
    """One object's run-time decision tree as the paper's Fig. 5 draws it: the path the
    robot followed (tests with position and cost, measured values on the branches
    taken, recoveries in red, the grasp at the end) and, for the branches not taken,
    what the learner would have grown there: each to its first test and two levels
    below it, fewer when that would make the picture wider than about a screen."""
    session = record.session
    figure = object_figures(events, record.index, session.ctx, orientation_free=session.orientation_free)
    for levels in (2, 1, 0):
        tree = layout(figure(levels))
        if tree.width <= _MAX_TREE_WIDTH_IN:
            break
    title = f"object {record.index}: {label}  →  {record.grasp or '-'} ({record.outcome or 'unfinished'})"
    plot_tree_layout(path, tree, title)


_MAX_TREE_WIDTH_IN = 20.0  # about a screen at 100 dpi
_MIN_TREE_WIDTH_IN = 6.0  # room for the title
_TREE_MARGIN_IN = 0.3
_LEGEND = ("blue: the path followed, the measured value on the branch taken",
           "red: unreliable values, failed grasps, recoveries",
           "grey: branches not taken, as the learner would grow them (… deeper tests elided)")
_BOX_FACE = {("test", True): "#dbe9f6", ("test", False): "#f4f7fb", ("grasp", True): "#d8f0d2",
             ("grasp", False): "#f0f7ee", ("ambiguous", True): "#fbeccc", ("ambiguous", False): "#fdf6e6"}
_TONE = {"plain": "#1a1a1a", "failed": "#c0392b", "ok": "#1e7b34", "note": "#5f5f5f"}
_LINK = {"taken": ("#1f4e9c", 2.0, "-"), "recovery": ("#c0392b", 2.0, "--"), "untaken": ("#a0a0a0", 0.8, "-")}


def plot_tree_layout(path: Path, tree: TreeLayout, title: str) -> None:
    """Draw a laid-out run-time tree (``reporting.tree_figure.layout``) to a PNG, one data
    unit an inch, so the boxes sized from their text fit it at any tree size."""
    m = _TREE_MARGIN_IN
    width = max(tree.width, _MIN_TREE_WIDTH_IN)
    legend = ["  ·  ".join(_LEGEND)] if width >= 14.0 else list(_LEGEND)  # one line when it fits
    head = 0.45 + 0.18 * len(legend)
    fig = plt.figure(figsize=(width + 2 * m, tree.height + head + 2 * m))
    ax = fig.add_axes((0.0, 0.0, 1.0, 1.0))
    ax.axis("off")
    ax.set_xlim(-m, width + m)
    ax.set_ylim(tree.height + m, -head - m)
    ax.text(0.0, -head - m / 2, title, fontsize=11, va="top", ha="left", weight="bold")
    ax.text(0.0, -head - m / 2 + 0.3, "\n".join(legend), fontsize=7.5, va="top", ha="left", color="#444444",
            linespacing=1.3)
    for link in sorted(tree.links, key=lambda k: k.style != "untaken"):  # the path drawn over the rest
        _draw_link(ax, tree.boxes[link.parent], tree.boxes[link.child], link)
    for box in tree.boxes:
        _draw_box(ax, box)
    fig.savefig(path, dpi=100)
    plt.close(fig)


def _draw_link(ax: Axes, parent: Box, child: Box, link: Link) -> None:
    colour, width, dash = _LINK[link.style]
    bus = child.top - LABEL_H - 0.12
    ax.plot([parent.x, parent.x, child.x, child.x], [parent.top + parent.height, bus, bus, child.top],
            color=colour, linewidth=width, linestyle=dash, zorder=1 if link.style == "untaken" else 2)
    if link.label:
        ax.text(child.x, child.top - LABEL_H / 2 - 0.02, link.label, fontsize=LABEL_PT, family="DejaVu Sans Mono",
                ha="center", va="center", color=colour if link.style != "untaken" else "#555555", zorder=3,
                weight="bold" if link.style != "untaken" else "normal",
                bbox={"boxstyle": "square,pad=0.08", "facecolor": "white", "edgecolor": "none"})


def _draw_box(ax: Axes, box: Box) -> None:
    left = box.x - box.width / 2
    if box.kind == "elided":
        ax.text(box.x, box.top + box.height / 2, "…", fontsize=BOX_PT * 1.6, ha="center", va="center",
                color=_TONE["note"], zorder=5)
        return
    ax.add_patch(Rectangle((left, box.top), box.width, box.height, facecolor=_BOX_FACE[(box.kind, box.taken)],
                           edgecolor="#1f4e9c" if box.taken else "#9a9a9a", linewidth=1.4 if box.taken else 0.7,
                           zorder=4))
    for i, line in enumerate(box.lines):
        ax.text(left + PAD, box.top + PAD + (i + 0.5) * LINE_H * BOX_PT, line.text, fontsize=BOX_PT,
                family="DejaVu Sans Mono", ha="left", va="center", color=_TONE[line.tone], zorder=5)


BT_COLUMN_IN = 1.15
"""Inches per level of the behaviour tree, left to right: a wrapped label fits in one."""
BT_ROW_IN = 0.34
"""Inches per leaf, top to bottom: two lines of a wrapped label fit in one."""
BT_LABEL_CHARS = 15
"""Where a label wraps (at a space; a single word longer stays whole)."""


def bt_label(name: str) -> str:
    """A node's name wrapped at spaces to :data:`BT_LABEL_CHARS`, so a level's column stays
    narrow: the figure's width is bounded by the tree's depth, never by its breadth."""
    return textwrap.fill(name, BT_LABEL_CHARS, break_long_words=False, break_on_hyphens=False)


def plot_behaviour_tree(path: Path, root: py_trees.behaviour.Behaviour) -> None:
    """The behaviour tree drawn left to right, one leaf per row: composites as boxes,
    leaves as rounded boxes. Drawn top-down the tree's fifty-odd leaves side by side made
    a picture some 4,000 px wide whose 7-point labels were unreadable on a screen; left
    to right, its width is its depth (a few columns) and its height grows with the leaves."""
    positions: dict[int, tuple[float, float]] = {}
    order = [0]
    deepest = [0]

    def place(node: py_trees.behaviour.Behaviour, depth: int) -> float:
        deepest[0] = max(deepest[0], depth)
        if not node.children:
            y = -float(order[0])
            order[0] += 1
        else:
            ys = [place(c, depth + 1) for c in node.children]
            y = (ys[0] + ys[-1]) / 2
        positions[id(node)] = (float(depth), y)
        return y

    place(root, 0)
    columns, rows = deepest[0] + 1, max(order[0], 1)
    fig, ax = plt.subplots(figsize=(columns * BT_COLUMN_IN, rows * BT_ROW_IN + 0.6))
    fig.subplots_adjust(left=0, right=1, bottom=0, top=1 - 0.6 / (rows * BT_ROW_IN + 0.6))
    ax.set_xlim(-0.5, columns - 0.5)
    ax.set_ylim(-rows + 0.5, 0.5)
    ax.axis("off")
    for node in root.iterate():
        x, y = positions[id(node)]
        for child in node.children:
            cx, cy = positions[id(child)]
            ax.plot([x + 0.2, x + 0.5, x + 0.5, cx - 0.2], [y, y, cy, cy], color="gray", linewidth=0.8)
        kind = type(node).__name__
        style = {"Sequence": ("tab:orange", "→ "), "Selector": ("tab:cyan", "? ")}.get(kind, ("white", ""))
        decorator = isinstance(node, py_trees.decorators.Decorator)
        face = "khaki" if decorator else style[0]
        ax.text(x, y, bt_label(f"{style[1]}{node.name}"), ha="center", va="center", fontsize=7.5, linespacing=1.0,
                bbox={"boxstyle": "round,pad=0.25" if not node.children else "square,pad=0.25", "facecolor": face,
                      "alpha": 0.85})
    fig.suptitle("csl-executive behaviour tree, root at the left (→ sequence, ? selector, khaki: loop decorators)",
                 fontsize=9, x=0.01, ha="left")
    fig.savefig(path, dpi=100)
    plt.close(fig)


def plot_learning_curve(path: Path, points: Sequence[CurvePoint], source: str) -> None:
    """The learning curve over runs (``csl library history``), as the paper reads it:
    robot minutes per object above, errors per object (grasps at a leaf that did not
    hold) and the share of objects not handled below, one point per run in the order they were made."""
    runs = [p.run for p in points]
    fig, (cost, wrong) = plt.subplots(2, 1, sharex=True, figsize=(max(6.0, min(16.0, 0.35 * len(runs) + 4.0)), 6))
    cost.plot(runs, [p.minutes_per_object for p in points], "o-", color="tab:blue")
    cost.set_ylabel("robot minutes per object")
    cost.set_ylim(bottom=0)
    cost.grid(alpha=0.3)
    wrong.plot(runs, [p.errors_per_object for p in points], "o-", color="tab:red",
               label="errors per object (grasps at a leaf that did not hold)")
    wrong.plot(runs, [p.failed_per_object for p in points], "s--", color="tab:gray",
               label="share of objects not handled")
    wrong.set_ylabel("per object")
    wrong.set_ylim(bottom=0)
    wrong.grid(alpha=0.3)
    wrong.legend(fontsize=8, loc="best")
    wrong.set_xlabel("run (in the order appended to the history)")
    wrong.xaxis.get_major_locator().set_params(integer=True)
    cost.set_title(f"Learning over {len(runs)} runs ({source})", fontsize=10)
    fig.tight_layout()
    fig.savefig(path, dpi=100)
    plt.close(fig)
