"""``--record``, ``--show-status`` and ``csl log`` on a recording, as ``csl run`` runs
them; the options refused in one line; nothing of Foxglove loaded when not asked."""

from __future__ import annotations

import argparse
import re
import subprocess
import sys
from pathlib import Path

import pytest

from csl_cli.args import add_recording_options
from csl_cli.main import build_parser, main
from csl_cli.recording_options import check_recording_options


def _run_args(out: Path, **recording: object) -> argparse.Namespace:
    """``csl run --out OUT`` with the recording options set as their flags would."""
    args = build_parser().parse_args(["run", "--out", str(out), "--no-plots"])
    for name, value in {"record": None, "live": False, "live_port": None, "live_pace": None, "show_status": False,
                        **recording}.items():
        setattr(args, name, value)
    return args


@pytest.mark.slow
def test_a_recorded_run_reads_back_as_the_same_story(tmp_path: Path, capsys) -> None:  # noqa: ANN001
    mcap = tmp_path / "episode.mcap"
    args = _run_args(tmp_path, record=mcap, show_status=True)
    assert args.handler(args) == 0
    out = capsys.readouterr().out
    assert f"recording: {mcap}" in out
    # --show-status: py_trees' tree after each of the lab's seven objects, plain text in a pipe
    assert out.count("{-} retrieve objects [") == 7 and "\x1b[" not in out
    assert "--> LocateObjects [✓] -- 7 objects" in out
    assert mcap.read_bytes()[:5] == b"\x89MCAP"
    assert main(["log", str(tmp_path / "episode.jsonl")]) == 0
    from_jsonl = capsys.readouterr().out
    assert main(["log", str(mcap)]) == 0
    assert capsys.readouterr().out == from_jsonl
    assert main(["log", str(mcap), "--events", "move", "--object", "0"]) == 0
    lines = capsys.readouterr().out.strip().splitlines()
    assert lines[0] == "object 0" and len(lines) > 1
    assert all(" move " in line and re.search(r", waypoints=[1-9]\d*$", line) for line in lines[1:])


def test_a_file_that_is_not_a_recording_is_one_line(tmp_path: Path, capsys) -> None:  # noqa: ANN001
    broken = tmp_path / "broken.mcap"
    broken.write_bytes(b"\x89MCAP0\r\n" + b"\x00" * 40)
    assert main(["log", str(broken)]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and f"{broken}: not a readable MCAP recording" in err[0]


@pytest.mark.parametrize(("given", "message"), [
    ({"live_port": 9000}, "--live-port goes with --live"),
    ({"live_pace": 0.5}, "--live-pace goes with --live"),
    ({"record": Path("/nonexistent/folder/x.mcap")}, "--record: folder /nonexistent/folder does not exist"),
])
def test_recording_options_are_checked_before_anything_runs(tmp_path: Path, given, message) -> None:  # noqa: ANN001
    with pytest.raises(ValueError, match=message):
        check_recording_options(_run_args(tmp_path, **given))


def test_a_record_file_that_cannot_be_made_is_one_line_naming_flag_and_file(tmp_path: Path, capsys) -> None:  # noqa: ANN001
    """The folder is there and writable, the file cannot be made (a name over the
    system's 255 bytes; as root, every ``os.access`` check passes): one line naming
    ``--record``, the file and why, exit 2, before anything is created."""
    record = tmp_path / ("x" * 300 + ".mcap")
    out = tmp_path / "out"
    assert main(["run", "--record", str(record), "--out", str(out), "--no-plots"]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert err == [f"csl: error: --record: cannot create {record}: file name too long"]
    assert list(tmp_path.iterdir()) == []  # neither the out folder nor anything else


def test_a_record_file_that_is_there_is_left_as_it_was(tmp_path: Path) -> None:
    """Checking an existing ``--record`` file neither truncates nor removes it; a new
    one is made to be sure it can be, then removed (the run makes it again)."""
    there = tmp_path / "old.mcap"
    there.write_bytes(b"old")
    check_recording_options(_run_args(tmp_path, record=there))
    check_recording_options(_run_args(tmp_path, record=tmp_path / "new.mcap"))
    assert sorted(p.name for p in tmp_path.iterdir()) == ["old.mcap"] and there.read_bytes() == b"old"


@pytest.mark.parametrize(("argv", "message"), [
    (["--live-port", "70000"], "a port is at most 65535"),
    (["--live-pace", "-1"], "must be a finite number of seconds >= 0"),
    (["--live-pace", "nan"], "must be a finite number of seconds >= 0"),
])
def test_bad_recording_flags_are_refused_while_parsing(argv, message, capsys) -> None:  # noqa: ANN001
    parser = argparse.ArgumentParser(prog="csl run")
    add_recording_options(parser)
    with pytest.raises(SystemExit):
        parser.parse_args(argv)
    assert message in capsys.readouterr().err


@pytest.mark.slow
def test_a_run_without_recording_loads_no_foxglove_nor_mcap() -> None:
    code = ("import sys, csl_cli.commands.episode, csl_cli.commands.log; "
            "print(sorted(m for m in sys.modules if m.split('.')[0] in ('foxglove', 'mcap')))")
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True).stdout
    assert out.strip() == "[]"


def test_a_file_recording_runs_flat_out(tmp_path: Path) -> None:
    from csl_cli.recording_options import open_recording
    from robot_profile import load_profile

    recording = open_recording(_run_args(tmp_path, record=tmp_path / "x.mcap"), load_profile())
    assert recording is not None
    try:
        assert recording.live_pace_s == 0.0 and recording.server is None and recording.mcap == tmp_path / "x.mcap"
    finally:
        recording.close()
    assert open_recording(_run_args(tmp_path), load_profile()) is None
