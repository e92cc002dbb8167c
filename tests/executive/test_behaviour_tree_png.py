"""``behaviour-tree.png`` is readable on a screen: drawn left to right, its width is
bounded by the tree's depth, not its breadth (it was once 3,941 px wide)."""

from __future__ import annotations

import struct
from pathlib import Path

from py_trees.behaviours import Success
from py_trees.composites import Sequence

from csl_cli.main import main
from reporting.plots import BT_COLUMN_IN, bt_label, plot_behaviour_tree


def png_size(path: Path) -> tuple[int, int]:
    """Width and height from the PNG's IHDR chunk (bytes 16 to 24)."""
    data = path.read_bytes()[:24]
    assert data[:8] == b"\x89PNG\r\n\x1a\n" and data[12:16] == b"IHDR"
    width, height = struct.unpack(">II", data[16:24])
    return width, height


def test_the_executives_tree_is_at_most_2000_px_wide(tmp_path: Path) -> None:
    png = tmp_path / "bt.png"
    assert main(["bt", "--render", str(png)]) == 0
    width, height = png_size(png)
    assert width <= 2000 and height > width / 2  # long, not wide: one leaf per row


def test_a_broader_tree_is_taller_not_wider(tmp_path: Path) -> None:
    def tree(leaves: int) -> Sequence:
        return Sequence("root", memory=False, children=[Success(f"leaf {i}") for i in range(leaves)])

    narrow, broad = tmp_path / "narrow.png", tmp_path / "broad.png"
    plot_behaviour_tree(narrow, tree(3))
    plot_behaviour_tree(broad, tree(60))
    (w3, h3), (w60, h60) = png_size(narrow), png_size(broad)
    assert w3 == w60 == round(2 * BT_COLUMN_IN * 100)  # two levels at 100 dpi
    assert h60 > 10 * h3


def test_labels_wrap_at_spaces_and_keep_a_long_word_whole() -> None:
    assert bt_label("→ ApplyTest or re-approach") == "→ ApplyTest or\nre-approach"
    assert bt_label("RememberAppearance") == "RememberAppearance"
