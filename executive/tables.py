"""Readable tables on the terminal (rich), plain when the output is not a terminal."""

from __future__ import annotations

from collections.abc import Sequence

from rich.console import Console
from rich.table import Table


def print_table(headers: Sequence[str], rows: Sequence[Sequence[str]], title: str | None = None) -> None:
    table = Table(title=title, show_lines=False)
    for h in headers:
        table.add_column(h, overflow="fold")
    for r in rows:
        table.add_row(*r)
    console = Console(soft_wrap=False)
    if not console.is_terminal:  # a log or a pipe: do not squeeze the table into 80 columns
        console = Console(soft_wrap=False, width=max(console.width, 180))
    console.print(table)
