"""What the fuzzers found, each reduced to its smallest example.

Each test states the documented behaviour and is marked ``xfail(strict=True)`` while
the fix waits in a file this work does not own: the reason says which file and how.
When the fix lands the test passes, the strict mark turns that into a failure, and
the mark (and its entry in ``surfaces.KNOWN``) is removed.
"""

from __future__ import annotations

import copy
import json
import math
import os
import threading
from pathlib import Path
from types import SimpleNamespace

import pytest

from tests.fuzz.surfaces import LIBRARY, WORLD, Workbench, _WORLD_DATA, _catalogue, run_cli

DEEP = b"[" * 30_000 + b"]" * 30_000
"""Deeper than Python's recursion limit in ``json.loads``."""


@pytest.mark.xfail(strict=True, reason="hero_driver/sim/worldfile.py load_world: json.loads raises RecursionError; "
                                       "catch it with JSONDecodeError")
def test_world_file_nested_too_deep(tmp_path: Path) -> None:
    from hero_driver.sim.worldfile import load_world

    path = tmp_path / "deep.json"
    path.write_bytes(DEEP)
    with pytest.raises(ValueError, match="deep.json"):
        load_world(path, _catalogue())


@pytest.mark.xfail(strict=True, reason="hero_driver/sim/worldfile.py parse_world: the robot's x_in/y_in are only "
                                       "checked >= 0; check them finite and inside the room")
@pytest.mark.parametrize("x", [math.nan, math.inf, 1e308])
def test_world_robot_outside_the_room(x: float) -> None:
    from hero_driver.sim.worldfile import parse_world

    world = copy.deepcopy(_WORLD_DATA)
    world["robot"]["x_in"] = x
    with pytest.raises(ValueError, match="robot"):
        parse_world(world, str(WORLD), _catalogue())


@pytest.mark.xfail(strict=True, reason="learner/library.py read_library_json: json.loads raises RecursionError; "
                                       "catch it with JSONDecodeError")
def test_library_file_nested_too_deep(tmp_path: Path) -> None:
    bench = Workbench(tmp_path)
    path = bench.file("deep.json", DEEP)
    code, _, err = run_cli(["library", "import", "--db", str(tmp_path / "l.sqlite"), str(path)], bench)
    assert code == 2 and err.count("\n") == 1


@pytest.mark.xfail(strict=True, reason="executive/episode_log.py read_log: json.loads raises RecursionError; "
                                       "catch it with JSONDecodeError")
def test_log_line_nested_too_deep(tmp_path: Path) -> None:
    bench = Workbench(tmp_path)
    path = bench.file("episode.jsonl", DEEP)
    code, _, err = run_cli(["log", str(path)], bench)
    assert code == 2 and err.startswith("csl: error: ") and err.count("\n") == 1


@pytest.mark.xfail(strict=True, reason="executive/commands/log.py run_log: formats e['tick'] with :>4 and "
                                       "e['event'] with :<18, and puts e['object'] in a set; check each event's "
                                       "tick and object are integers (or absent) and event a string, else "
                                       "ValueError naming the line")
@pytest.mark.parametrize("line", [{"event": "test", "tick": None}, {"event": {}, "tick": 1},
                                  {"event": "test", "object": []}])
def test_log_fields_of_another_type(tmp_path: Path, line: dict[str, object]) -> None:
    bench = Workbench(tmp_path)
    path = bench.file("episode.jsonl", json.dumps(line).encode())
    code, _, _ = run_cli(["log", str(path)], bench)
    assert code in (0, 2)


@pytest.mark.xfail(strict=True, reason="executive/episode_log.py read_log: a FIFO (or /dev/zero) is read to its "
                                       "end, forever; open only regular files, non-blocking, as WorldShelf does")
def test_log_of_a_fifo_does_not_hang(tmp_path: Path) -> None:
    from executive.episode_log import read_log

    fifo = tmp_path / "fifo"
    os.mkfifo(fifo)
    outcome: list[BaseException | None] = []

    def read() -> None:
        try:
            read_log(fifo)
            outcome.append(None)
        except BaseException as exc:  # noqa: BLE001 - handed to the test thread
            outcome.append(exc)

    reader = threading.Thread(target=read, daemon=True)
    reader.start()
    reader.join(3.0)
    if reader.is_alive():  # blocked in open(): a writer that closes at once lets it go
        os.close(os.open(fifo, os.O_WRONLY | os.O_NONBLOCK))
        reader.join(3.0)
        pytest.fail("read_log on a FIFO with no writer did not return in 3 s")
    assert isinstance(outcome[0], ValueError)


@pytest.mark.xfail(strict=True, reason="hero_driver/zenoh_link/codec.py loads: a >4300-digit integer raises a "
                                       "plain ValueError (the node answers internal); catch ValueError as CodecError")
def test_driver_integer_too_long() -> None:
    from hero_driver.zenoh_link.codec import CodecError
    from hero_driver.zenoh_link.verbs import BY_NAME

    with pytest.raises(CodecError):
        BY_NAME["noop"].decode_request(b'{"v": 1' + b"0" * 5000 + b"}")


@pytest.mark.xfail(strict=True, reason="learner/service/protocol.py _fields: json.loads raises RecursionError "
                                       "(the node answers internal); catch it as ProtocolError")
def test_learner_request_nested_too_deep(tmp_path: Path) -> None:
    from learner.service.zenoh_node import LearnerNode

    bench = Workbench(tmp_path)
    try:
        with pytest.raises(ValueError):
            LearnerNode._answer(SimpleNamespace(service=bench.learner), "version", DEEP)  # type: ignore[arg-type]
    finally:
        bench.close()


@pytest.mark.xfail(strict=True, reason="executive/commands/offline.py run_tree: --pose takes any finite distance, "
                                       "and 1e308 prices every test at inf; refuse a distance beyond the room's "
                                       "diagonal (or the largest procedure range plus the move model's reach)")
def test_tree_pose_far_away(tmp_path: Path) -> None:
    code, out, err = run_cli(["tree", "--pose", "1e308,0"], Workbench(tmp_path))
    assert code == 2 and "--pose" in err and "inf" not in out


@pytest.mark.xfail(strict=True, reason="executive/recording/reader.py read_recorded_events: a file that starts "
                                       "with the MCAP magic and then breaks off raises struct.error; catch the "
                                       "mcap reader's errors (struct.error, McapError) as ValueError naming the file")
def test_log_truncated_recording(tmp_path: Path) -> None:
    bench = Workbench(tmp_path)
    path = bench.file("episode.mcap", b"\x89MCAP")
    code, _, err = run_cli(["log", str(path)], bench)
    assert code == 2 and "episode.mcap" in err


@pytest.mark.xfail(strict=True, reason="hero_driver/sim/catalogue.py FieldReader.fail/only: the field name is "
                                       "put in quotes as it is, so a key holding a newline splits the error; "
                                       "use {field!r}")
def test_world_unknown_field_named_in_one_line() -> None:
    from hero_driver.sim.worldfile import parse_world

    world = {**copy.deepcopy(_WORLD_DATA), "\n": 1}
    with pytest.raises(ValueError) as refused:
        parse_world(world, str(WORLD), _catalogue())
    assert "\n" not in str(refused.value)


@pytest.mark.xfail(strict=True, reason="learner/library.py LibraryStore: a store damaged inside its pages raises "
                                       "sqlite3.OperationalError/DatabaseError while rows are read (csl prints a "
                                       "traceback, exit 1), and a damaged schema puts its SQL, newlines and all, "
                                       "in the opening's error; wrap the reads in the opening's 'not a csl library "
                                       "database' ValueError, with the sqlite message's first line only")
@pytest.mark.parametrize(("text", "after"), [(b"Depth-Degree-1", 14), (b"appearance_round INTEGER", 24)],
                         ids=["a row", "the schema"])
def test_library_store_damaged_inside(tmp_path: Path, text: bytes, after: int) -> None:
    from learner.library import LibraryStore, load_library, read_library_json

    store = tmp_path / "lib.sqlite"
    with LibraryStore(store) as opened:
        opened.add(read_library_json(LIBRARY)[:1])
    data = bytearray(store.read_bytes())
    data[data.index(text) + after] = 0xFF  # text that is no longer UTF-8
    store.write_bytes(bytes(data))
    with pytest.raises(ValueError) as refused:
        load_library(store)
    assert "\n" not in str(refused.value)
    code, _, err = run_cli(["library", "stats", "--db", str(store)], Workbench(tmp_path))
    assert code == 2 and err.count("\n") == 1


@pytest.mark.xfail(strict=True, reason="hero_driver/zenoh_link/codec.py _fields: an unknown key is put in the "
                                       "message as it is, so a key holding a newline splits the bad_request "
                                       "line; use {key!r}")
def test_driver_unknown_field_in_one_line() -> None:
    from hero_driver.zenoh_link.codec import CodecError
    from hero_driver.zenoh_link.verbs import BY_NAME

    with pytest.raises(CodecError) as refused:
        BY_NAME["camera"].decode_request(b'{"v": 1, "a\\nb": 1}')
    assert "\n" not in str(refused.value)


@pytest.mark.xfail(strict=True, reason="hero_driver/sim/worldfile.py _board: Path.is_file raises OSError "
                                       "(ENAMETOOLONG) for a name over 255 bytes; treat an OSError as 'not a file'")
def test_world_board_name_too_long() -> None:
    from hero_driver.sim.worldfile import parse_world

    world = {**copy.deepcopy(_WORLD_DATA), "board": "b" * 300}
    with pytest.raises(ValueError, match="board"):
        parse_world(world, str(WORLD), _catalogue())


@pytest.mark.xfail(strict=True, reason="executive/cli.py _Parser.error: argparse's 'unrecognized arguments' joins "
                                       "the tokens as they are, so one holding a newline splits the error; "
                                       "escape control characters in the message (unicode_escape) before printing")
def test_cli_unrecognised_argument_in_one_line(tmp_path: Path) -> None:
    code, _, err = run_cli(["log", "episode.jsonl", "--nope", "a\nb"], Workbench(tmp_path))
    assert code == 2 and err.count("\n") == 1


@pytest.mark.xfail(strict=True, reason="executive/args.py world_argument: Path.is_file raises OSError (file name "
                                       "too long) inside argparse, which main does not catch: a traceback; treat "
                                       "an OSError as 'not a file'")
def test_cli_world_name_too_long(tmp_path: Path) -> None:
    code, _, err = run_cli(["demo", "--world", "w" * 300, "--no-plots"], Workbench(tmp_path))
    assert code == 2 and err.count("\n") == 1
