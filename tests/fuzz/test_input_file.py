"""``learner.library.input_file``: a file a person named is read only when it is a regular
file, so the library file and the episode log refuse a FIFO, a device, a folder or
an impossible name in one line, at once (the finding ``test_log_of_a_fifo_does_not_hang``)."""

from __future__ import annotations

import os
from pathlib import Path

import pytest

from learner.library.input_file import NotAFile, open_input, read_input


def _thing(tmp_path: Path, kind: str) -> Path:
    if kind == "fifo":
        os.mkfifo(tmp_path / "fifo")
        return tmp_path / "fifo"
    return {"missing": tmp_path / "missing.json", "folder": tmp_path, "device": Path("/dev/zero"),
            "long": tmp_path / ("n" * 300)}[kind]


@pytest.mark.parametrize(("kind", "says"), [
    ("missing", "missing.json: library file not found"),
    ("folder", ": is a folder, not a library file"),
    ("fifo", "fifo: is a device or a pipe, not a library file"),  # open() would wait for a writer
    ("device", "/dev/zero: is a device or a pipe, not a library file"),  # read() would never end
    ("long", ": cannot open the library file: File name too long"),
])
def test_what_is_not_a_regular_file_is_one_line(tmp_path: Path, kind: str, says: str) -> None:
    with pytest.raises(NotAFile) as refused:
        open_input(_thing(tmp_path, kind), "library file")
    assert str(refused.value).endswith(says) and "\n" not in str(refused.value)


def test_the_library_file_reader_goes_through_it(tmp_path: Path) -> None:
    from learner.library.format import read_library_json

    with pytest.raises(ValueError, match="is a device or a pipe, not a library file"):
        read_library_json(_thing(tmp_path, "fifo"))


@pytest.mark.parametrize(("size", "limit", "kept"), [(10, None, 10), (10, 10, 10), (11, 10, None), (0, 0, 0)])
def test_a_limit_reads_one_byte_past_it_at_most(tmp_path: Path, size: int, limit: int | None,
                                                kept: int | None) -> None:
    path = tmp_path / "f.jsonl"
    path.write_bytes(b"x" * size)
    with open_input(path, "episode log") as stream:
        if kept is None:
            with pytest.raises(NotAFile, match=f"more than {limit} bytes, too large for an episode log$"):
                read_input(stream, path, "episode log", limit)
            assert stream.tell() == limit + 1
        else:
            assert read_input(stream, path, "episode log", limit) == b"x" * kept
