"""The run-time tree figure (the paper's Fig. 5): the path from the log, the branches not
taken regrown by the learner, and a layout whose boxes never overlap.

The library is the hand-worked four objects of tests/learner/fixtures.py: from (60,0)
the best test is Width-Degree-1°(24,0) (move 72 s, sense 100 s) with branches [8,9]
(cup, tumbler), [18,18] (box) and [30,30] (closed box); below [8,9], Height(6,*) (move
36 s, D-Scan-0.3 84 s) splits the cup [3.5] from the tumbler [6].
"""

from __future__ import annotations

from pathlib import Path

import pytest
from hypothesis import given, settings, strategies as st

from behaviours.records import ObjectRecord
from reporting.plots import plot_object_tree, plot_tree_layout
from reporting.tree_figure import (LABEL_H, Branch, Line, Shape, TreeLayout, box_size, label_width, layout,
                                   object_figure)
from learner.choosing.criteria import criterion
from learner.costs import ModelMoveCost
from learner.runtime import RecognitionSession
from planner import Region
from tests.learner.fixtures import P, context, four_objects, hero

WIDTH, HEIGHT = "Width-Degree-1°(24,0)", "Height(6,*)"


def ev(kind: str, **data: object) -> dict[str, object]:
    return {"event": kind, "object": 0, **data}


def start() -> list[dict[str, object]]:
    return [ev("object", start=[60, 0]),
            ev("choose", how="best", test=WIDTH, at=[24, 0], move_s=72.0, sense_s=100.0),
            ev("sense", procedure="H-Sweep-1°", values={"Width-Degree-1°": 8.5})]


def clean_path() -> list[dict[str, object]]:
    """Two tests and a grasp that holds: the cup."""
    return start() + [
        ev("branch", test=WIDTH, value=8.5, range=[8, 9]),
        ev("choose", how="best", test=HEIGHT, at=[6, 0], move_s=36.0, sense_s=84.0),
        ev("sense", procedure="D-Scan-0.3", values={"Height": 3.4, "Depth": 3.0, "Top-Hole?": 1.0}),
        ev("branch", test=HEIGHT, value=3.4, range=[3.5, 3.5]),
        ev("choose_grasp", how="leaf", grasp="Front-Wrap", at=[6, 0], move_s=0.0, candidates=["cup"]),
        ev("grasp", grasp="Front-Wrap", as_feature=False, success=True),
        ev("learn", id="cup#2", features=4)]


def texts(shape: Shape) -> list[str]:
    return [line.text for line in shape.lines]


def test_a_two_test_path_branches_at_every_test_and_highlights_the_branch_taken() -> None:
    root = object_figure(clean_path() + [ev("grasp", object=1, grasp="x", success=False)], 0,
                         context(four_objects()))
    assert texts(root) == ["move-to-(24,0) 72s", f"{WIDTH} 100s"]
    assert [(b.label, b.style) for b in root.branches] == [
        ("[8,9] = 8.5", "taken"), ("[18,18]", "untaken"), ("[30,30]", "untaken")]
    height, box, closed = (b.child for b in root.branches)
    assert height.taken and not box.taken and not closed.taken
    # the branches not taken, as the learner grows them from (24,0): the box's Front-Pinch
    # is 18 in nearer (2 s/in); the closed box's No-Grab holds from anywhere
    assert texts(box) == ["move-to-(6,0) 36s", "Front-Pinch(6,*) 45s", "box"] and box.kind == "grasp"
    assert texts(closed) == ["No-Grab(*,*) 0s", "closed"]
    assert texts(height) == ["move-to-(6,0) 36s", f"{HEIGHT} 84s"]
    assert [(b.label, b.style) for b in height.branches] == [("[3.5,3.5] = 3.4", "taken"), ("[6,6]", "untaken")]
    cup, tumbler = (b.child for b in height.branches)
    assert texts(tumbler) == ["Top-Pinch(6,*) 63s", "tumbler"]
    assert texts(cup) == ["Front-Wrap(6,*) 60s", "cup", "  ✓ holds", "learned cup#2 (4 features)"]
    assert cup.lines[2].tone == "ok" and cup.branches == ()

    placed = layout(root)
    depth1 = [i for i, b in enumerate(placed.boxes) if b.depth == 1]
    assert len(depth1) == 3
    from_root = [k for k in placed.links if k.parent == 0]
    assert sorted(k.child for k in from_root) == depth1
    assert [(k.label, k.style) for k in from_root if k.style == "taken"] == [("[8,9] = 8.5", "taken")]
    assert sum(b.taken for b in placed.boxes) == 3  # the two tests and the grasp


def test_an_unreliable_value_and_the_reselected_test_share_one_box() -> None:
    # 13.5 lies between [8,9] and [18,18] widened by the ±3° error: reselect Height(6,*),
    # whose branches at the root are the cup's 3.5, the tumbler's 6 and the box's 9
    events = start() + [
        ev("unreliable", test=WIDTH, value=13.5, ranges=[[8, 9], [18, 18], [30, 30]]),
        ev("choose", how="reselect", test=HEIGHT, at=[6, 0], move_s=36.0, sense_s=84.0),
        ev("sense", procedure="D-Scan-0.3", values={"Height": 9.1}),
        ev("branch", test=HEIGHT, value=9.1, range=[9, 9]),
        ev("choose_grasp", how="leaf", grasp="Front-Pinch", at=[6, 0], move_s=0.0, candidates=["box"]),
        ev("grasp", grasp="Front-Pinch", as_feature=False, success=True)]
    root = object_figure(events, 0, context(four_objects()))
    assert texts(root) == ["move-to-(24,0) 72s", f"{WIDTH} 100s", "  ✗ 13.5: no branch, unreliable",
                           "move-to-(6,0) 36s", f"reselect: {HEIGHT} 84s"]
    assert root.lines[2].tone == "failed"
    assert [(b.label, b.style) for b in root.branches] == [
        ("[3.5,3.5]", "untaken"), ("[6,6]", "untaken"), ("[9,9] = 9.1", "taken")]
    assert texts(root.branches[2].child)[:2] == ["Front-Pinch(6,*) 45s", "box"]


def test_a_failed_grasp_rebuilds_below_it_from_the_root_without_its_descriptions() -> None:
    events = clean_path()[:-2] + [
        ev("grasp", grasp="Front-Wrap", as_feature=False, success=False),
        ev("side_effect", effect="none", shift_in=0.0, pixels=50),
        ev("drop_grasp", grasp="Front-Wrap", candidates=["box", "closed", "tumbler"]),
        ev("discriminate", already=True, wrong="Front-Wrap"),
        ev("choose", how="best", test=WIDTH, at=[6, 0], move_s=0.0, sense_s=0.0),
        ev("branch", test=WIDTH, value=8.5, range=[9, 9]),
        ev("choose_grasp", how="leaf", grasp="Top-Pinch", at=[6, 0], move_s=0.0, candidates=["tumbler"]),
        ev("grasp", grasp="Top-Pinch", as_feature=False, success=True)]
    root = object_figure(events, 0, context(four_objects()))
    failed = root.branches[0].child.branches[0].child
    assert texts(failed) == ["Front-Wrap(6,*) 60s", "cup", "  ✗ fails", "  drop Front-Wrap, rebuild",
                             "  discriminate: already told apart"]
    [rebuild] = failed.branches
    assert (rebuild.label, rebuild.style) == ("rebuild, 3 left", "recovery")
    rebuilt = rebuild.child
    assert texts(rebuilt) == [f"{WIDTH} known, 0s"]
    # without the cup the tumbler's 9 is a range of its own
    assert [b.label for b in rebuilt.branches] == ["[9,9] = 8.5", "[18,18]", "[30,30]"]
    assert texts(rebuilt.branches[0].child) == ["Top-Pinch(6,*) 63s", "tumbler", "  ✓ holds"]


def test_a_lesson_stored_by_its_appearance_says_so_not_zero_features() -> None:
    events = clean_path()[:-1] + [ev("learn", id="cup#2", features=0, by="appearance", wrong=["Top-Pinch"])]
    root = object_figure(events, 0, context(four_objects()))
    cup = root.branches[0].child.branches[0].child
    assert texts(cup)[-1] == "learned cup#2 (by its appearance, nothing sensed)"


def test_backtracking_goes_on_below_with_the_parent_choosing_again() -> None:
    events = start() + [
        ev("branch", test=WIDTH, value=8.5, range=[8, 9]),
        ev("choose", how="best", test=HEIGHT, at=[6, 0], move_s=36.0, sense_s=84.0),
        ev("sense", procedure="D-Scan-0.3", values={"Height": 4.8}),
        ev("unreliable", test=HEIGHT, value=4.8, ranges=[[3.5, 3.5], [6, 6]]),
        ev("backtrack", depth=0),
        ev("choose", how="backtrack", test=HEIGHT, at=[6, 0], move_s=0.0, sense_s=0.0),
        ev("unreliable", test=HEIGHT, value=4.8, ranges=[[3.5, 3.5], [6, 6], [9, 9]]),
        ev("nearest", branch=[3.5, 3.5], value=4.8)]
    root = object_figure(events, 0, context(four_objects()))
    child = root.branches[0].child
    assert texts(child)[-1] == "  ✗ 4.8: no branch, unreliable" and child.branches[0].label == "backtrack"
    again = child.branches[0].child
    assert child.branches[0].style == "recovery"
    assert texts(again) == [f"{HEIGHT} known, 0s", "  ✗ 4.8: no branch, unreliable"]
    assert [(b.label, b.style) for b in again.branches] == [
        ("[3.5,3.5] ≈ 4.8 nearest", "recovery"), ("[6,6]", "untaken"), ("[9,9]", "untaken")]
    assert texts(again.branches[0].child) == ["…"]  # the log ends there


def test_regrown_branches_are_elided_below_the_levels_asked_for() -> None:
    shallow = object_figure(start() + [ev("branch", test=WIDTH, value=18, range=[18, 18])], 0,
                            context(four_objects()), levels=0)
    cup_or_tumbler = shallow.branches[0].child
    assert texts(cup_or_tumbler) == ["move-to-(6,0) 36s", f"{HEIGHT} 84s"]
    assert [(b.label, texts(b.child)) for b in cup_or_tumbler.branches] == [("", ["…"])]
    deeper = object_figure(start() + [ev("branch", test=WIDTH, value=18, range=[18, 18])], 0,
                           context(four_objects()), levels=1)
    assert [b.label for b in deeper.branches[0].child.branches] == ["[3.5,3.5]", "[6,6]"]


# -- the layout -------------------------------------------------------------------------

lines = st.lists(st.text(alphabet="abcXYZ(),°[]0-9 ", min_size=1, max_size=30).map(Line), min_size=1, max_size=4)


def shapes(depth: int = 4) -> st.SearchStrategy[Shape]:
    leaf = st.builds(lambda ls: Shape(tuple(ls), "grasp", False), lines)
    if depth == 0:
        return leaf
    branch = st.builds(Branch, st.text(alphabet="[],=0123456789.", max_size=18), shapes(depth - 1),
                       st.sampled_from(["taken", "recovery", "untaken"]))
    node = st.builds(lambda ls, bs: Shape(tuple(ls), "test", True, tuple(bs)), lines,
                     st.lists(branch, min_size=1, max_size=4))
    return st.one_of(leaf, node)


def _count(shape: Shape) -> int:
    return 1 + sum(_count(b.child) for b in shape.branches)


@settings(max_examples=60, deadline=None)
@given(shapes())
def test_no_two_boxes_or_labels_overlap_and_every_box_fits_the_figure(root: Shape) -> None:
    placed = layout(root)
    assert len(placed.boxes) == _count(root) and len(placed.links) == len(placed.boxes) - 1
    label_of = {k.child: k.label for k in placed.links}
    extents = []
    for i, b in enumerate(placed.boxes):
        half = max(b.width, label_width(label_of[i]) if label_of.get(i) else 0.0) / 2
        extents.append((b.x - half, b.x + half, b.top - LABEL_H, b.top + b.height))
        assert b.x - half >= -1e-9 and b.x + half <= placed.width + 1e-9
        assert b.top + b.height <= placed.height + 1e-9
    for k in placed.links:
        assert placed.boxes[k.child].depth == placed.boxes[k.parent].depth + 1
        assert placed.boxes[k.child].top > placed.boxes[k.parent].top + placed.boxes[k.parent].height
    for i, (l1, r1, t1, b1) in enumerate(extents):
        for l2, r2, t2, b2 in extents[i + 1:]:
            assert r1 <= l2 + 1e-9 or r2 <= l1 + 1e-9 or b1 <= t2 + 1e-9 or b2 <= t1 + 1e-9


def test_boxes_are_sized_from_their_text() -> None:
    empty, ten, twenty = (box_size([Line("x" * n)]) for n in (0, 10, 20))
    assert twenty[0] - ten[0] == pytest.approx(ten[0] - empty[0]) and ten[0] > empty[0]  # the widest line
    assert box_size([Line("x"), Line("y")])[1] - ten[1] == pytest.approx(ten[1] - box_size([])[1])  # a line more


# -- the picture ------------------------------------------------------------------------


def test_the_png_is_drawn_at_the_layouts_size(tmp_path: Path) -> None:
    placed = layout(object_figure(clean_path(), 0, context(four_objects())))
    out = tmp_path / "tree.png"
    plot_tree_layout(out, placed, "object 0: cup")
    data = out.read_bytes()
    assert data[:8] == b"\x89PNG\r\n\x1a\n"
    width_px = int.from_bytes(data[16:20], "big")
    assert abs(width_px - round((max(placed.width, 6.0) + 0.6) * 100)) <= 1  # 0.3 in margins, 100 dpi


def test_plot_object_tree_draws_a_record_of_the_episode(tmp_path: Path) -> None:
    k = hero()
    session = RecognitionSession.for_library(four_objects(), k, criterion("cs-id3"), ModelMoveCost(k.move), P(60, 0))
    region = Region(((0.0, 0.0), (4.0, 0.0), (4.0, 4.0), (0.0, 4.0)), (2.0, 2.0), 25, None, True, 4.0, 4.0)
    record = ObjectRecord(0, region, 25, session, ModelMoveCost(k.move), region)  # type: ignore[arg-type]
    record.finish("grasped", "Front-Wrap", P(6, 0))
    out = tmp_path / "tree-0.png"
    plot_object_tree(out, record, "cup", clean_path())
    assert out.read_bytes()[:4] == b"\x89PNG"


def test_an_object_with_nothing_logged_says_so() -> None:
    shape = object_figure([], 3, context(four_objects()))
    assert texts(shape) == ["no decision logged for this object"]
    assert isinstance(layout(shape), TreeLayout)
