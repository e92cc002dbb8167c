"""One object's run-time decision tree as the paper draws it (its Fig. 5), as plain data.

The paper draws a run-time tree as test nodes, each with its position and cost, one edge
per branch labelled with the branch's value range, and grasps at the leaves. At run
time the learner grows only the path the object at hand needs, so the figure is rebuilt
afterwards from two sources:

- the episode log gives the *path*: each visit of the robot at a tree node is one box
  listing the tests tried there in order (a test whose value was unreliable, in red,
  with the value, then the reselected one), the edge it left by (the branch followed,
  with the measured value; or a recovery: backtrack, start over, rebuild after a failed
  grasp) and, at the end, the grasp and whether it held;
- the learner gives the rest: the descriptions at each node are replayed from the same
  library (``learner.choosing.node.split``), the chosen test's ranges recomputed
  (``rank``), and every branch *not* taken is regrown with ``learner.decision_tree.grow``
  from the test's position, as the learner would have grown it had the value fallen
  there, shown a few levels deep and then elided with "…".

Our reading where the log is silent: the regrown branches are priced with the object's
move-cost estimator as it stands after the episode (after a push it prices around where
the object was last seen), and whether a value holds from every side
(``orientation_free``) is the object's last known state. Both only change the costs
shown on untaken branches, never the path.

:func:`object_figure` turns the log into a tree of :class:`Shape`; :func:`layout` places
it (a contour-packed tidy tree, sizes in inches); ``reporting.plots`` draws it.
"""

from __future__ import annotations

import math
from collections import Counter
from collections.abc import Callable, Mapping, Sequence
from dataclasses import dataclass, field
from typing import Literal

from behaviours.events import RECOVERIES
from learner.choosing.leaf import AmbiguousLeaf, GraspLeaf, grasp_options
from learner.choosing.matrix import Test
from learner.choosing.node import Context, Node, ScoredTest, split
from learner.choosing.partition import Range
from learner.choosing.selection import rank
from learner.decision_tree import TestNode, TreeNode, grow
from learner.position import Position, position_from_json

Tone = Literal["plain", "failed", "ok", "note"]
Kind = Literal["test", "grasp", "ambiguous", "elided"]
Style = Literal["taken", "recovery", "untaken"]


@dataclass(frozen=True)
class Line:
    """One line of a box; its tone says how to colour it (failed: an unreliable value, a
    failed grasp or a recovery; ok: a grasp that held; note: what was learned, ids)."""

    text: str
    tone: Tone = "plain"


@dataclass(frozen=True)
class Shape:
    """One box of the figure with the branches below it. ``taken``: the robot was there."""

    lines: tuple[Line, ...]
    kind: Kind
    taken: bool
    branches: tuple[Branch, ...] = ()


@dataclass(frozen=True)
class Branch:
    """An edge: a value range (and the measured value when followed), or a recovery."""

    label: str
    child: Shape
    style: Style


# -- from the log and the learner to shapes ---------------------------------------------


def object_figure(events: Sequence[Mapping[str, object]], index: int, ctx: Context, *,
                  orientation_free: bool = False, levels: int = 1) -> Shape:
    """The run-time tree of object ``index``: the path from its log events, the branches
    not taken regrown by the learner over ``ctx`` (the library, criterion and move
    costs the object was recognized with), each shown to its first test and ``levels``
    levels below that."""
    return object_figures(events, index, ctx, orientation_free=orientation_free)(levels)


def object_figures(events: Sequence[Mapping[str, object]], index: int, ctx: Context, *,
                   orientation_free: bool = False) -> Callable[[int], Shape]:
    """:func:`object_figure` to any depth from one replay: the log is followed and the
    untaken branches regrown once, and each call draws them ``levels`` levels deep."""
    replay = _Replay(ctx, orientation_free)
    for e in events:
        if e.get("object") == index:
            replay.event(e)
    return replay.figure


@dataclass
class _Visit:
    """The robot at one tree node: the lines of its box and how it left the node."""

    lines: list[Line] = field(default_factory=list)
    kind: Kind = "test"
    # a branch not taken (its regrown subtree, drawn to the depth asked for) or None: the path goes on there
    branches: list[tuple[str, Shape | TreeNode | None]] = field(default_factory=list)
    onward: str = ""  # label of the edge to the next visit, when not a branch
    style: Style = "taken"


@dataclass
class _Attempt:
    """The test (or grasp) chosen at the current node, while it is carried out."""

    test: Test | None  # None for a grasp at a leaf (or a test this library does not hold)
    scored: ScoredTest | None
    at: Position
    grasp: str | None = None  # a grasp: at a leaf, or tried as a feature


class _Replay:
    """Follows one object's events, keeping the node the learner is at and the path."""

    def __init__(self, ctx: Context, orientation_free: bool) -> None:
        self.ctx, self.orientation_free = ctx, orientation_free
        self.tests = {str(t): t for t in ctx.matrix.tests}
        self.visits: list[_Visit] = []
        self.path: list[tuple[Node, Test]] = []  # nodes above the current one and the test followed there
        self.node = Node.root(len(ctx.matrix.descriptions))
        self.pending: tuple[str, Style] | None = ("", "taken")  # the edge into the next visit
        self.position = Position(None, None)
        self.measurements: dict[tuple[str, Position], float] = {}
        self.dropped: set[str] = set()
        self.pushes: Counter[str] = Counter()
        self.attempt: _Attempt | None = None
        self.effect = ""

    # -- the figure -----------------------------------------------------------------
    def figure(self, levels: int) -> Shape:
        """The figure, regrown branches ``levels`` levels below their first test (the
        same replay draws any depth: a trailing "…" is added once)."""
        if self.pending is not None and self.visits:
            self._visit().lines.append(Line("…", "note"))  # the log ends before anything was done here
        if not self.visits:
            return Shape((Line("no decision logged for this object", "note"),), "test", False)
        nxt: Shape | None = None
        for visit in reversed(self.visits):
            branches: list[Branch] = []
            for label, child in visit.branches:
                if child is not None:
                    branches.append(Branch(label, child if isinstance(child, Shape) else _shape_of(child, levels),
                                           "untaken"))
                elif nxt is not None:
                    branches.append(Branch(label, nxt, visit.style))
            if not visit.branches and nxt is not None:
                branches.append(Branch(visit.onward, nxt, visit.style))
            nxt = Shape(tuple(visit.lines), visit.kind, True, tuple(branches))
        assert nxt is not None
        return nxt

    def _visit(self) -> _Visit:
        """The current visit; arriving at a node opens a new one."""
        if self.pending is not None:
            label, style = self.pending
            if self.visits and not self.visits[-1].branches:
                self.visits[-1].onward, self.visits[-1].style = label, style
            self.visits.append(_Visit())
            self.pending = None
        return self.visits[-1]

    def _arrive(self, node: Node, label: str, style: Style) -> None:
        """The path moves to ``node`` along an edge labelled ``label``."""
        self.node, self.attempt = node, None
        if label == "backtrack" and self.pending is not None and self.pending[0].startswith("backtrack"):
            label = f"backtrack ×{int(self.pending[0].partition('×')[2] or 1) + 1}"  # up several levels at once
        self.pending = (label, style)

    # -- events ------------------------------------------------------------------------
    def event(self, e: Mapping[str, object]) -> None:
        kind = str(e.get("event"))
        handler = getattr(self, "_on_" + kind, None)
        if handler is not None:
            handler(e)
        elif kind in RECOVERIES:  # a recovery this figure has no drawing for yet: named on the path
            self._visit().lines.append(Line(f"  {kind.replace('_', ' ')}", "failed"))

    def _on_object(self, e: Mapping[str, object]) -> None:
        self.position = position_from_json(e["start"], "start")
        self._new_round("", "taken")

    def _on_choose(self, e: Mapping[str, object]) -> None:
        visit = self._visit()
        visit.kind = "test"
        name = str(e["test"])
        at = position_from_json(e["at"], "at")
        test = self.tests.get(name)
        self.attempt = _Attempt(test, self._scored(test, at), at,
                                test.feature if test is not None and test.is_grasp else None)
        move, sense = _seconds(e.get("move_s")), _seconds(e.get("sense_s"))
        if move is None or move > 0:
            visit.lines.append(Line(f"move-to-{at} {_secs(move)}"))
        how = "reselect: " if e.get("how") == "reselect" else ""
        cost = "known, 0s" if move == 0 and sense == 0 else _secs(sense)
        visit.lines.append(Line(f"{how}{name}{' as a test' if self.attempt.grasp else ''} {cost}"))
        self.position = at

    def _on_move(self, e: Mapping[str, object]) -> None:
        if e.get("collided"):
            self._visit().lines.append(Line("  ✗ collided on the way", "failed"))
        elif e.get("to") is not None:
            self.position = position_from_json(e["to"], "to")

    def _on_sense(self, e: Mapping[str, object]) -> None:
        values = e.get("values")
        if self.attempt is not None and isinstance(values, Mapping):
            self._record(values, self.attempt.at)

    def _on_branch(self, e: Mapping[str, object]) -> None:
        lo, hi = _pair(e["range"])
        self._follow((lo, hi), f"{_range(lo, hi)} = {_num(_value(e['value']))}", "taken")

    def _on_nearest(self, e: Mapping[str, object]) -> None:
        lo, hi = _pair(e["branch"])
        self._follow((lo, hi), f"{_range(lo, hi)} ≈ {_num(_value(e['value']))} nearest", "recovery")

    def _on_grasp_feature_failed(self, e: Mapping[str, object]) -> None:
        self._follow((0.0, 0.0), "fails", "taken")

    def _on_unreliable(self, e: Mapping[str, object]) -> None:
        value = e.get("value")
        text = "no value (dropout)" if value is None else f"{_num(_value(value))}: no branch"
        self._visit().lines.append(Line(f"  ✗ {text}, unreliable", "failed"))

    def _on_backtrack(self, e: Mapping[str, object]) -> None:
        depth = int(_value(e["depth"]))
        if depth >= len(self.path):
            return
        parent, test = self.path[depth]
        self.path = self.path[:depth]
        for key in [k for k in self.measurements if k[0] == test.feature
                    and (test.position.covers(k[1]) or k[1].covers(test.position))]:
            del self.measurements[key]
        self._arrive(parent, "backtrack", "recovery")

    def _on_choose_grasp(self, e: Mapping[str, object]) -> None:
        visit = self._visit()
        visit.kind = "grasp"
        grasp = str(e["grasp"])
        at = position_from_json(e["at"], "at")
        options = [o for o in grasp_options(self.node, self.position, self.ctx) if o.grasp == grasp]
        where = options[0].library_position if options and options[0].library_position else at
        self.attempt = _Attempt(None, None, at, grasp)
        move = _seconds(e.get("move_s"))
        if move is None or move > 0:
            visit.lines.append(Line(f"move-to-{at} {_secs(move)}"))
        try_ = "ambiguous leaf, try " if e.get("how") == "ambiguous" else ""
        visit.lines.append(Line(f"{try_}{grasp}{where} {_secs(self.ctx.knowledge.grasp(grasp).time_s)}"))
        candidates = e.get("candidates")
        if isinstance(candidates, Sequence) and candidates:
            visit.lines.append(Line(_ids([str(c) for c in candidates]), "note"))
        self.position = at

    def _on_no_path(self, e: Mapping[str, object]) -> None:
        to = position_from_json(e["to"], "to")
        self._visit().lines.append(Line(f"  ✗ no path to {to}", "failed"))

    def _on_other_end(self, e: Mapping[str, object]) -> None:
        to = position_from_json(e["to"], "to")
        self._visit().lines.append(Line(f"  from the other end {to}", "failed"))

    def _on_driver_error(self, e: Mapping[str, object]) -> None:
        self._visit().lines.append(Line(f"  ✗ driver: {e.get('code')}", "failed"))

    def _on_grasp(self, e: Mapping[str, object]) -> None:
        visit = self._visit()
        if e.get("as_feature") and e.get("success") and self.attempt is not None:
            grasp = self.attempt.grasp  # following the branch ends the attempt
            self._follow((1.0, 1.0), "holds", "taken")
            self._visit().kind = "grasp"
            self._visit().lines.append(Line(f"{grasp} ✓ in the hand", "ok"))
        elif e.get("success"):
            visit.lines.append(Line("  ✓ holds", "ok"))
        else:
            visit.lines.append(Line("  ✗ fails", "failed"))

    def _on_side_effect(self, e: Mapping[str, object]) -> None:
        effect = e.get("effect")
        if effect == "pushed":
            self.effect = f"pushed {_num(_value(e.get('shift_in', 0.0)))} in"
        elif effect == "changed":
            self.effect = "changed (knocked over)"
        else:
            self.effect = ""

    def _on_start_over(self, e: Mapping[str, object]) -> None:
        visit = self._visit()
        visit.lines.append(Line(f"  {self.effect or 'side effects'}: start over", "failed"))
        grasp = self.attempt.grasp if self.attempt is not None else None
        if e.get("changed"):
            self.dropped.clear()
            self.pushes.clear()
            self.measurements.clear()
        elif grasp is not None:
            self.pushes[grasp] += 1
            if self.pushes[grasp] >= 2:
                self.dropped.add(grasp)
            else:
                self.dropped.discard(grasp)
        self.position = position_from_json(e["at"], "at")
        self._new_round("start over", "recovery")

    def _on_drop_grasp(self, e: Mapping[str, object]) -> None:
        grasp = str(e["grasp"])
        self._visit().lines.append(Line(f"  drop {grasp}, rebuild", "failed"))
        candidates = e.get("candidates")
        kept = set(candidates) if isinstance(candidates, Sequence) else set()
        descriptions = self.ctx.matrix.descriptions
        self.dropped = {d.grasp for d in descriptions} - {d.grasp for d in descriptions if d.object_id in kept}
        self._new_round(f"rebuild, {len(kept)} left", "recovery")

    def _on_discriminate(self, e: Mapping[str, object]) -> None:
        # measured after the failed grasp, before the rebuilt tree's first test: it belongs
        # to the failed grasp's box, not to the next one
        box = self.visits[-1] if self.visits else self._visit()
        if e.get("already"):
            box.lines.append(Line("  discriminate: already told apart", "note"))
            return
        values = e.get("values")
        if isinstance(values, Mapping):
            self._record(values, self.position)
            told = " (told apart)" if e.get("told_apart") else ""
            for feature, value in values.items():
                shown = "no value" if value is None else _num(_value(value))
                box.lines.append(Line(f"  discriminate: {feature} = {shown}{told}", "note"))

    def _on_leave(self, e: Mapping[str, object]) -> None:
        self._visit().lines.append(Line("  ✓ left on the floor", "ok"))

    def _on_learn(self, e: Mapping[str, object]) -> None:
        if e.get("id"):
            by_appearance = e.get("by") == "appearance"
            what = "by its appearance, nothing sensed" if by_appearance else f"{e.get('features')} features"
            self._visit().lines.append(Line(f"learned {e['id']} ({what})", "note"))

    def _on_gave_up(self, e: Mapping[str, object]) -> None:
        self._visit().lines.append(Line(f"✗ gave up: {e.get('reason')}", "failed"))

    # -- the learner's side ---------------------------------------------------------------
    def _new_round(self, label: str, style: Style) -> None:
        """The tree is (re)built from the root over the descriptions not ruled out."""
        dropped = [i for i, d in enumerate(self.ctx.matrix.descriptions) if d.grasp in self.dropped]
        self.path = []
        self._arrive(Node.root(len(self.ctx.matrix.descriptions), dropped), label, style)

    def _scored(self, test: Test | None, at: Position) -> ScoredTest | None:
        """The chosen test with its branch ranges at the current node (the ranges depend
        only on the descriptions there, so ranking this one test alone recomputes them)."""
        if test is None:
            return None
        others = frozenset(t for t in self.ctx.matrix.tests if t != test)
        ranked = rank(self.node, at, self.ctx, self.measurements, others)
        return ranked[0] if ranked else None

    def _follow(self, taken: Range, label: str, style: Style) -> None:
        """The attempt's branch ``taken`` is followed: its siblings are regrown."""
        visit, attempt = self._visit(), self.attempt
        if attempt is None:
            return
        scored = attempt.scored
        idx = None if scored is None else _index(scored.ranges, taken)
        if scored is None or idx is None:  # not replayable from this library: the followed branch alone
            visit.branches = [(label, None)]
            child = self.node
        else:
            children = split(self.node, scored, self.ctx.matrix)
            visit.branches = [(label, None) if i == idx else
                              (_branch_label(scored.test, r), self._regrow(children[i], attempt, r))
                              for i, r in enumerate(scored.ranges)]
            child = children[idx]
        visit.style = style
        if attempt.test is not None:
            self.path.append((self.node, attempt.test))
        self.node, self.attempt, self.pending = child, None, ("", style)

    def _regrow(self, node: Node, attempt: _Attempt, branch: Range) -> Shape | TreeNode:
        """What the learner would grow below a branch not taken."""
        assert attempt.test is not None and attempt.scored is not None
        if attempt.test.is_grasp and branch[0] >= 1.0:
            return Shape((Line(f"{attempt.test.feature} ✓ in the hand", "ok"),), "grasp", False)
        exclude = frozenset(t for _, t in self.path) | {attempt.test}
        return grow(node, attempt.scored.target, self.ctx, dict(self.measurements), exclude)

    def _record(self, values: Mapping[str, object], at: Position) -> None:
        where = Position(at.distance_in, None) if self.orientation_free else at
        for feature, value in values.items():
            if isinstance(value, (int, float)):
                self.measurements[(feature, where)] = float(value)


ELIDED = Shape((Line("…"),), "elided", False)


def _shape_of(tree: TreeNode, levels: int) -> Shape:
    """A regrown subtree: its first test and ``levels`` more levels below it; below the
    deepest test shown, one "…" stands for the rest."""
    if isinstance(tree, GraspLeaf):
        if tree.grasped:
            return Shape((Line(f"{tree.grasp} ✓ in the hand", "ok"),), "grasp", False)
        lines = [Line(f"move-to-{tree.position} {_secs(tree.move_cost)}")] if tree.move_cost > 0 else []
        lines += [Line(f"{tree.grasp}{tree.library_position or tree.position} {_secs(tree.grasp_cost)}"),
                  Line(_ids(list(tree.object_ids)), "note")]
        return Shape(tuple(lines), "grasp", False)
    if isinstance(tree, AmbiguousLeaf):
        return Shape((Line("ambiguous, try"), Line(" | ".join(o.grasp for o in tree.options)),
                      Line(_ids(list(tree.object_ids)), "note")), "ambiguous", False)
    assert isinstance(tree, TestNode)
    t = tree.test
    lines = [Line(f"move-to-{t.target} {_secs(t.move_cost)}")] if t.move_cost > 0 else []
    known = t.move_cost == 0 and t.sense_cost == 0
    as_test = " as a test" if t.test.is_grasp else ""
    lines.append(Line(f"{t.test}{as_test} {'known, 0s' if known else _secs(t.sense_cost)}"))
    if levels <= 0:
        return Shape(tuple(lines), "test", False, (Branch("", ELIDED, "untaken"),))
    return Shape(tuple(lines), "test", False, tuple(
        Branch(_branch_label(t.test, r), _shape_of(child, levels - 1), "untaken") for r, child in tree.branches))


# -- text ------------------------------------------------------------------------------


def _branch_label(test: Test, r: Range) -> str:
    if test.is_grasp:
        return "holds" if r[0] >= 1.0 else "fails"
    return _range(*r)


def _range(lo: float, hi: float) -> str:
    return f"[{_num(lo)},{_num(hi)}]"


def _num(v: float) -> str:
    """A value as the paper prints it: 25, 27.5, 3.42."""
    return f"{v:.2f}".rstrip("0").rstrip(".") if math.isfinite(v) else str(v)


def _secs(s: float | None) -> str:
    return "no path" if s is None or not math.isfinite(s) else f"{s:.0f}s"


def _ids(ids: list[str], width: int = 34) -> str:
    """Candidate object ids, shortened to fit a box: the first, then how many more."""
    text = ", ".join(ids)
    if len(text) <= width:
        return text
    more = f" +{len(ids) - 1}" if len(ids) > 1 else ""
    first = ids[0]
    room = width - len(more)
    return (first if len(first) <= room else first[:room - 1] + "…") + more


def _index(ranges: Sequence[Range], taken: Range) -> int | None:
    for i, (lo, hi) in enumerate(ranges):
        if math.isclose(lo, taken[0], abs_tol=1e-6) and math.isclose(hi, taken[1], abs_tol=1e-6):
            return i
    return None


def _pair(value: object) -> tuple[float, float]:
    assert isinstance(value, Sequence) and len(value) == 2
    return _value(value[0]), _value(value[1])


def _value(value: object) -> float:
    assert isinstance(value, (int, float))
    return float(value)


def _seconds(value: object) -> float | None:
    """Logged seconds; null means infinite (no path)."""
    return None if value is None else _value(value)


# -- where the boxes go ---------------------------------------------------------------

BOX_PT = 8.0  # font size of the boxes' text (points); monospace, so widths are known
LABEL_PT = 7.0  # font size of the edge labels
CHAR_W = 0.63 / 72  # DejaVu Sans Mono's advance per point, in inches, as drawn at 100 dpi (whole pixels)
LINE_H = 1.3 / 72  # line height per point of font size, in inches
PAD = 0.07  # inside a box, each side (in)
GAP = 0.22  # between neighbouring boxes on a level (in)
LINK_H = 0.5  # between a level's deepest box and the next level: the bus and the labels (in)
LABEL_H = LABEL_PT * LINE_H + 0.04  # the label band just above a box (in)


@dataclass(frozen=True)
class Box:
    """A placed box: centre ``x`` and ``top`` in inches (``top`` grows downwards)."""

    x: float
    top: float
    width: float
    height: float
    depth: int
    lines: tuple[Line, ...]
    kind: Kind
    taken: bool


@dataclass(frozen=True)
class Link:
    """An edge from box ``parent`` to box ``child`` (indices into ``TreeLayout.boxes``)."""

    parent: int
    child: int
    label: str
    style: Style


@dataclass(frozen=True)
class TreeLayout:
    """The figure: boxes in preorder (the root first), links, and the overall size (in)."""

    boxes: tuple[Box, ...]
    links: tuple[Link, ...]
    width: float
    height: float


def box_size(lines: Sequence[Line]) -> tuple[float, float]:
    """Width and height (in) of a box holding ``lines``."""
    chars = max((len(line.text) for line in lines), default=1)
    return chars * CHAR_W * BOX_PT + 2 * PAD, len(lines) * LINE_H * BOX_PT + 2 * PAD


def label_width(label: str) -> float:
    return len(label) * CHAR_W * LABEL_PT + 0.08


@dataclass(frozen=True)
class _Placed:
    """A subtree measured: its contour (left, right extent per level, relative to its
    root's centre) and its children's offsets from its root's centre."""

    contour: tuple[tuple[float, float], ...]
    offsets: tuple[float, ...]
    children: tuple[_Placed, ...]


def _measure(shape: Shape, label: str) -> _Placed:
    """Reingold-Tilford style: each child subtree is pushed right until it clears its left
    siblings at every level. A box on the path sits straight above the next box on the
    path, so the path runs down one column and the branches not taken fan out to both
    sides (centring over the children lets a long path drift sideways and the figure
    grow as wide as all its levels together), unless centring it over its children
    makes its subtree narrower; other boxes are centred over their children."""
    half = max(box_size(shape.lines)[0], label_width(label) if label else 0.0) / 2
    kids = [_measure(b.child, b.label) for b in shape.branches]
    if not kids:
        return _Placed(((-half, half),), (), ())
    acc = list(kids[0].contour)
    offsets = [0.0]
    for kid in kids[1:]:
        shift = max(acc[d][1] + GAP - kid.contour[d][0] for d in range(min(len(acc), len(kid.contour))))
        offsets.append(shift)
        for d, (lo, hi) in enumerate(kid.contour):
            if d < len(acc):
                acc[d] = (min(acc[d][0], shift + lo), max(acc[d][1], shift + hi))
            else:
                acc.append((shift + lo, shift + hi))
    anchors = [o for o, b in zip(offsets, shape.branches) if b.style != "untaken"][:1]  # the path, if here
    anchors.append((offsets[0] + offsets[-1]) / 2)
    best: _Placed | None = None
    for a in anchors:
        placed = _Placed(((-half, half),) + tuple((lo - a, hi - a) for lo, hi in acc), tuple(o - a for o in offsets),
                         tuple(kids))
        if best is None or _span(placed.contour) < _span(best.contour) - 1e-6:
            best = placed
    assert best is not None
    return best


def _span(contour: Sequence[tuple[float, float]]) -> float:
    return max(hi for _, hi in contour) - min(lo for lo, _ in contour)


def layout(root: Shape) -> TreeLayout:
    """Place the tree: levels top-down, each as tall as its tallest box plus room for the
    edges and their labels; no two boxes (with their labels) overlap on a level."""
    placed = _measure(root, "")
    left = min(lo for lo, _ in placed.contour)
    heights: dict[int, float] = {}

    def level_heights(shape: Shape, depth: int) -> None:
        heights[depth] = max(heights.get(depth, 0.0), box_size(shape.lines)[1])
        for b in shape.branches:
            level_heights(b.child, depth + 1)

    level_heights(root, 0)
    tops = [0.0]
    for d in range(1, len(heights)):
        tops.append(tops[-1] + heights[d - 1] + LINK_H)
    boxes: list[Box] = []
    links: list[Link] = []

    def emit(shape: Shape, p: _Placed, x: float, depth: int) -> int:
        w, h = box_size(shape.lines)
        me = len(boxes)
        boxes.append(Box(x, tops[depth], w, h, depth, shape.lines, shape.kind, shape.taken))
        for branch, kid, offset in zip(shape.branches, p.children, p.offsets):
            child = emit(branch.child, kid, x + offset, depth + 1)
            links.append(Link(me, child, branch.label, branch.style))
        return me

    emit(root, placed, -left, 0)
    width = max(hi for _, hi in placed.contour) - left
    return TreeLayout(tuple(boxes), tuple(links), width, tops[-1] + heights[len(heights) - 1])
