"""The pytest plugin (entry point ``csl_testing`` in the ``pytest11`` group): fixtures
for snapshot tests of scenarios (docs/snapshot-testing.md).

Loaded by every pytest run where csl-executive is installed, so it imports neither
the simulator nor syrupy until a test asks for a fixture: a user without syrupy keeps
a working pytest, and only ``csl_snapshot`` fails, with the line that fixes it.
"""

from __future__ import annotations

import functools
from importlib import import_module
from pathlib import Path
from types import ModuleType
from typing import TYPE_CHECKING

import pytest

if TYPE_CHECKING:
    from csl_testing.scenario import ScenarioFactory

NEEDS_SYRUPY = "csl_snapshot needs syrupy, which is not installed: pip install syrupy"


def _single_file_module() -> ModuleType | None:
    """syrupy's single-file extensions, or None when syrupy cannot be imported."""
    try:
        return import_module("syrupy.extensions.single_file")
    except ImportError:
        return None


@functools.cache
def text_extension() -> type:
    """syrupy's single-file extension in text mode with a ``.txt`` suffix: one file per
    test under ``__snapshots__/<test module>/``, which reads well in review. Built on
    first use because syrupy may not be installed; then the test fails with one line
    (outside the import's handler, so no chained error is printed under it)."""
    single_file = _single_file_module()
    if single_file is None:
        pytest.fail(NEEDS_SYRUPY, pytrace=False)

    class TextSnapshot(single_file.SingleFileSnapshotExtension):  # type: ignore[name-defined,misc]
        _write_mode = single_file.WriteMode.TEXT
        file_extension = "txt"

    return TextSnapshot


@pytest.fixture
def csl_scenario(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> ScenarioFactory:
    """Builds scenarios (``csl_scenario(world=..., seed=...)``,
    ``csl_scenario.one_object("cup-8oz/upright")``) whose learner stores go under the
    test's ``tmp_path``, with ``CSL_HOME`` in a folder there so nothing reaches the
    user's own library."""
    from csl_testing.scenario import ScenarioFactory

    home = tmp_path / "csl-home"
    home.mkdir()
    monkeypatch.setenv("CSL_HOME", str(home))
    return ScenarioFactory(tmp_path)


@pytest.fixture
def csl_snapshot(request: pytest.FixtureRequest) -> object:
    """syrupy's ``snapshot`` writing one ``.txt`` file per test: compare a transcript
    or a tree display with ``==``; ``pytest --snapshot-update`` writes the files."""
    extension = text_extension()
    return request.getfixturevalue("snapshot").use_extension(extension)
