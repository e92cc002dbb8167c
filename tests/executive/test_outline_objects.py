"""Training objects from the robot's own scans (``executive/outline_objects.py``): each
catalogue object outlined from a lidar survey round it, against the catalogue's truth;
and ``csl train --sim --perception onboard``."""

from __future__ import annotations

import dataclasses
import math
from pathlib import Path

import pytest

from csl_cli.main import main
from executive.outline_objects import outline_objects
from executive.sim_training import train_in_simulator
from executive.training_sources import catalogue_objects
from hero_driver.sim.catalogue import profile_and_catalogue
from learner.library.format import read_library_json
from learner.position import Position
from robot_profile import SCANNER_DEFAULTS, ScannerSpec, load_profile

BEAM_STEP_RAD = math.radians(1.0)  # the shipped lidar: 360 beams
STANDOFF_IN = 24.0  # the survey's (mapping/outline.py)
RANGE_FRAC = 0.005  # the simulator's default scan noise: sigma, a share of the range


def _footprints() -> dict[str, tuple[str, float, float]]:
    """Each training object's catalogue footprint: (shape, length, width); a circle's
    length and width are its diameter."""
    _, catalogue = profile_and_catalogue()
    out = {}
    for entry in catalogue.values():
        fp = entry.footprint
        if entry.set == "training":
            out[entry.id] = ((fp.shape, 2 * fp.radius_in, 2 * fp.radius_in) if fp.shape == "circle"
                             else (fp.shape, fp.length_in, fp.width_in))
    return out


def test_exact_scans_outline_every_training_object_as_the_catalogue_has_it() -> None:
    """Noise off, ranges are exact: each rectangle's outline is its catalogue footprint
    (to the 0.001 in a training object keeps) along the catalogue's axis (the object
    lies at yaw 0), each circle is round, and the teacher's labels come through
    unturned (the lying soda can's end-on grip at 0°)."""
    seen = outline_objects()
    truth = {o.object_id: o for o in catalogue_objects()}
    assert [o.object_id for o in seen.objects] == list(truth)  # Table 3's 14, in the catalogue's order
    for o in seen.objects:
        expected = truth[o.object_id]
        assert o.round == expected.round == (_footprints()[o.object_id][0] == "circle"), o.object_id
        assert _flat(o.polygon) == pytest.approx(_flat(expected.polygon), abs=0.001), o.object_id
        assert seen.axis_offsets_deg[o.object_id] == pytest.approx(0.0, abs=1e-4), o.object_id
        assert (o.grasp, o.grasp_position) == (expected.grasp, expected.grasp_position)
        assert o.appearance is None  # a planar scan has no pixels to measure
    # the camera's pixels call the lying 16 oz tumbler (4.6 x 3.6 in) round; the scans do not
    assert not next(o for o in seen.objects if o.object_id == "tumbler-16oz/lying").round
    soda = next(o for o in seen.objects if o.object_id == "soda-can-12oz/lying")
    assert soda.grasp_position == Position(6.0, 0.0)


def _flat(polygon: tuple[tuple[float, float], ...]) -> list[float]:
    return [c for corner in polygon for c in corner]


def _axis_bound_deg(length_in: float, width_in: float) -> float:
    """Five standard errors of the outline's axis for a box at yaw 0 surveyed from its
    four face normals, worked out by hand.

    Each face (length L) is square to one view, its nearest point ``d`` = 24 in less half
    the box's depth across it away, so 1° beams put n = L / (d · 1° in rad) returns on it,
    evenly along it, each off the face by the range noise σ = 0.5 % of at most 24 in.
    One angle fitted to points spread so has standard error σ / √(Σ n L² / 12) (a line
    fit's slope), summed over the four faces. The returns views see at a slant add to
    the fit, so the bound is on the safe side; five of them fail a right fit less than
    once in a million."""
    sigma = RANGE_FRAC * STANDOFF_IN
    spread = 0.0
    for face, depth in ((length_in, width_in), (width_in, length_in)):
        d = STANDOFF_IN - depth / 2
        n = face / (d * BEAM_STEP_RAD)
        spread += 2 * n * face ** 2 / 12  # two faces of each length
    return 5 * math.degrees(sigma / math.sqrt(spread))


@pytest.mark.parametrize("seed", [0, 1, 2])
def test_noisy_outlines_keep_the_catalogue_axis_within_the_range_noise(seed: int) -> None:
    seen = outline_objects(noise=True, seed=seed)
    for o in seen.objects:
        shape, length, width = _footprints()[o.object_id]
        assert o.round == (shape == "circle"), o.object_id
        offset = seen.axis_offsets_deg[o.object_id]
        if o.round:
            assert offset == 0.0 and o.polygon == ()  # a round footprint's axis is world +x by convention
            continue
        assert abs(offset) <= _axis_bound_deg(length, width), (o.object_id, offset)


def test_the_hand_worked_bound_for_the_lying_soda_can() -> None:
    """4.8 x 2.6 in: long faces at 22.7 in get 12.1 returns, short ones at 21.6 in 6.9;
    Σ n L²/12 = 2 (12.1 · 23.04 + 6.9 · 6.76) / 12 = 54.3 in², σ = 0.12 in: 0.93°, times 5."""
    assert _axis_bound_deg(4.8, 2.6) == pytest.approx(5 * 0.93, abs=0.05)


def test_a_wide_beamed_scanner_is_refused_before_any_survey(tmp_path, capsys) -> None:  # noqa: ANN001
    """HERO's sonar swept in place answers each 30° beam with the nearest echo anywhere
    across it (12 in wide at 24 in): its returns would outline the beams, not the object."""
    hero = load_profile()
    with pytest.raises(ValueError, match=r"^onboard perception: .*hero2000\.toml: \[scanner\]: the sonar's beams are "
                                         r"30° wide, .* outlines need a thin-beamed scanner \(a lidar\)$"):
        outline_objects(profile=dataclasses.replace(hero, scanner=_scanner("sonar")))
    sonar = tmp_path / "sonar.toml"
    sonar.write_text(Path(hero.source).read_text(encoding="utf-8").replace('model = "lidar"', 'model = "sonar"'),
                     encoding="utf-8")
    assert main(["train", "--sim", "--perception", "onboard", "--knowledge", str(sonar),
                 "--out", str(tmp_path / "lib.json")]) != 0
    err = capsys.readouterr().err.strip()
    assert err.count("\n") == 0 and f"{sonar}: [scanner]: the sonar's beams are 30° wide" in err


def test_an_outline_the_fit_refuses_is_one_line_naming_the_object() -> None:
    """A lidar with 24 thin beams, 15° apart, puts 4 returns on the 3.3 in cup from four
    views (one a view: the beams either side of the one at it pass 6.4 in off its centre),
    fewer than the 10 an outline needs."""
    coarse = dataclasses.replace(_scanner("lidar"), beams=24)
    with pytest.raises(ValueError) as raised:
        outline_objects(profile=dataclasses.replace(load_profile(), scanner=coarse))
    assert str(raised.value) == ("onboard perception: 'cup-8oz/upright': outline: 4 returns within 12.5 in of "
                                 "(200.0, 200.0), too few to outline (at least 10) (the scanner: lidar, 24 beams "
                                 "15° apart)")


def _scanner(model: str) -> ScannerSpec:
    return ScannerSpec(model=model, **SCANNER_DEFAULTS[model])  # type: ignore[arg-type]


def test_an_unknown_perception_is_refused_by_name() -> None:
    profile = load_profile()
    with pytest.raises(ValueError, match="perception must be one of camera, onboard, got 'sonar'"):
        train_in_simulator(profile.knowledge(), profile, perception="sonar")


def test_csl_train_sim_onboard_writes_a_library_from_the_outlines(tmp_path, capsys) -> None:  # noqa: ANN001
    """The exact outlines are the catalogue's rectangles squared to the room: their faces'
    normals are 0, 90, 180 and 270° exactly (the camera's pixel polygons tilt them)."""
    out = tmp_path / "lib.json"
    assert main(["train", "--sim", "--perception", "onboard", "--out", str(out)]) == 0
    text = capsys.readouterr().out
    assert "training orientations (deg): 0, 90, 180, 270\n" in text
    checked = next(line for line in text.splitlines() if line.startswith("against the simulator's exact values"))
    assert checked.split(": ")[1].startswith("0 of ")
    library = read_library_json(out)
    assert len(library) == 14 and all(d.appearance is None for d in library)


def test_perception_goes_with_sim(tmp_path, capsys) -> None:  # noqa: ANN001
    assert main(["train", "--perception", "onboard", "--objects", "o.json", "--measurements", "m.json",
                 "--out", str(tmp_path / "lib.json")]) != 0
    err = capsys.readouterr().err
    assert "--perception chooses how the simulator sees the training objects: it goes with --sim" in err
