"""Trees as people read them: the paper's indented text, and JSON for tools.

Text follows the paper's figures: a test is ``move-to-(d,θ) (Ns)`` then
``Feature(d,θ) (Ns)``; each branch is its range ``[lo, hi]``; a leaf is
``Grasp(d,θ) (Ns)``, preceded by its move when it has one. The move names the concrete
position the robot goes to; the feature and the grasp name the position as the library
records it, ``*`` for a don't-care slot (``Height(6,*)``).
"""

from __future__ import annotations

import math
from typing import Any

from learner.choosing.leaf import AmbiguousLeaf, GraspLeaf
from learner.decision_tree import TestNode, TreeNode


def tree_text(node: TreeNode, indent: str = "  ") -> str:
    """The whole tree as indented lines."""
    lines: list[str] = []
    _text(node, 0, indent, lines)
    return "\n".join(lines)


def _text(node: TreeNode, depth: int, indent: str, lines: list[str]) -> None:
    pad = indent * depth
    if isinstance(node, TestNode):
        t = node.test
        lines.append(f"{pad}move-to-{str(t.target)} ({_secs(t.move_cost)})")
        lines.append(f"{pad}{t.test.feature}{str(t.test.position)} ({_secs(t.sense_cost)})")
        for (lo, hi), child in node.branches:
            lines.append(f"{pad}{indent}[{_num(lo)}, {_num(hi)}]")
            _text(child, depth + 2, indent, lines)
    elif isinstance(node, GraspLeaf):
        where = str(node.library_position or node.position)
        if node.grasped:
            lines.append(f"{pad}{node.grasp}{where} (grasped)")
            return
        if node.move_cost > 0:
            lines.append(f"{pad}move-to-{str(node.position)} ({_secs(node.move_cost)})")
        lines.append(f"{pad}{node.grasp}{where} ({_secs(node.grasp_cost)})")
    else:
        lines.append(f"{pad}ambiguous: try " + ", then ".join(
            f"{o.grasp}{str(o.library_position or o.position)} ({_secs(o.move_cost + o.grasp_cost)})"
            for o in node.options))


def tree_json(node: TreeNode) -> dict[str, Any]:
    """The tree as plain JSON-ready data.

    ``position`` is as the library records it (``"*"`` for a don't-care slot);
    ``target`` is the concrete position the robot goes to. A test whose value is
    already known costs nothing: its ``score`` is ``null`` (infinite) and ``free`` true.
    """
    if isinstance(node, TestNode):
        t = node.test
        return {
            "kind": "test",
            "feature": t.test.feature,
            "procedure": t.test.procedure,
            "position": t.test.position.to_json(),
            "target": t.target.to_json(),
            "move_cost": _round(t.move_cost),
            "sense_cost": _round(t.sense_cost),
            "score": None if math.isinf(t.score) else t.score,
            "gain": t.gain,
            "free": t.cost == 0,
            "is_grasp": t.test.is_grasp,
            "alternatives": [str(a.test) for a in node.alternatives],
            "branches": [{"range": [_num_json(lo), _num_json(hi)], "node": tree_json(child)}
                         for (lo, hi), child in node.branches],
        }
    if isinstance(node, GraspLeaf):
        return {
            "kind": "grasp",
            "grasp": node.grasp,
            "position": (node.library_position or node.position).to_json(),
            "target": node.position.to_json(),
            "move_cost": _round(node.move_cost),
            "grasp_cost": _round(node.grasp_cost),
            "grasped": node.grasped,
            "objects": list(node.object_ids),
        }
    assert isinstance(node, AmbiguousLeaf)
    return {
        "kind": "ambiguous",
        "grasps": [o.grasp for o in node.options],
        "options": [tree_json(o) for o in node.options],
        "objects": list(node.object_ids),
    }


def _secs(s: float) -> str:
    return "inf" if math.isinf(s) else f"{s:.0f}s"


def _num(v: float) -> str:
    return str(int(v)) if float(v).is_integer() else f"{v:g}"


def _num_json(v: float) -> float | int:
    return int(v) if float(v).is_integer() else v


def _round(v: float) -> float | None:
    return None if math.isinf(v) else round(v, 6)  # JSON has no infinity: null
