"""Pictures of a run: the map with regions and paths, each object's run-time tree, and
the behaviour tree. PNG files, drawn with matplotlib (no display needed)."""

from __future__ import annotations

from collections.abc import Sequence
from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
from matplotlib.lines import Line2D  # noqa: E402
from matplotlib.patches import Patch  # noqa: E402
import py_trees  # noqa: E402

from behaviours.events import RECOVERIES  # noqa: E402
from behaviours.records import ObjectRecord  # noqa: E402
from hero_driver.interface import CameraImage  # noqa: E402

_COLOURS = {"grasped": "tab:green", "left": "tab:blue", "failed": "tab:red", None: "tab:gray"}


def plot_map(path: Path, image: CameraImage, records: Sequence[ObjectRecord], events: Sequence[dict],
             labels: Sequence[str], start: tuple[float, float] | None = None) -> None:
    """The overhead image at the start, each object's region where it was first seen
    (coloured by outcome), and where the robot went."""
    h, w = image.pixels.shape
    extent = (image.origin_x_in, image.origin_x_in + w * image.inches_per_pixel,
              image.origin_y_in - h * image.inches_per_pixel, image.origin_y_in)
    fig, ax = plt.subplots(figsize=(10, 7.5))
    ax.imshow(image.pixels, cmap="gray", extent=extent, origin="upper", vmin=0, vmax=255)
    for record, label in zip(records, labels):
        region = record.first_region or record.region
        xs, ys = zip(*region.polygon)
        colour = _COLOURS.get(record.outcome, "tab:gray")
        ax.fill(xs, ys, facecolor="none", edgecolor=colour, linewidth=2)
        ax.annotate(f"{record.index}: {label}\n{record.grasp or '-'} ({record.outcome})",
                    region.centroid, xytext=(8, 8), textcoords="offset points", fontsize=7, color=colour,
                    bbox={"facecolor": "white", "alpha": 0.75, "edgecolor": "none"})
    ends = [tuple(e["pose"][:2]) for e in events if e.get("event") == "move" and "pose" in e]
    route = ([start] if start else []) + ends
    if route:
        ax.plot([p[0] for p in route], [p[1] for p in route], "-", color="tab:orange", linewidth=1, alpha=0.8)
        ax.plot([p[0] for p in ends], [p[1] for p in ends], "o", color="tab:orange", markersize=3)
    if start:
        ax.plot(*start, marker="*", color="tab:orange", markersize=14, markeredgecolor="black")
    handles = [
        Line2D([], [], color="tab:green", linewidth=2, label="grasped"),
        Line2D([], [], color="tab:blue", linewidth=2, label="left (No-Grab)"),
        Line2D([], [], color="tab:red", linewidth=2, label="failed"),
        Line2D([], [], color="tab:orange", marker="o", markersize=3, label="robot: where each move ended"),
        Line2D([], [], color="tab:orange", marker="*", markersize=10, linestyle="none", markeredgecolor="black",
               label="robot start"),
        Patch(facecolor="#6e6e6e", label="walls, furniture (light grey: the robot's base)"),
    ]
    ax.legend(handles=handles, loc="lower right", fontsize=7, framealpha=0.9)
    ax.set_xlabel("x (in)")
    ax.set_ylabel("y (in)")
    ax.set_title("The lab from the overhead camera: objects where first seen, outcomes, the robot's route")
    fig.tight_layout()
    fig.savefig(path, dpi=110)
    plt.close(fig)


def plot_object_tree(path: Path, record: ObjectRecord, label: str, events: Sequence[dict]) -> None:
    """One object's run-time tree as it grew: each test a box (where, what it cost), each
    edge the value measured and the branch followed; unreliable values and recoveries in
    red; the grasp at the end."""
    steps = _tree_steps(record.index, events)
    fig_h = max(3.0, 0.62 * len(steps) + 1.2)
    fig, ax = plt.subplots(figsize=(8.5, fig_h))
    ax.axis("off")
    ax.set_xlim(0, 1)
    ax.set_ylim(-len(steps), 0.8)
    ax.set_title(f"object {record.index}: {label}  ->  {record.grasp or '-'} ({record.outcome})", fontsize=10)
    for i, (text, kind, edge) in enumerate(steps):
        y = -i
        face = {"test": "#dbe9f6", "grasp": "#d8f0d2", "fail": "#f7d4d4", "note": "#f4f4f4"}[kind]
        ax.text(0.5, y, text, ha="center", va="center", fontsize=8, family="monospace",
                bbox={"boxstyle": "round,pad=0.35", "facecolor": face, "edgecolor": "#555555"})
        if i + 1 < len(steps):
            ax.annotate("", xy=(0.5, y - 0.72), xytext=(0.5, y - 0.28),
                        arrowprops={"arrowstyle": "->", "color": "#c0392b" if edge.startswith("!") else "#333333"})
            if edge:
                ax.text(0.53, y - 0.5, edge.lstrip("!"), fontsize=7, va="center",
                        color="#c0392b" if edge.startswith("!") else "#333333")
    fig.savefig(path, dpi=100, bbox_inches="tight")
    plt.close(fig)


def _tree_steps(index: int, events: Sequence[dict]) -> list[tuple[str, str, str]]:
    """(box text, kind, label of the edge below it) for each step of one object."""
    steps: list[tuple[str, str, str]] = []

    def edge(label: str) -> None:
        if steps:
            text, kind, _ = steps[-1]
            steps[-1] = (text, kind, label)

    for e in events:
        if e.get("object") != index:
            continue
        kind = e.get("event")
        if kind == "choose":
            free = " (known: free)" if e["move_s"] == 0 and e["sense_s"] == 0 else \
                f"  move {_s(e['move_s'])}, sense {_s(e['sense_s'])}"
            tag = "" if e["how"] == "best" else f"{e['how']}: "
            steps.append((f"{tag}{e['test']} at {_at(e['at'])}{free}", "test", ""))
        elif kind == "branch":
            edge(f"= {e['value']:g}  ->  [{e['range'][0]:g}, {e['range'][1]:g}]")
        elif kind == "unreliable":
            value = "no value" if e["value"] is None else f"= {e['value']:g}"
            edge(f"!{value}: between the branches, unreliable")
        elif kind == "grasp" and e.get("as_feature"):
            edge(f"{'!' if not e['success'] else ''}grasp as a feature: {'holds' if e['success'] else 'failed'}")
        elif kind == "choose_grasp":
            steps.append((f"{'ambiguous: try ' if e['how'] == 'ambiguous' else ''}{e['grasp']} at {_at(e['at'])}",
                          "grasp", ""))
        elif kind == "grasp":
            edge(f"{'' if e['success'] else '!'}{e['grasp']}: {'holds' if e['success'] else 'failed'}")
        elif kind == "leave":
            edge("left on the floor")
        elif kind in RECOVERIES:
            steps.append((_recovery(e), "fail", ""))
        elif kind == "learn" and e.get("id"):
            steps.append((f"learned {e['id']} ({e['features']} features)", "note", ""))
    return steps


def _recovery(e: dict) -> str:
    kind = e["event"]
    if kind == "backtrack":
        return f"backtrack to depth {e['depth']}"
    if kind == "nearest":
        return f"nearest neighbour: {e['value']:g} -> [{e['branch'][0]:g}, {e['branch'][1]:g}]"
    if kind == "start_over":
        return "start over: " + ("knocked over, all sensing void" if e["changed"] else "pushed, from where it lies")
    if kind == "drop_grasp":
        return f"drop {e['grasp']}, rebuild ({len(e['candidates'])} descriptions left)"
    if kind == "discriminate":
        return "discriminate: already told apart" if e.get("already") else \
            f"discriminate: {e['procedure']} ({'told apart' if e.get('told_apart') else 'not yet'})"
    if kind == "other_end":
        return f"grasp from the other end {_at(e['to'])}"
    return f"no path to {_at(e['to'])}"


def _at(position: Sequence[object]) -> str:
    return "(" + ",".join(str(p) for p in position) + ")"


def _s(seconds: float | None) -> str:
    return "no path" if seconds is None else f"{seconds:.0f}s"


def plot_behaviour_tree(path: Path, root: py_trees.behaviour.Behaviour) -> None:
    """The behaviour tree drawn top-down: composites as boxes, leaves as rounded boxes."""
    positions: dict[int, tuple[float, float]] = {}
    order = [0]

    def place(node: py_trees.behaviour.Behaviour, depth: int) -> float:
        if not node.children:
            x = float(order[0])
            order[0] += 1
        else:
            xs = [place(c, depth + 1) for c in node.children]
            x = sum(xs) / len(xs)
        positions[id(node)] = (x, -depth)
        return x

    place(root, 0)
    width = max(8.0, order[0] * 1.15)
    fig, ax = plt.subplots(figsize=(width, 7))
    ax.axis("off")
    for node in root.iterate():
        x, y = positions[id(node)]
        for child in node.children:
            cx, cy = positions[id(child)]
            ax.plot([x, cx], [y - 0.15, cy + 0.15], color="gray", linewidth=0.8)
        kind = type(node).__name__
        style = {"Sequence": ("tab:orange", "→ "), "Selector": ("tab:cyan", "? ")}.get(kind, ("white", ""))
        decorator = isinstance(node, py_trees.decorators.Decorator)
        face = "khaki" if decorator else style[0]
        ax.text(x, y, f"{style[1]}{node.name}", ha="center", va="center", fontsize=7,
                bbox={"boxstyle": "round" if not node.children else "square", "facecolor": face, "alpha": 0.8})
    ax.set_title("csl-executive behaviour tree (→ sequence, ? selector, khaki: loop decorators)")
    fig.savefig(path, dpi=100, bbox_inches="tight")
    plt.close(fig)
