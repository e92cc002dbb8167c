"""Suite-wide settings: no colours in py_trees output, so snapshots are plain text, and
no test ever writes to the user's data folder."""

import os
from pathlib import Path

import pytest

os.environ.setdefault("PY_TREES_DISABLE_COLORS", "1")


@pytest.fixture(autouse=True)
def _csl_home(tmp_path_factory: pytest.TempPathFactory, monkeypatch: pytest.MonkeyPatch) -> Path:
    """``CSL_HOME`` in a temporary folder for every test: a command run without
    ``--library`` or ``--db`` would otherwise create ``~/.local/share/csl``."""
    home = tmp_path_factory.mktemp("csl-home")
    monkeypatch.setenv("CSL_HOME", str(home))
    return home
