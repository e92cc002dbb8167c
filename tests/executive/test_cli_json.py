"""``--json``: one JSON document on standard output for a script, in place of the tables
(``demo``, ``run``, ``library show``, ``library stats``; ``driver check`` is tested with
the driver process in test_cli_driver_inspect.py)."""

from __future__ import annotations

import json
from collections import Counter
from pathlib import Path

import pytest

from executive import defaults
from csl_cli.main import main
from learner.library.format import descriptions_from_json, descriptions_to_json, read_library_json

LAB_OBJECTS = ["closed-box-2x2x2/upright", "tumbler-20oz/upside-down", "soda-bottle-16oz/upright",
               "magazine-box-9x4x7/upright", "soda-bottle-16oz/lying", "tumbler-20oz/upright",
               "closed-box-10x10x10/upright"]


@pytest.mark.slow
def test_demo_json_is_the_table_as_one_document(tmp_path: Path, capsys) -> None:  # noqa: ANN001
    assert main(["demo", "--no-plots", "--out", str(tmp_path / "table")]) == 0
    table = capsys.readouterr().out.splitlines()
    assert main(["demo", "--json", "--out", str(tmp_path / "json")]) == 0
    doc = json.loads(capsys.readouterr().out)  # the whole of stdout: nothing else printed there
    objects = doc["objects"]
    assert [o["object"] for o in objects] == LAB_OBJECTS and [o["index"] for o in objects] == list(range(7))
    for o in objects:
        assert o["robot_s"] == o["moving_s"] + o["sensing_s"] + o["grasping_s"]
        # the same seed, the same episode: the table's row says what the document says
        row = next(line.split() for line in table if line.startswith(f"{o['index']}  "))
        assert row[1:6] == [o["object"] + ("*" if o["ended_as"] else ""), o["grasp"], o["outcome"], "yes" if o["correct"] else "NO",
                            f"{o['robot_s'] / 60:.1f}"]
        assert row[7] == str(o["tests"])
    assert objects[6]["outcome"] == "left" and objects[6]["grasp"] == "No-Grab"
    assert sum(objects[0]["recoveries"].values()) >= 1 and all(n >= 1 for n in objects[0]["recoveries"].values())
    summary = doc["summary"]
    assert summary["objects"] == summary["judged"] == 7 and summary["correct"] == sum(o["correct"] for o in objects)
    assert abs(summary["mean_robot_s"] - sum(o["robot_s"] for o in objects) / 7) < 1e-9
    out = tmp_path / "json"
    assert doc["plots"] == [str(out / "map.png"), *(str(out / f"tree-{i}.png") for i in range(7)),
                            str(out / "behaviour-tree.png")]
    assert all(Path(p).is_file() for p in doc["plots"])
    assert doc["library"] == str(out / "library.sqlite") and doc["episode"]["log"] == str(out / "episode.jsonl")
    assert doc["library_created"] is False  # the demo's own scratch library, made afresh every time
    assert doc["exit_status"] == 0 and doc["why"] == "all 7 objects were handled"


def test_run_json_carries_the_exit_status_and_why(tmp_path: Path, capsys) -> None:  # noqa: ANN001
    # one recognition step reaches a grasp only where the camera's appearance leaves one:
    # the upright soda bottle and the 10 in closed box; five fail (test_cli_executive)
    argv = ["run", "--json", "--max-steps", "1", "--no-plots", "--out", str(tmp_path),
            "--library", str(tmp_path / "lib.sqlite")]
    assert main(argv) == 1
    doc = json.loads(capsys.readouterr().out)
    assert doc["exit_status"] == 1 and doc["why"] == "5 of 7 objects were not handled"
    assert [o["object"] for o in doc["objects"] if o["correct"]] == ["soda-bottle-16oz/upright",
                                                                    "closed-box-10x10x10/upright"]
    assert doc["summary"]["correct"] == 2 and doc["plots"] == []
    assert doc["library"] == str(tmp_path / "lib.sqlite") and doc["library_created"] is True


def test_library_show_and_stats_json(tmp_path: Path, capsys) -> None:  # noqa: ANN001
    db = tmp_path / "lib.sqlite"
    assert main(["library", "--db", str(db), "import", str(defaults.EXAMPLE_LIBRARY)]) == 0
    capsys.readouterr()
    example = read_library_json(defaults.EXAMPLE_LIBRARY)
    assert main(["library", "--db", str(db), "show", "--json"]) == 0
    shown = json.loads(capsys.readouterr().out)
    assert shown == descriptions_to_json(example)  # the library format itself: it reads back
    assert descriptions_to_json(descriptions_from_json(shown)) == shown
    assert main(["library", "--db", str(db), "stats", "--json"]) == 0
    stats = json.loads(capsys.readouterr().out)
    assert stats["descriptions"] == 14
    assert stats["by_grasp"] == dict(sorted(Counter(d.grasp for d in example).items()))
    assert stats["feature_values"] == sum(len(d.observations) for d in example) == sum(stats["by_feature"].values())
    assert stats["by_grasp"]["No-Grab"] == 2  # the closed box and the open box facing down
