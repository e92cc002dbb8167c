"""docs/vendor-guide.md's table of vendor mistakes names, for each, the test that serves
the altered driver: every named test exists, so the table cannot claim a catch that no
test shows (issue: every mistake a fixture)."""

from __future__ import annotations

import ast
import re
from pathlib import Path

ROOT = Path(__file__).resolve().parents[2]
GUIDE = ROOT / "docs" / "vendor-guide.md"
SECTION = "### Mistakes we have seen, and where each is caught"


def _rows() -> list[list[str]]:
    text = GUIDE.read_text(encoding="utf-8")
    lines = text[text.index(SECTION):].splitlines()
    start = next(i for i, line in enumerate(lines) if line.startswith("| mistake |"))
    rows = []
    for line in lines[start + 2:]:
        if not line.startswith("|"):
            break
        rows.append([cell.strip() for cell in line.strip().strip("|").split("|")])
    return rows


def _tests_in(path: Path) -> set[str]:
    tree = ast.parse(path.read_text(encoding="utf-8"))
    return {node.name for node in tree.body if isinstance(node, ast.FunctionDef) and node.name.startswith("test_")}


def test_every_mistake_is_caught_somewhere_and_names_its_fixture() -> None:
    rows = _rows()
    assert len(rows) >= 20
    for mistake, suite, run, fixtures in rows:
        assert suite or run, f"{mistake}: caught nowhere"
        named = re.findall(r"`(tests/[\w/]+\.py)::(test_\w+)`", fixtures)
        assert named, f"{mistake}: no fixture named"
        for path, name in named:
            assert name in _tests_in(ROOT / path), f"{mistake}: {path}::{name} does not exist"


def test_the_issues_mistakes_are_all_in_the_table() -> None:
    mistakes = " ".join(row[0] for row in _rows())
    for kind in ("centimetres", "stuck at \"held\"", "yaw", "extra field in the sense reply", "milliseconds",
                 "radians", "freed just after its reply", "`internal` to every grasp", "room changed"):
        assert kind in mistakes, kind
