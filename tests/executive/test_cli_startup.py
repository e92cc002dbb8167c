"""``csl --help`` and the argument parsing of every command stay light: the planner
stack, the simulator, the transport and matplotlib are imported only by the command
that runs them (a user's shell completion or ``--help`` should not pay ~1 s for them)."""

from __future__ import annotations

import json
import subprocess
import sys
from pathlib import Path

REPO = Path(__file__).resolve().parents[2]
HEAVY = ("matplotlib", "ompl", "pymunk", "cv2", "zenoh", "py_trees", "scipy")


def test_building_the_parser_imports_no_heavy_stack() -> None:
    code = ("import json, sys\nfrom csl_cli.main import build_parser\nbuild_parser()\n"
            f"print(json.dumps(sorted(m for m in {HEAVY!r} if m in sys.modules)))")
    out = subprocess.run([sys.executable, "-c", code], cwd=REPO, capture_output=True, text=True, check=True)
    assert json.loads(out.stdout) == []
