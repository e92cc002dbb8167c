"""What the fuzzers found, each reduced to its smallest example and kept as a
regression test once fixed (``docs/reliability.md``, Findings).

Each test states the documented behaviour: a one-line ``ValueError``, ``bad_request``
or exit status 2, never a traceback or a hang. A new finding joins them as
``xfail(strict=True)`` naming the file at fault, with a pattern in
``surfaces.KNOWN`` so that the fuzz surfaces count it instead of failing on it
again; when its fix lands, the mark and the pattern go.
"""

from __future__ import annotations

import contextlib
import copy
import re
import json
import math
import os
import threading
from collections.abc import Callable
from pathlib import Path
from types import SimpleNamespace

import pytest
from hypothesis import example, given, settings
from hypothesis import strategies as st

from tests.fuzz.surfaces import LIBRARY, PROFILE, WORLD, Workbench, _WORLD_DATA, _catalogue, run_cli

DEEP = b"[" * 30_000 + b"]" * 30_000
"""Deeper than Python's recursion limit in ``json.loads``."""


def test_world_file_nested_too_deep(tmp_path: Path) -> None:
    """A world file nested deeper than the recursion limit is refused naming the file (``load_world``)."""
    from hero_driver.sim.worldfile import load_world

    path = tmp_path / "deep.json"
    path.write_bytes(DEEP)
    with pytest.raises(ValueError, match="deep.json"):
        load_world(path, _catalogue())


@pytest.mark.parametrize("x", [math.nan, math.inf, 1e308])
def test_world_robot_outside_the_room(x: float) -> None:
    """A robot at NaN, inf or beyond the wall is refused naming ``robot`` (``parse_world``, ``FieldReader.number``)."""
    from hero_driver.sim.worldfile import parse_world

    world = copy.deepcopy(_WORLD_DATA)
    world["robot"]["x_in"] = x
    with pytest.raises(ValueError, match="robot"):
        parse_world(world, str(WORLD), _catalogue())


def test_library_file_nested_too_deep(tmp_path: Path) -> None:
    """``csl library import`` of a deep nest: exit 2, one line (``read_library_json`` via ``learner.library.json_text``)."""
    bench = Workbench(tmp_path)
    path = bench.file("deep.json", DEEP)
    code, _, err = run_cli(["library", "import", "--db", str(tmp_path / "l.sqlite"), str(path)], bench)
    assert code == 2 and err.count("\n") == 1


def test_log_line_nested_too_deep(tmp_path: Path) -> None:
    """``csl log`` of a deep nest: exit 2, one line (``read_log`` via ``learner.library.json_text``)."""
    bench = Workbench(tmp_path)
    path = bench.file("episode.jsonl", DEEP)
    code, _, err = run_cli(["log", str(path)], bench)
    assert code == 2 and err.startswith("csl: error: ") and err.count("\n") == 1


@pytest.mark.parametrize(("line", "named"), [
    ({"event": "test", "tick": None}, "'tick' must be an integer, got NoneType"),
    ({"event": {}, "tick": 1}, "'event' must be a string, got dict"),
    ({"event": "test", "object": []}, "'object' must be an integer, got list"),
    ({"event": "test", "tick": True}, "'tick' must be an integer, got bool"),
])
def test_log_fields_of_another_type(tmp_path: Path, line: dict[str, object], named: str) -> None:
    """An event whose tick, kind or object has another type is refused naming the event
    and the field, not a TypeError (``run_log``); a null object (an episode-level event)
    is still read."""
    bench = Workbench(tmp_path)
    good = json.dumps({"tick": 0, "event": "test", "object": None})
    path = bench.file("episode.jsonl", f"{good}\n{json.dumps(line)}\n".encode())
    code, _, err = run_cli(["log", str(path)], bench)
    assert code == 2 and err == f"csl: error: {path}: event 2: {named}\n"


def _outcome_within(read: Callable[[Path], object], path: Path, seconds: float = 3.0) -> BaseException | None:
    """What ``read(path)`` raised (None: it returned), failing the test when it has not
    returned within ``seconds``. A reader blocked opening a FIFO is let go by a writer
    that closes at once, so no thread is left behind."""
    outcome: list[BaseException | None] = []

    def run() -> None:
        try:
            read(path)
            outcome.append(None)
        except BaseException as exc:  # noqa: BLE001 - handed to the test thread
            outcome.append(exc)

    reader = threading.Thread(target=run, daemon=True)
    reader.start()
    reader.join(seconds)
    if reader.is_alive():
        if path.is_fifo():
            os.close(os.open(path, os.O_WRONLY | os.O_NONBLOCK))
            reader.join(seconds)
        pytest.fail(f"reading {path.name} did not return in {seconds:g} s")
    return outcome[0]


@pytest.mark.parametrize("device", ["fifo", "/dev/zero"])
def test_log_of_a_fifo_does_not_hang(tmp_path: Path, device: str) -> None:
    """A FIFO (no writer: open would wait) or /dev/zero (read would never end) is refused
    at once as not a regular file (``read_log``, ``learner.library.input_file``)."""
    from executive.episode_log import read_log

    path = tmp_path / device
    if device == "fifo":
        os.mkfifo(path)
    refused = _outcome_within(read_log, path)
    assert isinstance(refused, ValueError) and "is a device or a pipe, not an episode log" in str(refused)


def test_knowledge_of_a_fifo_does_not_hang(tmp_path: Path) -> None:
    """Found while fixing the log's FIFO, not by a surface: ``csl tree --knowledge FIFO``
    (and every command taking ``--knowledge``) blocks for ever."""
    from robot_profile.reader import load_profile

    path = tmp_path / "knowledge.toml"
    os.mkfifo(path)
    assert isinstance(_outcome_within(load_profile, path), ValueError)


def test_log_larger_than_any_episode(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    """A file beyond ``MAX_LOG_BYTES`` is refused after reading one byte more than it,
    not read to its end; one at the cap is read."""
    from executive import episode_log

    monkeypatch.setattr(episode_log, "MAX_LOG_BYTES", 40)
    event = json.dumps({"tick": 1, "event": "test"}).encode()  # 28 bytes, then blanks JSON allows
    at_cap = event + b" " * (40 - len(event) - 1) + b"\n"
    assert len(episode_log.read_log(Workbench(tmp_path).file("a.jsonl", at_cap))) == 1
    with pytest.raises(ValueError, match=r"b\.jsonl: more than 40 bytes, too large for an episode log$"):
        episode_log.read_log(Workbench(tmp_path).file("b.jsonl", b" " + at_cap))


def test_driver_integer_too_long() -> None:
    """A 5,000-digit integer is ``bad_request``, not ``internal`` (``codec.loads``)."""
    from hero_driver.zenoh_link.codec import CodecError
    from hero_driver.zenoh_link.verbs import BY_NAME

    with pytest.raises(CodecError, match=r"^message: an integer of more than 4300 digits$"):
        BY_NAME["noop"].decode_request(b'{"v": 1' + b"0" * 5000 + b"}")


def test_learner_request_nested_too_deep(tmp_path: Path) -> None:
    """A learner request nested too deep is ``bad_request``, not ``internal`` (``protocol._fields``)."""
    from learner.service.zenoh_node import LearnerNode

    bench = Workbench(tmp_path)
    try:
        with pytest.raises(ValueError, match=r"^not valid JSON: nested too deeply"):
            LearnerNode._answer(SimpleNamespace(service=bench.learner), "version", DEEP)  # type: ignore[arg-type]
    finally:
        bench.close()


def test_tree_pose_far_away(tmp_path: Path) -> None:
    """``csl tree --pose 1e308,0`` is refused naming ``--pose``, never prints inf (``run_tree``)."""
    code, out, err = run_cli(["tree", "--pose", "1e308,0"], Workbench(tmp_path))
    assert code == 2 and err.startswith("csl: error: --pose: ") and "inf" not in out
    code, out, _ = run_cli(["tree", "--pose", "10000,0"], Workbench(tmp_path))  # the farthest accepted
    assert code == 0 and "inf" not in out


def test_log_truncated_recording(tmp_path: Path) -> None:
    """A recording cut after its magic is one line naming the file (``read_recorded_events``)."""
    bench = Workbench(tmp_path)
    path = bench.file("episode.mcap", b"\x89MCAP")
    code, _, err = run_cli(["log", str(path)], bench)
    assert code == 2 and "episode.mcap" in err


def test_world_unknown_field_named_in_one_line() -> None:
    """An unknown key holding a newline is named on one line (``FieldReader.fail``)."""
    from hero_driver.sim.worldfile import parse_world

    world = {**copy.deepcopy(_WORLD_DATA), "\n": 1}
    with pytest.raises(ValueError) as refused:
        parse_world(world, str(WORLD), _catalogue())
    assert "\n" not in str(refused.value)


@pytest.mark.parametrize(("text", "after"), [(b"Depth-Degree-1", 14), (b"appearance_round INTEGER", 24)],
                         ids=["a row", "the schema"])
def test_library_store_damaged_inside(tmp_path: Path, text: bytes, after: int) -> None:
    """A store damaged inside is one line from ``load_library`` and exit 2 from ``csl library stats``
    (``LibraryStore``)."""
    from learner.library.format import read_library_json
    from learner.library.store import LibraryStore, load_library

    store = tmp_path / "lib.sqlite"
    with LibraryStore(store) as opened:
        opened.add(read_library_json(LIBRARY)[:1])
    data = bytearray(store.read_bytes())
    at = [i for i in range(len(data)) if data.startswith(text, i)]
    for i in at:  # every copy: a page SQLite no longer uses may hold one too
        data[i + after] = 0xFF  # text that is no longer UTF-8
    assert at
    store.write_bytes(bytes(data))
    # refused when opened (SQLite's quick check) or when read, never served
    refusal = r"lib.sqlite: (not a csl library database: |the library database is damaged \(SQLite's check: )"
    with pytest.raises(ValueError, match=refusal) as refused:
        load_library(store)
    assert "\n" not in str(refused.value)
    code, _, err = run_cli(["library", "stats", "--db", str(store)], Workbench(tmp_path))
    assert code == 2 and err.count("\n") == 1 and re.search(refusal, err)


def test_driver_unknown_field_in_one_line() -> None:
    """An unknown key holding a newline is named on one line (``codec._fields``)."""
    from hero_driver.zenoh_link.codec import CodecError
    from hero_driver.zenoh_link.verbs import BY_NAME

    with pytest.raises(CodecError) as refused:
        BY_NAME["camera"].decode_request(b'{"v": 1, "a\\nb": 1}')
    assert str(refused.value) == "'a\\nb': unknown field"


def test_world_board_name_too_long() -> None:
    """A ``board`` name over 255 bytes is refused naming ``board``, not an OSError (``worldfile._board``)."""
    from hero_driver.sim.worldfile import parse_world

    world = {**copy.deepcopy(_WORLD_DATA), "board": "b" * 300}
    with pytest.raises(ValueError, match="board"):
        parse_world(world, str(WORLD), _catalogue())


def test_cli_unrecognised_argument_in_one_line(tmp_path: Path) -> None:
    """An unrecognised argument holding a newline is escaped: one error line (``_Parser.error``)."""
    code, _, err = run_cli(["log", "episode.jsonl", "--nope", "a\nb"], Workbench(tmp_path))
    assert code == 2 and err == "csl: error: unrecognized arguments: --nope a\\nb (see 'csl --help')\n"


def test_cli_world_name_too_long(tmp_path: Path) -> None:
    """``--world`` of 300 characters is refused while parsing, not an OSError (``world_argument``)."""
    code, _, err = run_cli(["demo", "--world", "w" * 300, "--no-plots"], Workbench(tmp_path))
    assert code == 2 and err.count("\n") == 1 and "is neither a world file nor a shipped world" in err


@settings(max_examples=100, deadline=None)
@given(st.lists(st.dictionaries(st.sampled_from(["note", "test", "why"]), st.text(max_size=8)
                                | st.integers(-(10**6), 10**6)), min_size=1, max_size=4))
@example([{"note": "a\u2028b"}, {"why": "\x85\x1c\r"}])
def test_log_reads_back_what_episode_log_wrote(tmp_path_factory: pytest.TempPathFactory,
                                               fields: list[dict[str, object]]) -> None:
    """Whatever text an event holds, ``read_log`` reads back what ``EpisodeLog`` wrote.
    Found while fixing the log reader, not by a fuzz surface (whose property is only
    "refused cleanly"): ``splitlines`` also split lines at U+2028 and U+0085, which
    ``ensure_ascii=False`` writes as they are, so such a log was refused as not JSON."""
    from behaviours.events import Event
    from executive.episode_log import EpisodeLog, read_log

    path = tmp_path_factory.mktemp("log") / "episode.jsonl"
    log = EpisodeLog(path)
    for n, extra in enumerate(fields):
        log.tick = n
        log.event(Event.LOCATED, **extra)
    log.close()
    assert read_log(path) == [{"tick": n, "event": Event.LOCATED.value, **extra} for n, extra in enumerate(fields)]


@pytest.mark.parametrize(("codes", "why"), [(b"\xff\xff\xff\x7f", "KeyError: 2147483647"),
                                            ("abc", "TypeError: "), (b"\x01\x00\x00", "ValueError: ")],
                         ids=["a code with no observation", "text", "a blob cut short"])
def test_library_store_rows_that_do_not_decode(tmp_path: Path, codes: object, why: str) -> None:
    """Found by ``bench/fuzz.py`` (16 + 7 cases in 10,000): a store damaged so that a
    description's observation codes no longer decode is one line from ``load_library``
    naming the store, as a store SQLite cannot read is (``LibraryStore.descriptions``)."""
    import contextlib
    import sqlite3

    from learner.library.format import read_library_json
    from learner.library.store import _CODED, LibraryStore, load_library

    store = tmp_path / "lib.sqlite"
    with LibraryStore(store) as opened:
        opened.add(read_library_json(LIBRARY)[:1])
    with contextlib.closing(sqlite3.connect(store)) as db, db:
        db.execute(f"UPDATE descriptions SET {_CODED} = ?", (codes,))
    with pytest.raises(ValueError, match=rf"^{store}: not a csl library database: a row does not decode \({why}"):
        load_library(store)


def test_profile_name_in_one_line() -> None:
    """Found by ``bench/fuzz.py`` (1 case in 10,000, the shipped profile with a line
    cut into a multi-line string): a sensing procedure whose name holds a newline
    and whose ``time_s`` is negative is refused on one line."""
    import tomllib

    from robot_profile.reader import profile_from_dict

    data = tomllib.loads(PROFILE.read_text(encoding="utf-8"))
    data["sensing"][0].update(name="a\nb", time_s=-1)
    with pytest.raises(ValueError) as refused:
        profile_from_dict(data, "p.toml")
    assert "\n" not in str(refused.value)


@pytest.mark.slow
def test_log_recording_damaged_at_every_byte(tmp_path: Path) -> None:
    """Found with the log surface's damaged recordings: a real recording with any one
    byte set to 0x00 (even offsets) or 0xFF (odd), or cut at any 16th byte, is read or refused in one line
    naming it, never another exception. Before the fix the mcap reader's own errors
    escaped: zstd's "data corruption", a KeyError for a damaged channel id, OverflowError,
    MemoryError, struct.error (``read_recorded_events``, through ``read_events``)."""
    from recording.reader import read_events
    from tests.fuzz.surfaces import _recording

    bench = Workbench(tmp_path)
    pristine = _recording(bench)
    damaged = [pristine[:i] + bytes([0xFF * (i % 2)]) + pristine[i + 1:] for i in range(5, len(pristine))]
    damaged += [pristine[:i] for i in range(5, len(pristine), 16)]
    outcomes = {"read": 0, "refused": 0}
    for n, data in enumerate(damaged):
        path = bench.file(f"r{n % 2}.mcap", data)
        try:
            read_events(path)
            outcomes["read"] += 1
        except ValueError as refused:
            assert str(refused).startswith(str(path)) and "\n" not in str(refused), str(refused)
            outcomes["refused"] += 1
    assert outcomes["refused"] > 300 and outcomes["read"] > 300, outcomes  # both ways, many times


def test_learner_grasp_totals_overflow(tmp_path: Path) -> None:
    """Two ``record_grasps`` of one 1e308 s attempt each (finite, so each is accepted)
    make the grasp's running total inf: from then on every ``grasp_costs`` answer fails
    to encode (``bad_request`` "Out of range float values are not JSON compliant", for
    every robot) and the learned price of the grasp is inf. Refusing such an attempt,
    or keeping the totals finite, is what the property asks."""
    from learner.service.protocol import decode_grasp_costs_reply
    from learner.service.zenoh_node import LearnerNode
    from tests.fuzz.surfaces import all_finite

    bench = Workbench(tmp_path)
    try:
        for key in ("episode/0", "episode/1"):
            with contextlib.suppress(ValueError):  # a refusal is one way to hold the property
                bench.learner.record_grasp_attempts([("Front-Wrap", 1e308, True)], key=key)
        assert all_finite(bench.learner.grasp_costs())
        node = LearnerNode.__new__(LearnerNode)
        node.service = bench.learner
        assert all_finite(decode_grasp_costs_reply(node._answer("grasp_costs", b'{"v": 1}')))
    finally:
        bench.close()
