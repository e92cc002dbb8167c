"""``[robot]`` is required only where it is used (docs/knowledge-format.md, "Who reads
what"): the learner's commands run the doc's example as written, with no robot body;
the commands that drive the planner or the simulator refuse it in one line.

The example is taken from the doc itself, so the doc and this test cannot drift apart.
"""

from __future__ import annotations

import json
import math
import re
from pathlib import Path

import pytest

from csl_cli.main import main

DOC = Path(__file__).resolve().parents[2] / "docs" / "knowledge-format.md"


def _doc_example(folder: Path) -> Path:
    """The first TOML block of docs/knowledge-format.md, written as the doc shows it."""
    block = re.search(r"```toml\n(.*?)```", DOC.read_text(encoding="utf-8"), re.S)
    assert block is not None, "docs/knowledge-format.md has no TOML example"
    assert "[robot]" not in block.group(1)  # the point: procedures alone
    path = folder / "section4.toml"
    path.write_text(block.group(1), encoding="utf-8")
    return path


def _training_inputs(folder: Path) -> tuple[Path, Path]:
    """A cup (round, 3 in wide, Front-Wrap) and a 9 x 5 in box (Top-Pinch), scanned at
    6 in from each side: H-Scan-0.3 is the example's one sensing procedure."""
    cup = [[1.5 * math.cos(k * math.pi / 8), 1.5 * math.sin(k * math.pi / 8)] for k in range(16)]
    objects = {"format": "csl-training-objects", "version": 2, "objects": [
        {"id": "cup", "grasp": "Front-Wrap", "grasp_position": [6, "*"], "round": True, "polygon": cup},
        {"id": "box", "grasp": "Top-Pinch", "grasp_position": [6, "*"],
         "polygon": [[-4.5, -2.5], [4.5, -2.5], [4.5, 2.5], [-4.5, 2.5]]}]}
    measurements = [{"object": oid, "procedure": "H-Scan-0.3", "position": [6, theta],
                     "values": {"Width": width, "Front-Hole?": 0}}
                    for theta in (0, 90, 180, 270)
                    for oid, width in (("cup", 3.0), ("box", 5.0 if theta in (0, 180) else 9.0))]
    objects_path, measurements_path = folder / "objects.json", folder / "measurements.json"
    objects_path.write_text(json.dumps(objects), encoding="utf-8")
    measurements_path.write_text(json.dumps({"format": "csl-measurements", "version": 1,
                                             "measurements": measurements}), encoding="utf-8")
    return objects_path, measurements_path


def test_the_docs_example_trains_and_grows_a_tree_without_a_robot(tmp_path: Path, capsys) -> None:  # noqa: ANN001
    knowledge = _doc_example(tmp_path)
    objects, measurements = _training_inputs(tmp_path)
    library = tmp_path / "library.json"
    assert main(["train", "--knowledge", str(knowledge), "--objects", str(objects),
                 "--measurements", str(measurements), "--out", str(library)]) == 0
    trained = capsys.readouterr().out
    # the box's four sides (its edge normals) and the scan's one distance
    assert "training orientations (deg): 0, 90, 180, 270" in trained
    assert "training distances (in):     6" in trained
    assert f"wrote 2 descriptions to {library}" in trained

    assert main(["tree", "--knowledge", str(knowledge), "--library", str(library)]) == 0
    # From the default pose (60 in, 0°): the move to (6,0) is 54 in x 2 s/in + 20 s overhead
    # = 128 s; trying Front-Wrap as a binary feature costs 60 + 30 s of side-effect penalty
    # = 90 s, cheaper than the 105 s scan, and it tells the two grasps apart by itself.
    assert capsys.readouterr().out.splitlines() == [
        "move-to-(6,0) (128s)",
        "Front-Wrap(6,*) (90s)",
        "  [0, 0]",
        "    Top-Pinch(6,*) (63s)",
        "  [1, 1]",
        "    Front-Wrap(6,*) (grasped)",
    ]


@pytest.mark.parametrize("argv", [
    ["run", "--knowledge", "{k}"],
    ["demo", "--knowledge", "{k}"],
    ["train", "--sim", "--knowledge", "{k}", "--out", "{dir}/sim.json"],
    ["driver", "sim", "--profile", "{k}"],
])
def test_what_drives_the_planner_or_simulator_refuses_it_in_one_line(tmp_path: Path, capsys,  # noqa: ANN001
                                                                     argv: list[str]) -> None:
    knowledge = _doc_example(tmp_path)
    assert main([a.format(k=knowledge, dir=tmp_path) for a in argv]) == 2
    assert capsys.readouterr().err.strip().splitlines() == [f"csl: error: {knowledge}: missing table [robot]"]
