"""Tables a person reads, wherever the output goes.

On a terminal a table is drawn by rich and folded to the terminal's width (``COLUMNS``
or the window's): only the columns marked ``fold`` wrap onto more lines, the others keep
their words whole, so 80 columns never split 'grasped' or crop an id. In a pipe or a
file it is plain text: one line per row, columns aligned with two spaces, no box
drawing, no colour and no width limit, so ``grep``, ``sort`` and ``awk`` see whole rows.
"""

from __future__ import annotations

import json
import sys
from collections.abc import Sequence
from dataclasses import dataclass
from typing import TextIO

from rich import box
from rich.cells import cell_len
from rich.console import Console
from rich.table import Table
from rich.text import Text

GAP = "  "
"""Between two columns of a plain table."""


@dataclass(frozen=True)
class Column:
    """One column: its header, whether its numbers line up on the right, and whether
    it may wrap onto more lines when the terminal is too narrow for the table."""

    header: str
    numeric: bool = False
    fold: bool = False


def is_terminal(stream: TextIO | None = None) -> bool:
    """Whether ``stream`` (standard output by default) is a terminal, as rich decides it
    (so ``FORCE_COLOR``/``TTY_COMPATIBLE`` and friends are honoured the same way)."""
    return Console(file=stream or sys.stdout).is_terminal


def plain_lines(columns: Sequence[Column], rows: Sequence[Sequence[str]], title: str | None = None,
                caption: str | None = None) -> list[str]:
    """The table as plain text lines: title, header, one line per row, caption; no
    trailing spaces."""
    _check_shape(columns, rows)
    widths = [max([cell_len(c.header), *(cell_len(r[i]) for r in rows)]) for i, c in enumerate(columns)]

    def line(cells: Sequence[str]) -> str:
        parts = [(" " * (w - cell_len(text)) + text) if col.numeric else text + " " * (w - cell_len(text))
                 for col, w, text in zip(columns, widths, cells)]
        return GAP.join(parts).rstrip()

    out = [title] if title else []
    out.append(line([c.header for c in columns]))
    out.extend(line(r) for r in rows)
    if caption:
        out.append(caption)
    return out


def rich_table(columns: Sequence[Column], rows: Sequence[Sequence[str]], title: str | None = None,
               caption: str | None = None, row_lines: bool = False) -> Table:
    """The table for a terminal: a rule under the header, two spaces between columns, no
    borders (every column they would take is one the data needs at 80 columns). Cells
    are plain text, never rich markup: a feature such as ``[lo, hi]`` shows as written."""
    _check_shape(columns, rows)
    table = Table(title=title, caption=caption, box=box.SIMPLE_HEAD, show_lines=row_lines, show_edge=False,
                  padding=(0, 1, 0, 0), caption_justify="left")
    for c in columns:
        table.add_column(c.header, justify="right" if c.numeric else "left", no_wrap=not c.fold,
                         overflow="fold" if c.fold else "ellipsis")
    for r in rows:
        table.add_row(*(Text(cell) for cell in r))
    return table


def print_table(columns: Sequence[Column], rows: Sequence[Sequence[str]], title: str | None = None,
                caption: str | None = None, row_lines: bool = False) -> None:
    """Print a table on standard output: rich on a terminal, plain text otherwise
    (``row_lines`` separates rows whose cells wrap onto several lines, terminal only)."""
    if is_terminal():
        Console(soft_wrap=False).print(rich_table(columns, rows, title, caption, row_lines))
    else:
        print("\n".join(plain_lines(columns, rows, title, caption)))


def print_paragraph(text: str, indent: int = 0) -> None:
    """A long line: wrapped at the terminal's width (continuation lines indented by
    ``indent`` more), or printed whole when the output is not a terminal."""
    if not is_terminal():
        print(text)
        return
    console = Console(soft_wrap=False)
    width = max(console.width - indent, 20)
    lines = Text(text).wrap(console, width)
    for i, piece in enumerate(lines):
        console.print(Text(" " * (indent if i else 0)) + piece, overflow="fold")


def _check_shape(columns: Sequence[Column], rows: Sequence[Sequence[str]]) -> None:
    for r in rows:
        if len(r) != len(columns):
            raise ValueError(f"table row has {len(r)} cells for {len(columns)} columns: {list(r)!r}")


def print_json(document: object) -> None:
    """One JSON document on standard output (``--json``): indented, UTF-8 as is."""
    json.dump(document, sys.stdout, indent=2, ensure_ascii=False)
    print()
