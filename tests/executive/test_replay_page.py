"""``csl view``: the replay page's data read from a recorded lab episode and from an out
folder, worked by hand on a short made-up log, the page self-contained, bad input one
line, and the page replayed in a real headless browser (Debian's chromium)."""

from __future__ import annotations

import json
import re
import shutil
import struct
import zlib
from pathlib import Path

import pytest

import hero_driver.worlds
from csl_cli.main import main
from recording.replay_page import ACTIVE, UNKNOWN, load_replay, page, page_data, replay
from tests.executive.test_recording import record_episode

CHROMIUM = Path("/usr/bin/chromium")
CHROMEDRIVER = Path("/usr/bin/chromedriver")


@pytest.fixture(scope="module")
def recorded(tmp_path_factory: pytest.TempPathFactory) -> dict[str, object]:
    """A lab episode recorded to ``run/e.mcap``, and its log as an out folder ``out/``."""
    folder = tmp_path_factory.mktemp("replay")
    (folder / "run").mkdir()
    result, log, recording = record_episode(folder, mcap=folder / "run" / "e.mcap")
    recording.close()
    (folder / "out").mkdir()
    (folder / "out" / "episode.jsonl").write_text("".join(json.dumps(e) + "\n" for e in log.events),
                                                  encoding="utf-8")
    return {"folder": folder, "result": result, "log": log.events}


def test_a_recording_gives_every_tick_with_the_trees_statuses(recorded) -> None:  # noqa: ANN001
    result = recorded["result"]
    seen = load_replay(recorded["folder"] / "run" / "e.mcap")
    assert seen.tree_source == "recording" and seen.ticks == result.ticks
    assert len(seen.statuses) == len(seen.feedback) == len(seen.poses) == result.ticks + 1  # tick 0: before
    assert set(seen.statuses[0]) == {"INVALID"}  # nothing ticked yet
    assert [n["id"] for n in seen.nodes] == list(range(len(seen.nodes)))
    assert all(len(row) == len(seen.nodes) for row in seen.statuses)
    # the first tick locates the 7 objects; the root ends as the episode did
    assert (seen.status(0, "LocateObjects"), seen.status(1, "LocateObjects")) == ("INVALID", "SUCCESS")
    locate = next(n["id"] for n in seen.nodes if n["name"] == "LocateObjects")
    assert seen.feedback[1][locate] == "7 objects"
    assert seen.statuses[result.ticks][0] == result.status == "SUCCESS"
    assert seen.floor is not None and seen.floor.columns * seen.floor.rows == len(seen.floor.pixels)


def test_the_robot_stands_where_each_ticks_last_move_stopped(recorded) -> None:  # noqa: ANN001
    seen = load_replay(recorded["folder"] / "run" / "e.mcap")
    moves = [e for e in recorded["log"] if e["event"] == "move"]
    assert len(seen.moves) == len(moves) > 1
    lab = json.loads((Path(hero_driver.worlds.__file__).parent / "lab.json").read_text(encoding="utf-8"))
    start = lab["robot"]  # before the first tick: where the lab puts the robot (the first /robot/pose)
    assert seen.poses[0] == pytest.approx((start["x_in"], start["y_in"], start["heading_deg"]))
    last_of_tick = {e["tick"]: e["pose"] for e in moves}
    for tick in range(1, seen.ticks + 1):
        expected = last_of_tick.get(tick, seen.poses[tick - 1])
        assert seen.poses[tick] == pytest.approx(tuple(expected))


def test_each_objects_outcome_is_the_executives(recorded) -> None:  # noqa: ANN001
    seen = load_replay(recorded["folder"] / "run" / "e.mcap")
    records = recorded["result"].objects
    assert [o["index"] for o in seen.objects] == [r.index for r in records]
    assert [(o["outcome"], o["grasp"]) for o in seen.objects] == [(r.outcome, r.grasp) for r in records]
    starts = {e["object"]: e["tick"] for e in recorded["log"] if e["event"] == "object"}
    for o in seen.objects:
        assert o["start_tick"] == starts[o["index"]] <= o["end_tick"]
        assert [s["tick"] for s in o["steps"]] == sorted(s["tick"] for s in o["steps"])


def test_an_out_folder_rebuilds_the_tree_with_statuses_unknown(recorded) -> None:  # noqa: ANN001
    out = recorded["folder"] / "out"
    from_log = load_replay(out)
    from_recording = load_replay(recorded["folder"] / "run" / "e.mcap")
    assert from_log.tree_source == "rebuilt"
    assert [n["name"] for n in from_log.nodes] == [n["name"] for n in from_recording.nodes]  # the same tree
    assert (from_log.poses[1:], from_log.objects) == (from_recording.poses[1:], from_recording.objects)
    assert (from_log.floor, from_log.poses[0]) == (None, None)  # the log has neither the image nor the start
    located = next(e for e in recorded["log"] if e["event"] == "located")
    assert from_log.status(located["tick"], "LocateObjects") == ACTIVE  # an event names it at that tick
    assert from_log.status(0, "LocateObjects") == "INVALID"
    assert from_log.statuses[from_log.ticks][0] == "SUCCESS"  # the episode_end event's status
    assert UNKNOWN in from_log.statuses[1]


def _made_up_log() -> list[dict[str, object]]:
    """Four ticks, three objects: 0 grasped at tick 2 (a grasp tried as a test), 1 left
    at tick 3, 2 begun at tick 4 and never grasped before the episode ended."""
    return [
        {"tick": 1, "event": "located", "behaviour": "LocateObjects",
         "regions": [{"centroid": [10.0, 20.0], "pixels": 4}, {"centroid": [30.0, 40.0], "pixels": 9},
                     {"centroid": [50.0, 60.0], "pixels": 16}]},
        {"tick": 1, "event": "object", "object": 0, "behaviour": "RememberAppearance", "centroid": [10.0, 20.0],
         "pixels": 4},
        {"tick": 1, "event": "choose", "object": 0, "behaviour": "BestTest", "how": "best", "test": "Front-Wrap(6,*)",
         "gain": 1.0},
        {"tick": 2, "event": "move", "object": 0, "behaviour": "MoveTo test", "pose": [4.0, 20.0, 0.0],
         "path": [[0.0, 0.0, 90.0], [0.0, 20.0, 0.0]], "collided": False},
        {"tick": 2, "event": "move", "object": 0, "behaviour": "MoveTo test", "pose": [5.0, 20.0, 0.0],
         "path": [[4.0, 20.0, 0.0], [5.0, 20.0, 0.0]], "collided": False},
        {"tick": 2, "event": "grasp", "object": 0, "behaviour": "ApplyTest", "grasp": "Front-Wrap",
         "as_feature": True, "success": True},
        {"tick": 3, "event": "object", "object": 1, "behaviour": "RememberAppearance", "centroid": [30.0, 40.0]},
        {"tick": 3, "event": "leave", "object": 1, "behaviour": "Grasp", "grasp": "No-Grab"},
        {"tick": 4, "event": "object", "object": 2, "behaviour": "RememberAppearance", "centroid": [50.0, 60.0]},
        {"tick": 4, "event": "move", "object": 2, "behaviour": "MoveTo grasp", "pose": [44.0, 60.0, 180.0],
         "path": [[5.0, 20.0, 0.0], [44.0, 60.0, 180.0]], "collided": True},
        {"tick": 4, "event": "grasp", "object": 2, "behaviour": "Grasp", "grasp": "Top-Pinch", "as_feature": False,
         "success": False},
        {"tick": 4, "event": "episode_end", "status": "FAILURE", "ticks": 4},
    ]


def test_a_short_log_worked_by_hand() -> None:
    seen = replay(_made_up_log(), None, "made-up")
    assert seen.ticks == 4
    # where the base started is not in the log (a move's path leaves it out); each tick ends
    # where its last move stopped, or where the tick before ended
    assert seen.poses == (None, None, (5.0, 20.0, 0.0), (5.0, 20.0, 0.0), (44.0, 60.0, 180.0))
    assert replay(_made_up_log(), None, "made-up", start=(1.0, 2.0, 90.0)).poses[:3] == (
        (1.0, 2.0, 90.0), (1.0, 2.0, 90.0), (5.0, 20.0, 0.0))
    assert [(o["index"], o["start_tick"], o["end_tick"], o["outcome"], o["grasp"]) for o in seen.objects] == [
        (0, 1, 2, "grasped", "Front-Wrap"), (1, 3, 3, "left", "No-Grab"), (2, 4, 4, "failed", None)]
    assert [o["centroid"] for o in seen.objects] == [[10.0, 20.0], [30.0, 40.0], [50.0, 60.0]]
    assert [s["text"] for s in seen.objects[0]["steps"]] == ["test Front-Wrap(6,*) (best, gain 1.0)",
                                                             "tried as a test: Front-Wrap succeeded"]
    assert [m["collided"] for m in seen.moves] == [False, False, True]
    assert seen.status(2, "MoveTo test") == ACTIVE and seen.status(3, "MoveTo test") == UNKNOWN
    assert seen.status(4, "MoveTo grasp") == ACTIVE and seen.statuses[4][0] == "FAILURE"


def test_an_object_still_under_way_when_the_log_stops_has_no_outcome() -> None:
    log = [e for e in _made_up_log() if e["event"] != "episode_end"]  # the run died during object 2
    assert [o["outcome"] for o in replay(log, None, "cut").objects] == ["grasped", "left", None]


def test_the_page_is_self_contained(recorded, tmp_path: Path) -> None:  # noqa: ANN001
    out = shutil.copytree(recorded["folder"] / "out", tmp_path / "out")
    (out / "tree-0.png").write_bytes(_png(2, 2, 0))  # a decision-tree picture, as the demo draws one
    seen = load_replay(out)
    text = page(seen)
    assert not re.search(r"https?://", text, re.IGNORECASE)
    assert not re.search(r"""(src|href)\s*=\s*["'](?!data:|#)""", text)  # nothing loaded from anywhere
    data = re.search(r'<script type="application/json" id="data">(.*?)</script>', text, re.S)
    assert data is not None and json.loads(data.group(1)) == json.loads(json.dumps(page_data(seen)))
    assert seen.images[0].startswith("data:image/png;base64,")


def test_csl_view_writes_the_page_beside_the_run(recorded, capsys: pytest.CaptureFixture[str]) -> None:  # noqa: ANN001
    run = recorded["folder"] / "run" / "e.mcap"
    assert main(["view", str(run)]) == 0
    written = recorded["folder"] / "run" / "replay.html"
    assert capsys.readouterr().out.startswith(f"replay page: {written} ")
    assert "csl.BehaviourTreeNodes" not in written.read_text(encoding="utf-8")[:200]  # a page, not the data dump
    assert "<!DOCTYPE html>" in written.read_text(encoding="utf-8")


@pytest.mark.parametrize("make, expected", [
    (lambda d: d / "missing.mcap", "missing.mcap: no such file or folder"),
    (lambda d: _write(d / "empty.mcap", b""), "empty.mcap: no episode in it"),
    (lambda d: _write(d / "text.mcap", b"hello\n"), "text.mcap:1: not a JSON event"),
    (lambda d: _write(d / "cut.mcap", b"\x89MCAP0\r\n" + b"\x01" * 40), "cut.mcap: not a readable MCAP recording"),
    (lambda d: (d / "folder").mkdir() or d / "folder", "folder: not an out folder of csl run/demo"),
])
def test_bad_input_is_one_line_naming_the_file(make, expected, tmp_path: Path,  # noqa: ANN001
                                                capsys: pytest.CaptureFixture[str]) -> None:
    path = make(tmp_path)
    assert main(["view", str(path)]) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and expected in err and str(tmp_path) in err, err
    assert not (tmp_path / "replay.html").exists()


def test_a_malformed_move_or_tree_message_is_named() -> None:
    log = _made_up_log()
    log[3] = {**log[3], "pose": "here"}
    with pytest.raises(ValueError, match="made-up: the move at tick 2 has no 'pose'"):
        replay(log, None, "made-up")
    with pytest.raises(ValueError, match=r"made-up: event 2 is not an episode event"):
        replay([_made_up_log()[0], [1, 2]], None, "made-up")
    with pytest.raises(ValueError, match=r"made-up: message 1 on /behaviour_tree/nodes is not a tick of nodes"):
        replay(_made_up_log(), [{"tick": 1, "nodes": [{"id": 0}]}], "made-up")


def _write(path: Path, data: bytes) -> Path:
    path.write_bytes(data)
    return path


def _png(width: int, height: int, grey: int) -> bytes:
    def chunk(kind: bytes, body: bytes) -> bytes:
        return struct.pack(">I", len(body)) + kind + body + struct.pack(">I", zlib.crc32(kind + body))

    rows = b"".join(b"\0" + bytes([grey]) * width for _ in range(height))
    return (b"\x89PNG\r\n\x1a\n" + chunk(b"IHDR", struct.pack(">IIBBBBB", width, height, 8, 0, 0, 0, 0))
            + chunk(b"IDAT", zlib.compress(rows)) + chunk(b"IEND", b""))


# ---- the page in a real browser

@pytest.fixture
def browser(tmp_path: Path):  # noqa: ANN201
    """Debian's chromium, headless, driven by selenium through Debian's chromedriver;
    a fresh profile, no network features, a 1366 x 768 viewport."""
    if not CHROMIUM.exists() or not CHROMEDRIVER.exists():
        pytest.skip("no Debian chromium at /usr/bin/chromium: apt-get install chromium chromium-driver")
    webdriver = pytest.importorskip("selenium.webdriver")
    from selenium.webdriver.chrome.service import Service

    options = webdriver.ChromeOptions()
    options.binary_location = str(CHROMIUM)
    for flag in ("--headless", "--no-sandbox", "--disable-gpu", "--disable-quic", "--no-first-run",
                 "--disable-background-networking", "--disable-component-update", "--disable-sync",
                 "--window-size=1366,768", f"--user-data-dir={tmp_path / 'chromium-profile'}"):
        options.add_argument(flag)
    driver = webdriver.Chrome(service=Service(str(CHROMEDRIVER)), options=options)
    try:
        driver.execute_cdp_cmd("Emulation.setDeviceMetricsOverride",
                               {"width": 1366, "height": 768, "deviceScaleFactor": 1, "mobile": False})
        yield driver
    finally:
        driver.quit()


@pytest.mark.slow
def test_the_page_replays_in_a_headless_browser(recorded, browser, tmp_path: Path) -> None:  # noqa: ANN001
    from selenium.webdriver.common.by import By
    from selenium.webdriver.common.keys import Keys

    seen = load_replay(recorded["folder"] / "run" / "e.mcap")
    html = tmp_path / "replay.html"
    html.write_text(page(seen), encoding="utf-8")
    browser.get(html.as_uri())

    def statuses() -> list[str]:
        return [row.get_attribute("class") for row in browser.find_elements(By.CSS_SELECTOR, "#tree .node")]

    robot = browser.find_element(By.ID, "robot")
    assert browser.find_element(By.ID, "ticklabel").text == f"tick 0 / {seen.ticks}"
    at_start, robot_at_start = statuses(), (robot.get_attribute("transform"), robot.rect)
    assert len(at_start) == len(seen.nodes) and all("st-INVALID" in c for c in at_start)

    slider = browser.find_element(By.ID, "tick")
    slider.click()
    slider.send_keys(Keys.END)  # the keyboard moves a range input to its last value, as a user would
    assert browser.find_element(By.TAG_NAME, "body").get_attribute("data-tick") == str(seen.ticks)
    later = statuses()
    assert later != at_start and "st-SUCCESS" in later[0]  # the root, coloured as the episode ended
    assert later == [f"node st-{s}" + (" changed" if s != b else "")
                     for s, b in zip(seen.statuses[-1], seen.statuses[-2])]
    assert (robot.get_attribute("transform"), robot.rect) != robot_at_start  # the marker moved
    x, y, heading = seen.poses[-1]
    numbers = [float(n) for n in re.findall(r"-?[\d.]+(?:e-?\d+)?", robot.get_attribute("transform"))]
    assert numbers == pytest.approx([x, -y, -heading])
    grasped = browser.find_elements(By.CSS_SELECTOR, "#map .object-marker.grasped")
    assert len(grasped) == sum(o["outcome"] == "grasped" for o in seen.objects) > 0

    browser.find_element(By.ID, "back").click()
    assert browser.find_element(By.TAG_NAME, "body").get_attribute("data-tick") == str(seen.ticks - 1)
    shot = tmp_path / "replay.png"
    assert browser.save_screenshot(str(shot))
    width, height, variance = _png_size_and_variance(shot)
    assert (width, height) == (1366, 768) and variance > 0


def _png_size_and_variance(path: Path) -> tuple[int, int, float]:
    """A screenshot's size and the variance of its grey levels (0 for a blank page)."""
    import numpy as np
    from PIL import Image

    with Image.open(path) as image:
        assert image.format == "PNG"
        return image.width, image.height, float(np.asarray(image.convert("L"), dtype=float).var())


def test_csl_view_help_imports_no_numpy() -> None:
    from tests.executive.test_cli_startup import _imported_by

    assert _imported_by(["view", "--help"], ("numpy", "mcap", "reporting")) == []
