"""Tables that read well in an 80-column terminal and in a pipe.

On a terminal (a real pseudo-terminal here, 80 columns) the demo's table is one line
per object and no line is wider than the terminal; in a pipe a table is plain text,
one line per row, with no box drawing."""

from __future__ import annotations

import fcntl
import os
import pty
import re
import struct
import subprocess
import sys
import termios
from pathlib import Path

from hypothesis import given
from hypothesis import strategies as st
from rich.cells import cell_len
from rich.console import Console

import pytest

from executive import defaults
from csl_cli.main import main
from csl_cli.commands.offline import MEASURED_COLUMNS
from reporting.tables import Column, plain_lines, rich_table
from learner.library.format import read_library_json

REPO = Path(__file__).resolve().parents[2]
ANSI = re.compile(r"\x1b\[[0-9;?]*[A-Za-z]")
BOX = set("│┃━─┏┓└┘┡┩╇┳┻")
LAB_OBJECTS = ("closed-box-2x2x2/upright", "tumbler-20oz/upside-down", "soda-bottle-16oz/upright",
               "magazine-box-9x4x7/upright", "soda-bottle-16oz/lying", "tumbler-20oz/upright",
               "closed-box-10x10x10/upright")


def _in_terminal(argv: list[str], columns: int = 80, timeout_s: float = 120.0) -> list[str]:
    """Run ``csl ARGV`` with a pseudo-terminal of ``columns`` as its standard output;
    its lines, colour codes removed."""
    master, slave = pty.openpty()
    fcntl.ioctl(slave, termios.TIOCSWINSZ, struct.pack("HHHH", 50, columns, 0, 0))
    env = {**os.environ, "COLUMNS": str(columns), "TERM": "xterm", "PYTHONPATH": str(REPO)}
    process = subprocess.Popen([sys.executable, "-m", "csl_cli", *argv], cwd=REPO, env=env, stdin=slave,
                               stdout=slave, stderr=subprocess.DEVNULL)
    os.close(slave)
    chunks = []
    try:
        while True:
            try:
                data = os.read(master, 65536)
            except OSError:  # EIO: the child closed its end
                break
            if not data:
                break
            chunks.append(data)
    finally:
        os.close(master)
        process.wait(timeout=timeout_s)
    text = ANSI.sub("", b"".join(chunks).decode("utf-8", errors="replace"))
    return [line.rstrip("\r") for line in text.split("\n")]


@pytest.mark.slow
def test_the_demo_table_fits_80_columns_one_line_per_object(tmp_path: Path) -> None:
    lines = _in_terminal(["demo", "--no-plots", "--out", str(tmp_path)])
    report = lines[:next(i for i, line in enumerate(lines) if line.startswith("robot time:")) + 1]
    assert max(cell_len(line) for line in report) <= 80  # below it, lines naming files (as long as their paths)
    title = next(i for i, line in enumerate(lines) if "one row per object" in line)
    header, rule, *rest = lines[title + 1:]
    assert header.split()[:4] == ["#", "object", "grasp", "outcome"] and set(rule) == {"─"}
    # each object whole on its own line, numbered as `csl log --object N` takes it
    # (a trailing * marks an object knocked over during the episode, as the caption says)
    assert [[n, name.rstrip("*")] for n, name, *_ in (line.split() for line in rest[:7])] == [
        [str(i), name] for i, name in enumerate(LAB_OBJECTS)]
    assert rest[7].startswith("min: robot minutes")
    assert len(lines) < 40  # it was 292 lines at 80 columns, most of them one letter wide


@pytest.mark.slow
def test_in_a_pipe_the_demo_table_is_plain_text(tmp_path: Path, capsys) -> None:  # noqa: ANN001
    assert main(["demo", "--no-plots", "--out", str(tmp_path)]) == 0
    out = capsys.readouterr().out
    assert not BOX & set(out)
    lines = out.splitlines()
    assert lines[0] == "approach and recognize: one row per object"
    assert lines[1].split() == ["#", "object", "grasp", "outcome", "ok", "min", "ms", "tests"]
    assert all(line == line.rstrip() for line in lines)
    # the recoveries of object 0 on one line however long, for grep
    recovered = [line for line in lines if line.startswith("  0 closed-box-2x2x2/upright: ")]
    assert len(recovered) == 1 and " ×" in recovered[0]


def test_library_show_in_80_columns_has_every_id_whole_and_the_grasp(tmp_path: Path, capsys) -> None:  # noqa: ANN001
    db = tmp_path / "lib.sqlite"
    assert main(["library", "--db", str(db), "import", str(defaults.EXAMPLE_LIBRARY)]) == 0
    capsys.readouterr()
    lines = _in_terminal(["library", "--db", str(db), "show"])
    assert max(cell_len(line) for line in lines) <= 80
    header = next(line for line in lines if line.startswith("id "))
    assert header.split() == ["id", "grasp", "features"]
    # the longest shipped id, whole, with its grasp(position) on the same line
    assert any(line.split()[:2] == ["open-box-9x4x5/upright-facing-sideways", "Front-Pinch(6,*)"] for line in lines)
    assert main(["library", "--db", str(db), "show"]) == 0
    plain = capsys.readouterr().out.splitlines()
    assert plain[0] == "14 descriptions" and len(plain) == 2 + 14  # title, header, one line each
    first = read_library_json(defaults.EXAMPLE_LIBRARY)[0]
    assert plain[2].split()[:2] == [first.object_id, f"{first.grasp}{first.grasp_position}"]
    assert plain[2].endswith(" ".join(str(o) for o in first.observations))  # every feature, uncropped


def test_the_training_table_folds_and_never_crops() -> None:
    applied = ", ".join(f"V-Sweep-5°(39,{o})" for o in range(0, 360, 10))  # 36 procedures, ~600 characters
    table = rich_table(MEASURED_COLUMNS, [["open-box-9x4x5/upright-facing-sideways", "36", applied]])
    console = Console(width=80, record=True, force_terminal=True, color_system=None)
    console.print(table)
    text = console.export_text()
    assert max(cell_len(line) for line in text.splitlines()) <= 80
    assert "open-box-9x4x5/upright-facing-sideways" in text and "…" not in text
    shown = [piece.strip(" ,") for line in text.splitlines()[2:] for piece in line[44:].split(", ")]
    assert [p for p in shown if p] == applied.split(", ")


def test_plain_lines_by_hand() -> None:
    columns = [Column("grasp"), Column("n", numeric=True), Column("note")]
    assert plain_lines(columns, [["Top-Pinch", "5", ""], ["No-Grab", "12", "left alone"]], title="by grasp",
                       caption="n: descriptions") == [
        "by grasp",
        "grasp       n  note",
        "Top-Pinch   5",
        "No-Grab    12  left alone",
        "n: descriptions",
    ]


CELL = st.text(alphabet="abcXYZ019-/()×°", max_size=15)


@given(st.integers(1, 5).flatmap(lambda n: st.tuples(
    st.lists(st.tuples(st.text(alphabet="abc", min_size=1, max_size=8), st.booleans()), min_size=n, max_size=n),
    st.lists(st.lists(CELL, min_size=n, max_size=n), max_size=6))))
def test_plain_tables_are_one_aligned_line_per_row(shape) -> None:  # noqa: ANN001
    spec, rows = shape
    columns = [Column(h, numeric=numeric) for h, numeric in spec]
    lines = plain_lines(columns, rows)
    assert len(lines) == 1 + len(rows) and all(line == line.rstrip() for line in lines)
    widths = [max([len(c.header), *(len(r[i]) for r in rows)]) for i, c in enumerate(columns)]
    for cells, line in zip([[c.header for c in columns], *rows], lines):
        start = 0
        for column, width, cell in zip(columns, widths, cells):
            slot = line[start:start + width].ljust(width)
            assert slot == (cell.rjust(width) if column.numeric else cell.ljust(width))
            start += width + 2
