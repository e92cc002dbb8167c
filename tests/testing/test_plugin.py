"""The pytest plugin as a user meets it: the example of docs/snapshot-testing.md copied
into an empty folder and run with pytest (fixtures found through the entry point),
and a pytest without syrupy that still works."""

from __future__ import annotations

import os
import re
import subprocess
import sys
from pathlib import Path

import pytest

DOC = Path(__file__).resolve().parents[2] / "docs" / "snapshot-testing.md"
OWN_SNAPSHOTS = Path(__file__).resolve().parents[1] / "executive" / "__snapshots__" / "test_behaviour_tree"


def _example() -> str:
    """The doc's complete example: the python block that starts with its file's name."""
    found = re.search(r"```python\n(# test_my_robot\.py\n.*?)```", DOC.read_text(encoding="utf-8"), re.S)
    assert found, "docs/snapshot-testing.md lost its complete example"
    return found.group(1)


def _pytest(folder: Path, *args: str, env: dict[str, str] | None = None) -> subprocess.CompletedProcess[str]:
    """pytest in ``folder`` as a user starts it: without the ``PYTEST_XDIST_*`` variables of
    this run's worker, which would make syrupy leave its report to a controller that is not
    there."""
    env = {k: v for k, v in (os.environ if env is None else env).items() if not k.startswith("PYTEST_XDIST_")}
    return subprocess.run([sys.executable, "-m", "pytest", "-p", "no:cacheprovider", *args], cwd=folder,
                          capture_output=True, text=True, timeout=300, env=env)


@pytest.mark.slow  # three pytest processes, three episodes each
def test_the_docs_example_runs_in_an_empty_folder(tmp_path: Path) -> None:
    folder = tmp_path / "user"
    folder.mkdir()
    test_file = folder / "test_my_robot.py"
    test_file.write_text(_example(), encoding="utf-8")

    written = _pytest(folder, "--snapshot-update")
    assert written.returncode == 0, written.stdout + written.stderr
    snapshots = folder / "__snapshots__" / "test_my_robot"
    assert sorted(p.name for p in snapshots.iterdir()) == [
        "test_a_cup_is_recognised_and_grasped.txt", "test_tree_shape.txt", "test_what_is_learned_is_used_next_time.txt"]
    # the doc's cup is the project's own clean recognition: the same scenario, the same bytes
    assert (snapshots / "test_a_cup_is_recognised_and_grasped.txt").read_bytes() == (
        OWN_SNAPSHOTS / "test_appearance_recognition.txt").read_bytes()
    assert (snapshots / "test_what_is_learned_is_used_next_time.txt").read_text(encoding="utf-8").count(
        "# --- next encounter ---") == 1

    again = _pytest(folder)
    assert again.returncode == 0, again.stdout + again.stderr
    assert "3 passed" in again.stdout

    # the cup elsewhere on the floor: another path, another transcript (with the appearance on,
    # a noise seed alone may not change what the robot does)
    test_file.write_text(_example().replace('"cup-8oz/upright", seed=0', '"cup-8oz/upright", seed=0, x_in=60.0'),
                         encoding="utf-8")
    changed = _pytest(folder)
    assert changed.returncode == 1
    assert "1 failed, 2 passed" in changed.stdout and "1 snapshot failed" in changed.stdout
    assert "test_a_cup_is_recognised_and_grasped" in changed.stdout


@pytest.mark.slow
def test_pytest_without_syrupy_works_and_csl_snapshot_says_what_to_install(tmp_path: Path) -> None:
    hidden = tmp_path / "hidden" / "syrupy"
    hidden.mkdir(parents=True)
    (hidden / "__init__.py").write_text('raise ImportError("syrupy is hidden for this test")\n', encoding="utf-8")
    folder = tmp_path / "user"
    folder.mkdir()
    (folder / "test_plain.py").write_text(
        "import os\n\n\n"
        "def test_scenarios_need_no_syrupy(csl_scenario, tmp_path):\n"
        "    assert os.environ['CSL_HOME'] == str(tmp_path / 'csl-home')\n"
        "    assert csl_scenario.one_object('cup-8oz/upright').workdir == tmp_path\n\n\n"
        "def test_snapshot(csl_snapshot):\n"
        "    pass\n", encoding="utf-8")
    env = {**os.environ, "PYTHONPATH": str(hidden.parent)}
    result = _pytest(folder, "-p", "no:syrupy", env=env)
    assert result.returncode == 1, result.stdout + result.stderr
    assert re.search(r"\b1 passed, 1 error\b", result.stdout), result.stdout
    assert "csl_snapshot needs syrupy, which is not installed: pip install syrupy" in result.stdout
    assert "Traceback" not in result.stdout + result.stderr and "During handling" not in result.stdout


def test_loading_the_plugin_imports_neither_the_simulator_nor_syrupy() -> None:
    """Every pytest run in an environment with csl-executive loads the plugin."""
    probe = ("import sys, csl_testing.plugin; "
             "print(sorted(m for m in ('syrupy', 'executive', 'hero_driver', 'ompl', 'pymunk') if m in sys.modules))")
    loaded = subprocess.run([sys.executable, "-c", probe], capture_output=True, text=True, timeout=60, check=True)
    assert loaded.stdout.strip() == "[]"
