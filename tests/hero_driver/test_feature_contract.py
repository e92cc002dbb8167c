"""docs/driver-protocol.md's "Sensing features" held to the profiles and to the
simulator: every feature a shipped profile lists is defined there with the profile's
unit and span, every feature has a worked example (a hole both ways), and each worked
example's value is what the simulated HERO returns from the stated position with noise
off, exactly: the page defines the noiseless value, worked out by hand from the
geometry in the row itself."""

from __future__ import annotations

import math
import re
from pathlib import Path

import pytest

from hero_driver.interface import Pose
from hero_driver.sim.catalogue import profile_and_catalogue
from hero_driver.sim.noise import NoiseConfig
from hero_driver.sim.world import SimWorld
from hero_driver.sim.worldfile import one_object_world
from robot_profile import DEFAULT_PROFILE, load_profile

PAGE = Path(__file__).resolve().parents[2] / "docs" / "driver-protocol.md"
PROFILES = sorted(DEFAULT_PROFILE.parent.glob("*.toml"))
CENTRE = (200.0, 200.0)  # where one_object_world puts its object, as the examples say


def section(text: str, title: str) -> str:
    """The text of the ``## title...`` section, up to the next ``## `` heading."""
    start = text.index(f"\n## {title}")
    end = text.find("\n## ", start + 1)
    return text[start:end if end >= 0 else None]


def table(text: str, header: str) -> list[dict[str, str]]:
    """The rows of the Markdown table whose header row starts with ``header``, as
    dicts keyed by the header's cells."""
    lines = text.splitlines()
    first = next(i for i, line in enumerate(lines) if line.startswith(header))
    names = [cell.strip() for cell in lines[first].strip("|").split("|")]
    rows = []
    for line in lines[first + 2:]:
        if not line.startswith("|"):
            break
        rows.append(dict(zip(names, (cell.strip() for cell in line.strip().strip("|").split("|")), strict=True)))
    return rows


def code(cell: str) -> str:
    """The first ``code`` span of a cell."""
    found = re.search(r"`([^`]+)`", cell)
    assert found, cell
    return found.group(1)


SECTION = section(PAGE.read_text(encoding="utf-8"), "Sensing features")
DEFINITIONS = {code(row["feature"]): row for row in table(SECTION, "| feature | procedure |")}
EXAMPLES = table(SECTION, "| procedure | feature |")


def test_the_tables_were_found() -> None:
    assert len(DEFINITIONS) == 10 and len(EXAMPLES) >= 10


@pytest.mark.parametrize("path", PROFILES, ids=lambda path: path.stem)
def test_every_feature_of_a_shipped_profile_is_defined_with_its_unit_and_span(path: Path) -> None:
    for procedure in load_profile(path).sensing:
        for feature in procedure.features:
            row = DEFINITIONS.get(feature.name)
            assert row is not None, f"{path.name}: {feature.name} is not defined in {PAGE.name}"
            assert code(row["procedure"]) == procedure.name, feature.name
            assert code(row["unit"]) == feature.unit, feature.name
            if feature.binary:
                assert row["span"] == "0 or 1", feature.name
            else:
                low, high = (float(end) for end in row["span"].split("-"))
                assert (low, high) == feature.span, feature.name


def test_the_page_defines_exactly_the_hero_2000s_features() -> None:
    """A feature dropped from the profile leaves no stale definition behind (the Rover's
    are a subset, checked above)."""
    hero = {f.name for p in load_profile().sensing for f in p.features}
    assert set(DEFINITIONS) == hero


def test_every_feature_has_a_worked_example_and_a_hole_both_answers() -> None:
    examples: dict[str, set[float]] = {}
    for row in EXAMPLES:
        examples.setdefault(code(row["feature"]), set()).add(float(row["value"]))
    assert set(examples) == set(DEFINITIONS)
    for hole in ("Front-Hole?", "Top-Hole?"):
        assert examples[hole] == {0.0, 1.0}


def numbers(cell: str) -> list[float]:
    return [float(n) for n in re.findall(r"-?\d+(?:\.\d+)?", cell)]


@pytest.mark.parametrize("row", EXAMPLES, ids=lambda row: f"{code(row['feature'])}@{row['sonar point']}")
def test_a_worked_example_is_what_the_simulator_returns_without_noise(row: dict[str, str]) -> None:
    profile, catalogue = profile_and_catalogue(load_profile())
    sim = SimWorld(one_object_world(code(row["object"]), catalogue), 0, profile=profile, noise=NoiseConfig.off())
    target = sim.physics.objects[0]
    assert (target.x_in, target.y_in, target.yaw_deg) == (*CENTRE, 0.0)
    (sonar_x, sonar_y), (heading,) = numbers(row["sonar point"]), numbers(row["heading"])
    offset = profile.robot.geometry.sensor_offset_in
    h = math.radians(heading)
    sim.pose = Pose(sonar_x - offset * math.cos(h), sonar_y - offset * math.sin(h), heading)
    assert sim.sonar_point() == pytest.approx((sonar_x, sonar_y))
    result = sim.sense(code(row["procedure"]))
    assert result.distance_in == pytest.approx(float(row["d"]), abs=1e-6)
    assert result.values[code(row["feature"])] == pytest.approx(float(row["value"]), abs=1e-9)
