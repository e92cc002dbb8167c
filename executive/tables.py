"""Readable tables on the terminal (rich), plain when the output is not a terminal."""

from __future__ import annotations

from collections.abc import Sequence

from rich.console import Console
from rich.table import Table


def print_table(headers: Sequence[str], rows: Sequence[Sequence[str]], title: str | None = None,
                wrap: Sequence[str] = (), caption: str | None = None) -> None:
    """A table; only the ``wrap`` columns may wrap, the others keep their words whole
    (a narrow terminal squeezes the wrapping ones rather than splitting 'grasped')."""
    table = Table(title=title, caption=caption, show_lines=False)
    for h in headers:
        table.add_column(h, no_wrap=h not in wrap, overflow="fold" if h in wrap else "ellipsis")
    for r in rows:
        table.add_row(*r)
    console = Console(soft_wrap=False)
    if not console.is_terminal:  # a log or a pipe: do not squeeze the table into 80 columns
        console = Console(soft_wrap=False, width=max(console.width, 180))
    console.print(table)
