"""The vendor's starting point: examples/driver_template/, run as its own
process exactly as a vendor would, passes every check of ``csl driver check
--profile`` with its own profile but ``reference`` (it refuses the lab, and its toy
floor holds no reference objects), whose fingerprint it computes without this project
exactly as ``robot_profile.profile_stamp`` does; it drops its token before its
queryables at shutdown; its camera image is read by the executive's vision where the
toy world has things; it imports nothing of this project; its hardware stubs answer
``internal`` naming the stub; and the zenoh configs in docs/vendor-guide.md are ones
zenoh accepts."""

from __future__ import annotations

import ast
import importlib.util
import re
import subprocess
import sys
from collections.abc import Iterator
from contextlib import contextmanager
from pathlib import Path

import pytest
import zenoh

from hero_driver.interface import INTERNAL, DriverError
from hero_driver.zenoh_link.client import ZenohDriver
from hero_driver.zenoh_link.conformance import Procedures, shutdown_order
from hero_driver.zenoh_link.verbs import VERBS
from planner.vision import look
from robot_profile import load_profile, profile_stamp
from tests.hero_driver.test_zenoh_conformance import (ALL_CHECKS, BUSY_CHECKS, ROVER, run_check_detailed,
                                                      run_named_checks)
from tests.zenoh_rpc.support import free_endpoint

pytestmark = pytest.mark.zenoh

REPO = Path(__file__).resolve().parents[2]
TEMPLATE = REPO / "examples" / "driver_template"
TEMPLATE_PROFILE = TEMPLATE / "hero2000.toml"
GUIDE = REPO / "docs" / "vendor-guide.md"
START_TIMEOUT_S = 20.0


class Template:
    """The template driver in a child process, started from a neutral directory with
    no PYTHONPATH: it must run on what it ships with."""

    def __init__(self, robot: str, endpoint: str, *extra: str, cwd: Path) -> None:
        self.process = subprocess.Popen(
            [sys.executable, str(TEMPLATE / "driver.py"), "--robot", robot, "--listen", endpoint, *extra],
            cwd=cwd, env={"PATH": "/usr/bin:/bin"}, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
        line = self.process.stdout.readline() if self.process.stdout else ""
        if not line:
            self.process.wait(START_TIMEOUT_S)
            raise RuntimeError(f"template exited: {self.process.stderr.read() if self.process.stderr else ''}")

    def stop(self) -> int:
        self.process.terminate()
        status = self.process.wait(10)
        for stream in (self.process.stdout, self.process.stderr):
            if stream:
                stream.close()
        return status


@contextmanager
def toy_template(directory: Path, time_scale: float) -> Iterator[tuple[str, str]]:
    """The toy backend on a free port, its moves taking ``time_scale`` real s per robot s."""
    endpoint = free_endpoint()
    process = Template("tpl", endpoint, "--time-scale", str(time_scale), cwd=directory)
    try:
        yield "tpl", endpoint
    finally:
        assert process.stop() == 0  # SIGTERM: a clean shutdown, token first


@pytest.fixture
def template(tmp_path: Path) -> Iterator[tuple[str, str]]:
    """The toy backend, its moves at 0.05 real s per robot s: they still take real time
    (the turns check's 200 degrees, 40 robot s, take 2 s), and the whole suite runs in
    a few seconds. The busy check's 10-degree turn is then 0.1 s, too short to overlap
    a release: :func:`test_the_templates_turn_makes_a_second_verb_busy` slows it down."""
    with toy_template(tmp_path, 0.05) as served:
        yield served


def _template_knowledge():  # noqa: ANN202 - the template's own module, loaded from its file
    spec = importlib.util.spec_from_file_location("template_knowledge", TEMPLATE / "knowledge.py")
    assert spec is not None and spec.loader is not None
    module = importlib.util.module_from_spec(spec)
    sys.modules[spec.name] = module  # dataclasses look their module up while the file runs
    spec.loader.exec_module(module)
    return module


@pytest.mark.slow
def test_the_template_passes_every_conformance_check_but_the_reference(template: tuple[str, str],
                                                     capsys: pytest.CaptureFixture[str]) -> None:
    robot, endpoint = template
    # a 90-degree turn of the turns check takes 18 robot s, 0.9 s here: 15 s for each reply
    status, verdicts, details = run_check_detailed(endpoint, robot, capsys, 15.0, "--profile", str(TEMPLATE_PROFILE))
    assert set(verdicts) == ALL_CHECKS | {"reference"}
    # it refuses the lab, as a real robot must, and its toy floor holds no reference objects
    assert {name for name, verdict in verdicts.items() if verdict == "FAIL"} == {"reference"}, details
    assert details["reference"] == "sensing and grasping NOT checked: run with --reference"
    assert status == 1
    stamp = profile_stamp(load_profile(TEMPLATE_PROFILE))
    assert details["profile"] == f"serves hero2000 (sha256 {stamp.sha256[:12]}), as given"
    assert details["reset-objects"].startswith("not checked: the driver cannot restore world 'lab'")
    assert details["charge"] == "not checked: the driver does not offer the battery feature"
    # it serves, strictly, every verb that comes with no optional feature, and its hello lists only profile
    served = [v.name for v in VERBS if not v.touches_robot or v.driver_verb.feature is None]
    optional = [v.name for v in VERBS if v.name not in served]
    assert details["every-verb"] == (f"{len(served)} verbs refuse a JSON array bad_request: {', '.join(served)}; "
                                     f"not served (optional here): {', '.join(optional)}")
    # the box stands 56 in straight ahead of the sonar at the reset pose (100 - 3 - (30 + 11)):
    # a long sweep runs, the 6 in procedures are out of range
    assert details["sense"].startswith("SenseResult")
    assert "56.0 in away" in details["out-of-range-target"]
    assert "56.0 in away" in details["grasp"]


@pytest.mark.slow
def test_the_templates_turn_makes_a_second_verb_busy(tmp_path: Path) -> None:
    """At 0.25 real s per robot s the busy check's 10-degree turn (2 robot s) lasts
    0.5 s, long enough for the releases sent every 0.1 s to meet it running: the
    template must refuse them busy, exercised, not skipped as too short. Only the busy
    check and those it builds on run: at this pace the turns check alone would take 10 s
    (40 robot s)."""
    with toy_template(tmp_path, 0.25) as (robot, endpoint):
        results = run_named_checks(robot, endpoint, BUSY_CHECKS, timeout_s=5.0,
                                   procedures=Procedures.from_profile(TEMPLATE_PROFILE))
    assert [name for name, result in results.items() if not result.passed] == []
    assert "refused busy during a" in results["busy"].detail


def test_the_template_checked_as_another_robot_fails_in_one_line(template: tuple[str, str],
                                                                 capsys: pytest.CaptureFixture[str]) -> None:
    robot, endpoint = template
    status, verdicts, details = run_check_detailed(endpoint, robot, capsys, 5.0, "--profile", str(ROVER))
    assert (status, verdicts) == (1, {"profile": "FAIL"})
    served = profile_stamp(load_profile(TEMPLATE_PROFILE)).sha256[:12]
    assert details["profile"].startswith(f"the driver serves robot profile hero2000 (sha256 {served}), not rover")


def _reordered(text: str) -> str:
    """The same profile with its [[grasping]] entries in reverse order and every
    integer range written as floats: neither may change the fingerprint."""
    head, *grasps = text.split("[[grasping]]")
    return (head + "".join("[[grasping]]" + g.rstrip("\n") + "\n\n" for g in reversed(grasps))).replace(
        "range_in = [6, 6]", "range_in = [6.0, 6.0]")


@pytest.mark.parametrize("source", [TEMPLATE_PROFILE, ROVER, "reordered"])
def test_the_template_fingerprints_a_profile_as_the_project_does(source: Path | str, tmp_path: Path) -> None:
    path = source if isinstance(source, Path) else tmp_path / "hero2000.toml"
    if source == "reordered":
        path.write_text(_reordered(TEMPLATE_PROFILE.read_text(encoding="utf-8")), encoding="utf-8")
        assert path.read_text(encoding="utf-8") != TEMPLATE_PROFILE.read_text(encoding="utf-8")
    ours = _template_knowledge().load(path)
    assert (ours.name, ours.sha256) == tuple(vars(profile_stamp(load_profile(path))).values())


def test_the_template_fingerprint_names_the_robot_not_the_learner(tmp_path: Path) -> None:
    """A feature's error is the learner's business (same robot); a procedure's time is
    the robot's (another robot)."""
    text = TEMPLATE_PROFILE.read_text(encoding="utf-8")
    learner_only, slower = tmp_path / "a.toml", tmp_path / "b.toml"
    learner_only.write_text(text.replace("error = 5.0", "error = 6.0"), encoding="utf-8")
    slower.write_text(text.replace("time_s = 45", "time_s = 46"), encoding="utf-8")
    knowledge = _template_knowledge()
    original = knowledge.load(TEMPLATE_PROFILE).sha256
    assert knowledge.load(learner_only).sha256 == original
    assert knowledge.load(slower).sha256 != original


def test_the_template_drops_its_token_before_its_queryables(tmp_path: Path) -> None:
    endpoint = free_endpoint()
    process = Template("down", endpoint, cwd=tmp_path)
    stopped: list[int] = []
    result = shutdown_order("down", [endpoint], lambda: stopped.append(process.stop()), timeout_s=10.0)
    assert result.passed, result.detail
    assert int(result.detail.split()[3]) >= 5  # "token went first: N of M noops answered": pinged while it stopped
    assert stopped == [0]


def test_a_bad_profile_is_one_line(tmp_path: Path) -> None:
    bad = tmp_path / "robot.toml"
    bad.write_text("[robot]\nbase_radius_in = 9.0\n", encoding="utf-8")
    done = subprocess.run([sys.executable, str(TEMPLATE / "driver.py"), "--profile", str(bad)], cwd=tmp_path,
                          env={"PATH": "/usr/bin:/bin"}, capture_output=True, text=True, timeout=30)
    assert done.returncode != 0
    assert done.stderr.strip().splitlines() == [f"--profile {bad}: not a knowledge profile (KeyError: 'sensing')"]


def test_the_vision_finds_the_toy_box_and_robot_where_they_are(template: tuple[str, str]) -> None:
    robot, endpoint = template
    with ZenohDriver(robot, connect=[endpoint]) as driver:
        assert driver.wait_ready(10.0)
        scene = look(driver.camera().result(10.0))
    # the toy's box: 6 in along x by 10 in along y, centred at (100, 60); the robot at (30, 60) facing +x
    (box,) = scene.regions
    assert box.centroid == pytest.approx((100.0, 60.0), abs=0.8)  # one pixel
    assert box.orientation_deg is not None and box.orientation_deg % 180 == pytest.approx(90.0, abs=3.0)
    assert (box.length_in, box.width_in) == (pytest.approx(10.0, abs=1.6), pytest.approx(6.0, abs=1.6))
    assert scene.robot is not None
    assert (scene.robot.x_in, scene.robot.y_in) == (pytest.approx(30.0, abs=0.8), pytest.approx(60.0, abs=0.8))


def test_hardware_stubs_answer_internal_naming_the_stub(tmp_path: Path) -> None:
    endpoint = free_endpoint()
    process = Template("stub", endpoint, "--backend", "hardware", cwd=tmp_path)
    try:
        with ZenohDriver("stub", connect=[endpoint]) as driver:
            with pytest.raises(DriverError) as refused:
                driver.camera().result(10.0)
    finally:
        process.stop()
    assert refused.value.code == INTERNAL
    assert "VENDOR: camera() is not implemented" in refused.value.message


def test_a_bad_robot_name_is_one_line(tmp_path: Path) -> None:
    done = subprocess.run([sys.executable, str(TEMPLATE / "driver.py"), "--robot", "r/1"], cwd=tmp_path,
                          env={"PATH": "/usr/bin:/bin"}, capture_output=True, text=True, timeout=30)
    assert done.returncode != 0
    assert done.stderr.strip().splitlines() == ["--robot 'r/1': one key chunk of letters, digits, '_', '-', '.'"]


def test_the_template_imports_only_zenoh_numpy_and_the_standard_library() -> None:
    siblings = {path.stem for path in TEMPLATE.glob("*.py")}
    allowed = set(sys.stdlib_module_names) | {"zenoh", "numpy", "__future__"} | siblings
    imported = set()
    for path in TEMPLATE.glob("*.py"):
        for node in ast.walk(ast.parse(path.read_text(encoding="utf-8"))):
            if isinstance(node, ast.Import):
                imported |= {alias.name.split(".")[0] for alias in node.names}
            elif isinstance(node, ast.ImportFrom):
                imported.add((node.module or "").split(".")[0])
    assert {"zenoh", "numpy", "robot", "messages"} <= imported  # the scan sees the imports
    assert imported - allowed == set()


def test_the_vendor_guides_zenoh_configs_are_accepted_by_zenoh() -> None:
    blocks = re.findall(r"```json5\n(.*?)```", GUIDE.read_text(encoding="utf-8"), re.S)
    assert len(blocks) >= 2  # the driver's and the client's
    for block in blocks:
        zenoh.Config.from_json5(block)  # raises on a key zenoh does not know
