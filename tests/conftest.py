"""Suite-wide settings: no colours in py_trees output, so snapshots are plain text; no
test ever writes to the user's data folder; and hypothesis draws the same examples on
every run.

Why repeatable by default: a property test that draws new examples on every run fails
only now and then when it finds a rare case (a lone box at a floor corner seen through
the fish-eye camera, say), and then the suite's result depends on luck, not on the
change under test. The default profile (``repeatable``) derandomizes every property
test and keeps no example database (nothing written beside the sources); ``python -m pytest
--hypothesis-profile explore`` draws fresh examples, to look for new cases on purpose.

Neither profile has a deadline: hypothesis's default fails an example that takes over
200 ms of wall-clock time, which says more about the machine's load (parallel workers,
other jobs) than about the code; speed is measured in bench/.
"""

import os
import tempfile
from pathlib import Path

import pytest
from hypothesis import settings
from hypothesis.configuration import set_hypothesis_home_dir

os.environ.setdefault("PY_TREES_DISABLE_COLORS", "1")

settings.register_profile("repeatable", derandomize=True, database=None, print_blob=True, deadline=None)
settings.register_profile("explore", database=None, print_blob=True, deadline=None)


def pytest_configure(config: pytest.Config) -> None:
    """Load ``repeatable`` unless ``--hypothesis-profile`` names another profile, and
    keep hypothesis's own files (its cache of constants) in a temporary folder, not in
    ``.hypothesis/`` beside the sources."""
    if not config.getoption("hypothesis_profile", default=None):
        settings.load_profile("repeatable")
    set_hypothesis_home_dir(tempfile.mkdtemp(prefix="csl-hypothesis-"))


@pytest.fixture(autouse=True)
def _csl_home(tmp_path_factory: pytest.TempPathFactory, monkeypatch: pytest.MonkeyPatch) -> Path:
    """``CSL_HOME`` in a temporary folder for every test: a command run without
    ``--library`` or ``--db`` would otherwise create ``~/.local/share/csl``."""
    home = tmp_path_factory.mktemp("csl-home")
    monkeypatch.setenv("CSL_HOME", str(home))
    return home
