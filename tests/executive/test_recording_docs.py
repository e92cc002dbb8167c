"""docs/recording.md lists exactly the channels a recording has, each with its schema."""

from __future__ import annotations

import re
from pathlib import Path

from recording import topics

DOC = Path(__file__).resolve().parents[2] / "docs" / "recording.md"


def test_the_docs_list_every_channel_with_its_schema() -> None:
    rows = re.findall(r"^\| `(/[a-z_/]+)` \| `([A-Za-z.]+)` \| (.+) \|$", DOC.read_text(encoding="utf-8"),
                      re.MULTILINE)
    assert rows == [(t.name, t.schema, t.carries) for t in topics.ALL]
