"""docs/snapshot-testing.md's smaller examples, executed so they cannot go stale: the
cup's transcript it quotes, and the way to the executive's tree root. (Its complete
example runs in ``test_plugin.py``, whose output is held to the same snapshot file.)"""

from __future__ import annotations

import re
from pathlib import Path

DOC = Path(__file__).resolve().parents[2] / "docs" / "snapshot-testing.md"
CUP = (Path(__file__).resolve().parents[1] / "executive" / "__snapshots__" / "test_behaviour_tree"
       / "test_appearance_recognition.txt")


def _block_after(marker: str, language: str = "") -> str:
    """The first fenced block (of ``language``) after ``marker`` in the doc."""
    text = DOC.read_text(encoding="utf-8")
    found = re.search(re.escape(marker) + r".*?```" + language + r"\n(.*?)```", text, re.S)
    assert found, f"docs/snapshot-testing.md lost the block after {marker!r}"
    return found.group(1)


def test_the_quoted_transcript_is_how_the_cups_starts() -> None:
    """The quote is the snapshot's opening lines, each as it is, up to its '...'."""
    quoted = _block_after("The cup's transcript starts like this:").splitlines()
    assert quoted[-1] == "..." and "..." not in quoted[:-1]
    assert len(quoted) > 3
    assert CUP.read_text(encoding="utf-8").splitlines()[:len(quoted) - 1] == quoted[:-1]


class _Recorded:
    """Stands in for ``csl_snapshot``: keeps what the test compared with it."""

    def __init__(self) -> None:
        self.texts: list[str] = []

    def __eq__(self, other: object) -> bool:
        self.texts.append(str(other))
        return True

    __hash__ = None  # type: ignore[assignment]


def test_the_way_to_the_executives_tree_root_runs() -> None:
    code = _block_after("## The tree's shape", "python")
    assert code.startswith("# test_my_tree.py\n")
    namespace: dict[str, object] = {}
    exec(compile(code, "test_my_tree.py", "exec"), namespace)  # noqa: S102 - the doc's own example
    snapshot = _Recorded()
    namespace["test_the_recognition_branch"](snapshot)  # type: ignore[operator]
    (branch,) = snapshot.texts
    assert branch.splitlines()[0].endswith("follow the tree")
    assert "BestTest" in branch and "LocateObjects" not in branch  # the branch, not the whole tree
