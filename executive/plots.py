"""Pictures of a run: the map with regions and paths, each object's run-time tree, and
the behaviour tree. PNG files, drawn with matplotlib (no display needed)."""

from __future__ import annotations

from collections.abc import Sequence
from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import py_trees  # noqa: E402

from behaviours.context import ObjectRecord  # noqa: E402
from hero_driver.interface import CameraImage  # noqa: E402

_COLOURS = {"grasped": "tab:green", "left": "tab:blue", "failed": "tab:red", None: "tab:gray"}


def plot_map(path: Path, image: CameraImage, records: Sequence[ObjectRecord], events: Sequence[dict],
             labels: Sequence[str]) -> None:
    """The overhead image, each object's region (coloured by outcome) and the robot's path."""
    h, w = image.pixels.shape
    extent = (image.origin_x_in, image.origin_x_in + w * image.inches_per_pixel,
              image.origin_y_in - h * image.inches_per_pixel, image.origin_y_in)
    fig, ax = plt.subplots(figsize=(10, 7.5))
    ax.imshow(image.pixels, cmap="gray", extent=extent, origin="upper")
    for record, label in zip(records, labels):
        xs, ys = zip(*record.region.polygon)
        colour = _COLOURS.get(record.outcome, "tab:gray")
        ax.fill(xs, ys, facecolor="none", edgecolor=colour, linewidth=2)
        ax.annotate(f"{record.index}: {label}\n{record.grasp or '-'} ({record.outcome})",
                    record.region.centroid, xytext=(8, 8), textcoords="offset points", fontsize=7, color=colour,
                    bbox={"facecolor": "white", "alpha": 0.7, "edgecolor": "none"})
    poses = [e["pose"] for e in events if e.get("event") == "move" and "pose" in e]
    if poses:
        xs, ys = [p[0] for p in poses], [p[1] for p in poses]
        ax.plot(xs, ys, "-o", color="tab:orange", markersize=3, linewidth=1, label="robot path (move ends)")
        ax.legend(loc="lower right", fontsize=8)
    ax.set_xlabel("x (in)")
    ax.set_ylabel("y (in)")
    ax.set_title("The lab: regions found, outcomes, and where the robot went")
    fig.tight_layout()
    fig.savefig(path, dpi=110)
    plt.close(fig)


def plot_object_tree(path: Path, record: ObjectRecord, label: str, events: Sequence[dict]) -> None:
    """One object's run-time tree as it was grown: each test with its value and branch,
    recoveries in red, the grasp at the end."""
    lines: list[tuple[str, str]] = []
    for e in events:
        if e.get("object") != record.index:
            continue
        kind = e.get("event")
        if kind == "choose":
            lines.append((f"{e['how']}: {e['test']} at {tuple(e['at'])}  "
                          f"(move {e['move_s']}s, sense {e['sense_s']}s, gain {e['gain']})",
                          "black" if e["how"] == "best" else "tab:red"))
        elif kind == "branch":
            lines.append((f"    = {e['value']:g}  ->  branch [{e['range'][0]:g}, {e['range'][1]:g}]", "tab:blue"))
        elif kind == "unreliable":
            lines.append((f"    = {e['value']}  unreliable (between/outside the branches)", "tab:red"))
        elif kind in ("backtrack", "nearest", "start_over", "drop_grasp", "grasp_feature_failed", "discriminate"):
            detail = {k: v for k, v in e.items() if k not in ("tick", "event", "object", "behaviour")}
            lines.append((f"{kind.replace('_', ' ')} {detail}", "tab:red"))
        elif kind == "choose_grasp":
            lines.append((f"{e['how']}: {e['grasp']} at {tuple(e['at'])}", "black"))
        elif kind == "grasp":
            lines.append((f"    {e['grasp']}: {'holds' if e['success'] else 'failed'}",
                          "tab:green" if e["success"] else "tab:red"))
        elif kind == "leave":
            lines.append((f"    {e['grasp']}: left on the floor", "tab:blue"))
        elif kind == "learn":
            lines.append((f"learned {e['id']} ({e['features']} features)", "tab:green"))
    height = max(2.0, 0.28 * len(lines) + 1.0)
    fig, ax = plt.subplots(figsize=(11, height))
    ax.axis("off")
    ax.set_title(f"object {record.index}: {label} -> {record.grasp or '-'} ({record.outcome})", loc="left")
    for i, (text, colour) in enumerate(lines):
        ax.text(0.0, 1.0 - (i + 0.5) / max(len(lines), 1), text, family="monospace", fontsize=8, color=colour,
                transform=ax.transAxes, va="center")
    fig.savefig(path, dpi=100, bbox_inches="tight")
    plt.close(fig)


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
        ax.text(x, y, f"{style[1]}{node.name}", ha="center", va="center", fontsize=7, rotation=0 if node.children else 30,
                bbox={"boxstyle": "round" if not node.children else "square", "facecolor": face, "alpha": 0.8})
    ax.set_title("csl-executive behaviour tree (→ sequence, ? selector, khaki: loop decorators)")
    fig.savefig(path, dpi=100, bbox_inches="tight")
    plt.close(fig)
