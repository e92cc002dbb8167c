"""A run that fails before its first episode leaves nothing behind that it made: no
empty ``--out`` folder, no empty ``episode.jsonl`` or recording; what was there before
(the last run's log) stays as it was (csl_cli/run_output.py)."""

from __future__ import annotations

import socket
from pathlib import Path

import pytest

from csl_cli.main import main
from csl_cli.run_output import taken_back_unless_started
from executive.episode_log import EpisodeLog


def _tree(folder: Path) -> dict[str, bytes | None]:
    """Every entry under ``folder``, a file with its bytes, a folder as None."""
    return {str(p.relative_to(folder)): None if p.is_dir() else p.read_bytes() for p in sorted(folder.rglob("*"))}


def _one_error_line(capsys: pytest.CaptureFixture[str]) -> str:
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1, err
    return err[0]


def test_a_bad_library_leaves_no_out_folder(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    """The library is read after the out folder is made: the folder and the two
    parents made for it go again."""
    library = tmp_path / "not-a-library.sqlite"
    library.write_text("garbage")
    out = tmp_path / "runs" / "today" / "out"
    assert main(["run", "--no-plots", "--library", str(library), "--out", str(out)]) == 2
    assert "not a csl library database" in _one_error_line(capsys)
    assert _tree(tmp_path) == {"not-a-library.sqlite": b"garbage"}


def test_a_live_port_in_use_leaves_no_log_nor_recording(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    """The live view is opened after the library, the driver and the episode log, and
    the MCAP file is made before the port is bound: the port in use takes back the
    folder, the log never made and the recording."""
    out, record = tmp_path / "out", tmp_path / "run.mcap"
    with socket.socket() as taken:
        taken.bind(("127.0.0.1", 0))
        taken.listen()
        port = taken.getsockname()[1]
        argv = ["run", "--no-plots", "--library", str(tmp_path / "lib.sqlite"), "--out", str(out),
                "--record", str(record), "--live", "--live-port", str(port)]
        assert main(argv) == 2
    assert _one_error_line(capsys).startswith(f"csl: error: --live-port {port}: cannot serve the live view")
    assert sorted(_tree(tmp_path)) == ["lib.sqlite"]  # the library the run named stays: it is the user's


def test_a_bad_world_leaves_the_last_runs_log_as_it_was(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    """A world file the simulator (the driver) refuses, given after a run that left its
    log and plots: they stay, byte for byte, and nothing is added."""
    world = tmp_path / "broken-world.json"
    world.write_text('{"objects": 3}')
    out = tmp_path / "out"
    out.mkdir()
    (out / "episode.jsonl").write_text('{"tick": 1, "event": "episode_end"}\n')
    (out / "map.png").write_bytes(b"png")
    before = _tree(tmp_path)
    argv = ["run", "--no-plots", "--library", str(tmp_path / "lib.sqlite"), "--world", str(world),
            "--out", str(out), "--record", str(tmp_path / "run.mcap")]
    assert main(argv) == 2
    assert "broken-world.json" in _one_error_line(capsys)
    after = _tree(tmp_path)
    after.pop("lib.sqlite")  # the library the run named is made when it opens, before the world is read
    assert after == before


def test_what_a_started_run_made_is_kept(tmp_path: Path) -> None:
    """Once the log holds an event the episode has begun: a failure then keeps
    everything, the log first (the evidence of what happened)."""
    out = tmp_path / "new" / "out"
    with pytest.raises(RuntimeError), taken_back_unless_started(out, out / "episode.jsonl"):
        out.mkdir(parents=True)
        (out / "library.sqlite").write_bytes(b"db")
        log = EpisodeLog(out / "episode.jsonl")
        log.event("episode_end", status="FAILURE", ticks=1)
        log.close()
        raise RuntimeError("the robot fell over")
    assert sorted(p.name for p in out.iterdir()) == ["episode.jsonl", "library.sqlite"]


def test_before_the_first_event_everything_new_goes(tmp_path: Path) -> None:
    """Before the first event the log is not even made; new files, new folders and the
    parents made go, an existing parent stays."""
    out = tmp_path / "a" / "b"
    record = tmp_path / "run.mcap"
    with pytest.raises(KeyboardInterrupt), taken_back_unless_started(out, out / "episode.jsonl", [record]):
        EpisodeLog(out / "episode.jsonl")  # made, never written
        (out / "plots").mkdir(parents=True)
        (out / "plots" / "map.png").write_bytes(b"png")
        record.write_bytes(b"")
        raise KeyboardInterrupt
    assert list(tmp_path.iterdir()) == []


def test_a_run_that_returns_keeps_what_it_made(tmp_path: Path) -> None:
    out = tmp_path / "out"
    with taken_back_unless_started(out, out / "episode.jsonl"):
        out.mkdir()
        (out / "map.png").write_bytes(b"png")
    assert [p.name for p in out.iterdir()] == ["map.png"]
