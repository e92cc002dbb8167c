"""Suite-wide settings: no colours in py_trees output, so snapshots are plain text."""

import os

os.environ.setdefault("PY_TREES_DISABLE_COLORS", "1")
