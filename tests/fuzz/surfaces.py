"""Every input surface of csl, with a strategy for hostile cases and the property a
case must hold, shared by ``tests/fuzz`` (a few hundred cases) and ``bench/fuzz.py``
(tens of thousands).

The property is the same everywhere: bad input gives a clean error of
the documented kind (``ValueError``, ``bad_request``, exit status 2 with one line),
never another exception; what is accepted is sound (finite, inside the room); a
refused import leaves the library as it was. A case that breaks it raises
:class:`Finding`. Hangs are kept out by bounded sizes: no case is larger than a few
hundred kilobytes, and nothing reads a device or a FIFO (those are regression tests).
"""

from __future__ import annotations

import argparse
import contextlib
import dataclasses
import functools
import io
import json
import math
import os
import re
import sqlite3
import tomllib
from collections.abc import Callable, Iterator
from concurrent.futures import Future
from dataclasses import dataclass
from pathlib import Path
from typing import Any

from hypothesis import strategies as st

from tests.fuzz.mutation import bombs, damaged_bytes, dumps, json_values, mutated, payloads

REPO = Path(__file__).resolve().parents[2]
PROFILE = REPO / "hero_driver" / "profiles" / "hero2000.toml"
LIBRARY = REPO / "hero_driver" / "profiles" / "hero2000-library.json"
WORLD = REPO / "hero_driver" / "worlds" / "lab.json"


class Finding(AssertionError):
    """A case that broke the property: the message says how."""


def one_line(message: str, where: str) -> None:
    """A refusal is one line that says something."""
    text = message.strip()
    if not text or "\n" in text:
        raise Finding(f"{where}: a refusal must be one non-empty line, got {message!r}")


def refused(call: Callable[[], Any], where: str) -> Any:
    """Run ``call``: its result, or None when it refused with a one-line ValueError;
    any other exception is a finding."""
    try:
        return call()
    except ValueError as exc:
        one_line(str(exc), where)
        return None
    except Exception as exc:  # the property under test: nothing but ValueError escapes
        raise Finding(f"{where}: {type(exc).__name__}: {str(exc)[:200]}") from exc


def all_finite(value: object) -> bool:
    """Every number inside a dataclass, mapping or sequence is finite."""
    if isinstance(value, float):
        return math.isfinite(value)
    if dataclasses.is_dataclass(value) and not isinstance(value, type):
        return all(all_finite(getattr(value, f.name)) for f in dataclasses.fields(value))
    if isinstance(value, dict):
        return all(all_finite(v) for v in value.values())
    if isinstance(value, (list, tuple)):
        return all(all_finite(v) for v in value)
    return True


# ----------------------------------------------------------------------- the workbench


class Workbench:
    """The folder a surface's cases write to, and the real objects they run against
    (a simulated robot, a learner service), made once and reused across cases."""

    def __init__(self, folder: Path) -> None:
        self.folder = folder
        folder.mkdir(parents=True, exist_ok=True)
        self._robot: Any = None
        self._learner: Any = None

    def file(self, name: str, data: bytes) -> Path:
        path = self.folder / name
        path.write_bytes(data)
        return path

    @property
    def robot(self) -> Any:
        if self._robot is None:
            from hero_driver.sim_driver import SimulatedHero

            self._robot = SimulatedHero("fuzz", world=WORLD)
        return self._robot

    @property
    def learner(self) -> Any:
        if self._learner is None:
            from robot_profile import load_knowledge
            from learner.library.format import read_library_json
            from learner.service.local import LocalLearner

            self._learner = LocalLearner(self.folder / "learner.sqlite", seed_library=read_library_json(LIBRARY),
                                         knowledge=load_knowledge(PROFILE))
        return self._learner

    def renew_learner(self) -> None:
        """Start the next case from a fresh store (after a case left the store unsound,
        so that one finding does not make every later case fail on it too)."""
        if self._learner is not None:
            self._learner.close()
            self._learner = None
        for suffix in ("", "-wal", "-shm"):
            (self.folder / f"learner.sqlite{suffix}").unlink(missing_ok=True)

    def close(self) -> None:
        if self._learner is not None:
            self._learner.close()
        if self._robot is not None:
            self._robot.close()


@contextlib.contextmanager
def inside(folder: Path) -> Iterator[None]:
    """Run with ``folder`` as the working directory (a command's default outputs land there)."""
    before = os.getcwd()
    os.chdir(folder)
    try:
        yield
    finally:
        os.chdir(before)


# ------------------------------------------------------------------ knowledge (TOML)
# TOML's document is always a table: the root is never replaced.

_TOML_TEXT = PROFILE.read_text(encoding="utf-8")
_TOML_DATA = tomllib.loads(_TOML_TEXT)
toml_scalars = st.one_of(
    st.booleans(), st.integers(min_value=-(2**63), max_value=2**63 - 1),
    st.floats(allow_nan=True, allow_infinity=True), st.text(max_size=12),
    st.sampled_from([0, -1, 1e308, -1e308, math.nan, math.inf, "", "H-Sweep-1°", "Width"]),
)
toml_values = st.recursive(
    toml_scalars, lambda inner: st.lists(inner, max_size=4) | st.dictionaries(st.text(max_size=8), inner, max_size=3),
    max_leaves=8)
_TOML_LITERALS = ["nan", "inf", "-inf", "1e308", "-1", "0", '""', "[]", "{}", "true", '"x"', "[1, 2, 3]",
                  "9" * 30, "[[[[1]]]]", "{ a = 1 }", "'''", '"\\ud800"', "1979-05-27"]


@st.composite
def toml_text(draw: st.DrawFn) -> bytes:
    """The shipped profile with lines changed: a value replaced by another TOML
    literal, a line deleted, duplicated or cut, or bytes damaged."""
    lines = _TOML_TEXT.splitlines()
    for _ in range(draw(st.integers(1, 3))):
        i = draw(st.integers(0, len(lines) - 1))
        op = draw(st.sampled_from(["value", "value", "delete", "duplicate", "cut"]))
        if op == "value" and "=" in lines[i]:
            key = lines[i].split("=", 1)[0]
            lines[i] = f"{key}= {draw(st.sampled_from(_TOML_LITERALS))}"
        elif op == "delete":
            del lines[i]
        elif op == "duplicate":
            lines.insert(i, lines[i])
        else:
            lines[i] = lines[i][:draw(st.integers(0, len(lines[i])))]
    data = ("\n".join(lines) + "\n").encode("utf-8")
    return draw(st.one_of(st.just(data), damaged_bytes(data)))


profile_cases = st.one_of(st.tuples(st.just("dict"), mutated(_TOML_DATA, toml_values, root=False)),
                          st.tuples(st.just("text"), toml_text()))


def check_profile(case: tuple[str, Any], bench: Workbench) -> str:
    """``robot_profile.reader``: parsed data, or the file itself."""
    from robot_profile.reader import load_profile, profile_from_dict

    kind, value = case
    if kind == "dict":
        profile = refused(lambda: profile_from_dict(value, "fuzz.toml"), "profile_from_dict")
    else:
        path = bench.file("fuzz.toml", value)
        profile = refused(lambda: load_profile(path), "load_profile")
    if profile is None:
        return "refused"
    if not all_finite(profile):
        raise Finding(f"profile accepted with a non-finite number: {profile}")

    refused(lambda: profile.knowledge(), "the knowledge of an accepted profile")  # the learner's view of it
    return "accepted"


# ------------------------------------------------------------------------ world files

_WORLD_DATA = json.loads(WORLD.read_text(encoding="utf-8"))
world_cases = st.one_of(st.tuples(st.just("doc"), mutated(_WORLD_DATA)),
                        st.tuples(st.just("file"), payloads(_WORLD_DATA)))


_CATALOGUE: dict[str, Any] = {}


def _catalogue() -> dict[str, Any]:
    """The shipped catalogue, read once."""
    if not _CATALOGUE:
        from hero_driver.sim.catalogue import load_catalogue
        from robot_profile.reader import load_profile

        _CATALOGUE.update(load_catalogue([g.name for g in load_profile(PROFILE).grasping]))
    return _CATALOGUE


def check_world(case: tuple[str, Any], bench: Workbench) -> str:
    """``hero_driver.sim.worldfile``: a decoded document, or the file itself. An
    accepted world has finite numbers and its robot inside the room."""
    from hero_driver.sim.worldfile import load_world, parse_world

    catalogue = _catalogue()
    kind, value = case
    for sibling in WORLD.parent.glob("*.json"):  # what a world names beside it (the lab's board)
        if not (bench.folder / sibling.name).exists():
            bench.file(sibling.name, sibling.read_bytes())
    if kind == "doc":
        source = str(bench.folder / "fuzz.json")
        spec = refused(lambda: parse_world(value, source, catalogue), "parse_world")
    else:
        path = bench.file("fuzz.json", value)
        spec = refused(lambda: load_world(path, catalogue), "load_world")
    if spec is None:
        return "refused"
    if not all_finite(spec):
        raise Finding(f"world accepted with a non-finite number: {spec}")
    x, y, _ = spec.robot
    if not (0 <= x <= spec.room_width_in and 0 <= y <= spec.room_depth_in):
        raise Finding(f"world accepted with the robot at ({x:g}, {y:g}) outside the "
                      f"{spec.room_width_in:g}x{spec.room_depth_in:g} in room")
    return "accepted"


# --------------------------------------------------------------------- library (JSON)

_LIBRARY_DATA = json.loads(LIBRARY.read_text(encoding="utf-8"))
_SMALL_LIBRARY = {**_LIBRARY_DATA, "descriptions": _LIBRARY_DATA["descriptions"][:2]}
@st.composite
def _damaged_store(draw: st.DrawFn) -> list[tuple[int, int]]:
    """Where to damage a SQLite store: up to 4 (offset, byte) pairs, offsets as a
    fraction of the file in 1/4096ths so that they fall inside whatever size it has."""
    return draw(st.lists(st.tuples(st.integers(0, 4095), st.integers(0, 255)), min_size=1, max_size=4))


library_cases = st.one_of(st.tuples(st.just("doc"), mutated(_SMALL_LIBRARY)),
                          st.tuples(st.just("import"), payloads(_SMALL_LIBRARY)),
                          st.tuples(st.just("store"), _damaged_store()))


def _rows(db: Path) -> list[tuple[Any, ...]]:
    with contextlib.closing(sqlite3.connect(db)) as conn:
        return conn.execute("SELECT * FROM descriptions ORDER BY id").fetchall()


def _check_store(damage: list[tuple[int, int]], bench: Workbench) -> str:
    """A damaged copy of a real SQLite library through ``load_library``."""
    from learner.library.format import read_library_json
    from learner.library.store import LibraryStore, load_library

    pristine = bench.folder / "pristine.sqlite"
    if not pristine.exists():
        with LibraryStore(pristine) as store:
            store.add(read_library_json(LIBRARY)[:3])
    data = bytearray(pristine.read_bytes())
    for where, byte in damage:
        data[where * len(data) // 4096] = byte
    path = bench.file("damaged.sqlite", bytes(data))
    for suffix in ("-wal", "-shm"):
        Path(f"{path}{suffix}").unlink(missing_ok=True)
    out = refused(lambda: load_library(path), "load_library (damaged store)")
    return "refused" if out is None else "accepted"


def check_library(case: tuple[str, Any], bench: Workbench) -> str:
    """``learner.library.format``: a decoded document through ``descriptions_from_json``, or a
    file through ``csl library import``, whose refusal must leave the store as it was."""
    from learner.library.format import descriptions_from_json

    kind, value = case
    if kind == "store":
        return _check_store(value, bench)
    if kind == "doc":
        out = refused(lambda: descriptions_from_json(value, "fuzz.json"), "descriptions_from_json")
        if out is not None and not all_finite(out):
            raise Finding(f"library accepted with a non-finite value: {out}")
        return "refused" if out is None else "accepted"
    db = bench.folder / "import.sqlite"
    if not db.exists():
        code, _, err = run_cli(["library", "import", "--db", str(db), str(LIBRARY)], bench)
        assert code == 0, err
    before = _rows(db)
    path = bench.file("fuzz-library.json", value)
    code, _, err = run_cli(["library", "import", "--db", str(db), str(path)], bench)
    if code == 0:
        db.unlink()  # the next case starts from the shipped library again
        for suffix in ("-wal", "-shm"):
            Path(f"{db}{suffix}").unlink(missing_ok=True)
        return "accepted"
    if code != 2:
        raise Finding(f"csl library import: exit {code}: {err.strip()[-300:]}")
    if _rows(db) != before:
        raise Finding("csl library import: a refused import changed the library")
    return "refused"


# ---------------------------------------------------------------------- CLI and running


def run_cli(argv: list[str], bench: Workbench) -> tuple[int, str, str]:
    """``csl_cli.main.main`` in this process, in the workbench folder: (exit status,
    stdout, stderr). A SystemExit is taken as its status, the way the shell would."""
    from csl_cli.main import main

    out, err = io.StringIO(), io.StringIO()
    with inside(bench.folder), contextlib.redirect_stdout(out), contextlib.redirect_stderr(err):
        try:
            code = main(argv)
        except SystemExit as exc:
            code = exc.code if isinstance(exc.code, int) else (0 if exc.code is None else 2)
        except Exception as exc:  # the property under test
            raise Finding(f"csl {' '.join(argv)[:120]}: {type(exc).__name__}: {str(exc)[:200]}") from exc
    if not isinstance(code, int):
        raise Finding(f"csl {' '.join(argv)[:120]}: returned {code!r}, not an exit status")
    return code, out.getvalue(), err.getvalue()


def check_exit(argv: list[str], code: int, err: str) -> None:
    """Exit 0-3; a 2 comes with an error line and no traceback."""
    if code not in (0, 1, 2, 3):
        raise Finding(f"csl {' '.join(argv)[:120]}: exit status {code}")
    if "Traceback" in err:
        raise Finding(f"csl {' '.join(argv)[:120]}: printed a traceback")
    if code == 2:
        last = err.strip().split("\n")[-1]  # not splitlines: an argument may hold \x1c-\x1e
        if "error" not in last:
            raise Finding(f"csl {' '.join(argv)[:120]}: exit 2 without an error line, stderr {err[-600:]!r}")


# ----------------------------------------------------------------------- episode logs

_EVENT = {"tick": 3, "object": 0, "event": "test", "behaviour": "Sense", "test": "H-Sweep-5°", "cost_s": 45.0}
log_lines = st.one_of(mutated(_EVENT).map(dumps), json_values.map(dumps), st.binary(max_size=40),
                      st.sampled_from(bombs()[:4] + [b"", b"NaN", b"[]", b"{}"]))
_LOG_FLAGS = st.lists(st.sampled_from([["--object", "0"], ["--object", "-1"], ["--object", "9" * 5000],
                                       ["--events", "test"], ["--events", "nope"], ["--events", ""],
                                       ["--object", "x"]]), max_size=2)
log_cases = st.one_of(
    st.tuples(st.just("lines"), st.lists(log_lines, max_size=6), _LOG_FLAGS),
    st.tuples(st.just("recording"), st.one_of(_damaged_store(), st.integers(0, 4095)), _LOG_FLAGS),
)
"""An episode.jsonl of hostile lines, or a real MCAP recording damaged (1-4 bytes
overwritten, as a store is) or cut short (at a fraction of its length in 1/4096ths)."""


def _recording(bench: Workbench) -> bytes:
    """A real recording of a few events (foxglove's MCAP writer, zstd chunks, csl's
    events channel), made once per workbench."""
    path = bench.folder / "pristine.mcap"
    if not path.exists():
        from recording.session import Recording
        from robot_profile.reader import load_profile

        recording = Recording(load_profile(PROFILE).robot.geometry, mcap=path)
        try:
            for tick in range(6):
                recording.recorder.event({**_EVENT, "tick": tick, "object": tick // 2}, float(tick))
        finally:
            recording.close()
    return path.read_bytes()


def check_log(case: tuple[str, Any, list[list[str]]], bench: Workbench) -> str:
    """``csl log FILE`` on a file of hostile lines, or on a damaged recording."""
    kind, damage, flags = case
    if kind == "lines":
        path = bench.file("episode.jsonl", b"\n".join(damage))
    else:
        data = bytearray(_recording(bench))
        if isinstance(damage, int):
            data = data[:max(1, damage * len(data) // 4096)]
        else:
            for where, byte in damage:
                data[where * len(data) // 4096] = byte
        path = bench.file("episode.mcap", bytes(data))
    argv = ["log", str(path), *[token for flag in flags for token in flag]]
    code, _, err = run_cli(argv, bench)
    check_exit(argv, code, err)
    return "accepted" if code == 0 else "refused"


# --------------------------------------------------------------------- CLI arguments


def _options(parser: argparse.ArgumentParser, path: tuple[str, ...] = ()) -> dict[tuple[str, ...], list[str]]:
    """Each (sub)command's path and its option strings, from the real parser."""
    subs = [a for a in parser._actions if isinstance(a, argparse._SubParsersAction)]
    out: dict[tuple[str, ...], list[str]] = {}
    if not subs:
        out[path] = [s for a in parser._actions for s in a.option_strings if s not in ("-h", "--help")]
    for sub in subs:
        for name, child in sub.choices.items():
            out.update(_options(child, path + (name,)))
    return out


RUN_IN_FULL = {("tree",), ("log",), ("library", "show"), ("library", "import"), ("library", "export"),
               ("library", "stats")}
"""Commands the fuzzer runs to the end: they finish in milliseconds. The others (an
episode, a server, a network call) are fuzzed through the argument parser only."""
_VALUES = ["0", "1", "-1", "3", "nan", "inf", "-inf", "1e308", "-1e308", "1e308,0", "0,0", "nan,0", "1,2,3", "",
           "x", "sense=1", "sense=nan", "sense=-1", "nope=1", "tcp/127.0.0.1:1", "tcp/[::1]:0", "udp/x",
           "9" * 5000, "library.json", "knowledge.toml", "garbage.bin", "missing.json", "folder", "/dev/null",
           "out.png", "a" * 300, "--", "-", "\x00", "é"]


@functools.cache
def _option_table() -> dict[tuple[str, ...], list[str]]:
    """The real parser's commands and options, built once (not inside a draw)."""
    from csl_cli.main import build_parser

    return _options(build_parser())


@st.composite
def argvs(draw: st.DrawFn, table: dict[tuple[str, ...], list[str]]) -> list[str]:
    """A command of the real parser (``table``) with up to five of its own options (and
    now and then another command's) with values from a hostile pool."""
    every = sorted({o for opts in table.values() for o in opts})
    path = draw(st.sampled_from(sorted(table)))
    own = table[path] or ["--help"]
    argv = list(path)
    for _ in range(draw(st.integers(0, 5))):
        option = draw(st.one_of(st.sampled_from(own), st.sampled_from(own), st.sampled_from(every),
                                st.sampled_from(["--help", "--version", "--nope", "-x"])))
        argv.append(option)
        if draw(st.integers(0, 4)):
            argv.append(draw(st.one_of(st.sampled_from(_VALUES), st.text(max_size=6))))
    if draw(st.booleans()):
        argv.append(draw(st.sampled_from(_VALUES)))
    return argv


cli_cases = st.deferred(lambda: argvs(_option_table()))
"""Deferred: the parser is built when the fuzzing starts, not at import, and not inside
a draw (building it touches the ``random`` module, which Hypothesis warns about)."""


def _prepare_cli(bench: Workbench) -> None:
    if not (bench.folder / "library.json").exists():
        (bench.folder / "library.json").write_bytes(LIBRARY.read_bytes())
        (bench.folder / "knowledge.toml").write_bytes(PROFILE.read_bytes())
        (bench.folder / "garbage.bin").write_bytes(bytes(range(256)) * 4)
        (bench.folder / "folder").mkdir(exist_ok=True)


def _without_names(out: str, argv: list[str], folder: Path) -> str:
    """``out`` without the arguments it echoes that are names, not numbers: any that
    is not a number, and any that names a file the command wrote (``csl library
    export inf`` prints ``exported 14 descriptions to inf``); a number csl printed stays."""
    for arg in sorted(argv, key=len, reverse=True):
        try:
            float(arg)
            is_name = (folder / arg).exists()
        except (ValueError, OSError):  # OSError: a name too long to be a file
            is_name = len(arg) > 1
        if is_name:
            out = out.replace(arg, "")
    return out


def check_cli(argv: list[str], bench: Workbench) -> str:
    """``csl_cli.main.main``: quick commands run to the end, the rest are parsed."""
    from csl_cli.main import build_parser

    _prepare_cli(bench)
    text = [a.replace("\x00", "") for a in argv]  # an argv from a shell cannot hold NUL
    path = tuple(a for a in text[:2] if not a.startswith("-"))
    if path in RUN_IN_FULL or path[:1] in RUN_IN_FULL:
        code, out, err = run_cli(text, bench)
        if code == 0 and re.search(r"\b(inf|nan)\b", _without_names(out, text, bench.folder), re.IGNORECASE):
            raise Finding(f"csl {' '.join(text)[:120]}: exit 0 printing a non-finite number")
        left = sorted(p.name for p in bench.folder.rglob("*.tmp"))
        if left:  # library export writes atomically: a failure leaves nothing behind
            raise Finding(f"csl {' '.join(text)[:120]}: left a half-written file {left[0]}")
    else:
        err_io = io.StringIO()
        with inside(bench.folder), contextlib.redirect_stdout(io.StringIO()), contextlib.redirect_stderr(err_io):
            try:
                build_parser().parse_args(text)
                code = 0
            except SystemExit as exc:
                code = exc.code if isinstance(exc.code, int) else 2
            except Exception as exc:  # the property under test
                raise Finding(f"csl {' '.join(text)[:120]}: parsing raised {type(exc).__name__}: {exc}") from exc
        err = err_io.getvalue()
    check_exit(text, code, err)
    return "accepted" if code == 0 else "refused"


# ---------------------------------------------------------------- driver verb payloads

_GOOD_REQUESTS: dict[str, Any] = {
    "move": {"v": 1, "waypoints": [{"x_in": 40.0, "y_in": 30.0, "heading_deg": 0.0}], "face": None},
    "sense": {"v": 1, "procedure": "H-Sweep-5°"},
    "grasp": {"v": 1, "procedure": "Front-Wrap"},
    "release": {"v": 1},
    "camera": {"v": 1},
    "scan": {"v": 1},
    "reset": {"v": 1, "world": "lab", "seed": 1},
    "noop": {"v": 1},
    "hello": {"v": 1},
}
driver_cases = st.sampled_from(sorted(_GOOD_REQUESTS)).flatmap(
    lambda verb: st.tuples(st.just(verb), payloads(_GOOD_REQUESTS[verb])))


def check_driver(case: tuple[str, bytes], bench: Workbench) -> str:
    """A driver verb's payload through the codec and on to a simulated robot, as the
    node serves it: a CodecError is ``bad_request``; a DriverError is the driver's
    answer; anything else (the node's ``internal``) is a finding."""
    from hero_driver.interface import ERROR_CODES, DriverError
    from hero_driver.zenoh_link.codec import CodecError
    from hero_driver.zenoh_link.verbs import BY_NAME
    from hero_driver.zenoh_link.versions import greeting

    name, payload = case
    verb = BY_NAME[name]
    try:
        request = verb.decode_request(payload)
    except CodecError as exc:
        one_line(str(exc), f"{name} request")
        return "refused"
    except Exception as exc:  # the node would answer internal, with a traceback in its log
        raise Finding(f"{name}: decoding {payload[:80]!r}... raised {type(exc).__name__}: {str(exc)[:200]}") from exc
    target = bench.robot if verb.touches_robot else greeting(None)
    try:
        done: Future[Any] = verb.call(target, request)
        verb.encode_result(done.result(timeout=30))
    except DriverError as exc:
        if exc.code not in ERROR_CODES or exc.code == "internal":
            raise Finding(f"{name}: driver error with unknown code {exc.code!r}") from exc
        one_line(exc.message, f"{name} {exc.code}")
        return "refused"
    except Exception as exc:
        raise Finding(f"{name}: {request} raised {type(exc).__name__}: {str(exc)[:200]}") from exc
    if not all_finite(bench.robot.state()):
        raise Finding(f"{name}: {request} left the robot at {bench.robot.state()}")
    return "accepted"


# ------------------------------------------------------------------- learner requests

_LEARN = {"v": 1, "description": _LIBRARY_DATA["descriptions"][0], "key": "fuzz-key"}
learner_cases = st.one_of(
    st.tuples(st.just("learn"), payloads(_LEARN)),
    st.tuples(st.sampled_from(["library", "version"]), payloads({"v": 1})),
)
learner_changes_cases = st.tuples(st.just("changes"), payloads({"v": 1, "since": 0}))
"""``changes``: what the library gained after version ``since``."""
_RECORD = {"v": 1, "attempts": [["Front-Wrap", 60.0, True], ["Front-Pinch", 45.0, False]], "key": "fuzz-grasps"}
learner_grasps_cases = st.one_of(
    st.tuples(st.just("record_grasps"), payloads(_RECORD)),
    st.tuples(st.just("record_grasps"), payloads({"v": 1, "attempts": _RECORD["attempts"]})),  # no key: refused
    st.tuples(st.just("grasp_costs"), payloads({"v": 1})),
)
"""``record_grasps`` (with and without an idempotency key) and ``grasp_costs``: the
learned grasp costs of docs/method.md §5.7."""
_GRASP_VERBS = ("record_grasps", "grasp_costs")


def _reply_decoder(verb: str) -> Callable[[bytes], Any]:
    """The client's reader of ``verb``'s reply: what the node answers must read back."""
    from learner.service import protocol

    return {"learn": protocol.decode_learn_reply, "library": protocol.decode_library_reply,
            "version": protocol.decode_version_reply, "changes": protocol.decode_changes_reply,
            "record_grasps": protocol.decode_recorded_reply,
            "grasp_costs": protocol.decode_grasp_costs_reply}[verb]


def check_learner(case: tuple[str, bytes], bench: Workbench) -> str:
    """A learner request through the service node's own handler on a real SQLite
    service: ValueError is ``bad_request``; anything else (``internal``) is a finding.
    An accepted request's reply must read back with the client's decoder, and after a
    grasp-cost request the store's totals must still be finite."""
    from learner.service.zenoh_node import LearnerNode

    verb, payload = case
    node = LearnerNode.__new__(LearnerNode)  # the handler without a session: it reads only the service
    node.service = bench.learner
    try:
        body = node._answer(verb, payload)
        outcome = "accepted"
    except ValueError as exc:
        one_line(str(exc), f"{verb} bad_request")
        body, outcome = None, "refused"
    except Exception as exc:
        raise Finding(f"{verb}: {payload[:80]!r}... answered internal: {type(exc).__name__}: "
                      f"{str(exc)[:200]}") from exc
    if body is not None:
        try:
            _reply_decoder(verb)(body)
        except Exception as exc:  # a reply its own client cannot read
            raise Finding(f"{verb}: the reply to {payload[:80]!r} does not read back: {type(exc).__name__}: "
                          f"{str(exc)[:200]}") from exc
    if verb in _GRASP_VERBS and not all_finite(totals := bench.learner.grasp_costs()):
        bench.renew_learner()
        raise Finding(f"{verb}: after {payload[:120]!r} the grasp cost totals are non-finite: {totals}")
    return outcome


KNOWN: dict[str, tuple[tuple[str, str], ...]] = {}
"""Findings reduced to a regression test in ``tests/fuzz/test_findings.py`` but not yet
fixed, by surface: (a pattern of the finding's text, the test's name). A case that
matches one is counted as known instead of failing the fuzzing again; the entry goes
when the fix lands (its strict xfail then fails)."""


@dataclass(frozen=True)
class Surface:
    """One input surface: its cases and the property each must hold."""

    name: str
    cases: st.SearchStrategy[Any]
    check: Callable[[Any, Workbench], str]

    def run(self, case: Any, bench: Workbench) -> str:
        """``accepted``, ``refused``, or ``known:<regression test>`` for a case that
        hits a finding already recorded in :data:`KNOWN`; a new finding raises."""
        try:
            return self.check(case, bench)
        except Finding as finding:
            for pattern, test in KNOWN.get(self.name, ()):
                if re.search(pattern, str(finding)):
                    return f"known:{test}"
            raise


SURFACES: tuple[Surface, ...] = (
    Surface("profile", profile_cases, check_profile),
    Surface("world", world_cases, check_world),
    Surface("library", library_cases, check_library),
    Surface("log", log_cases, check_log),
    Surface("cli", cli_cases, check_cli),
    Surface("driver", driver_cases, check_driver),
    Surface("learner", learner_cases, check_learner),
    Surface("learner-changes", learner_changes_cases, check_learner),
    Surface("learner-grasps", learner_grasps_cases, check_learner),
)
BY_NAME: dict[str, Surface] = {s.name: s for s in SURFACES}
