"""``csl library export --columnar``: the version 3 file a big library loads fast from."""

from __future__ import annotations

import json

from csl_cli.main import main
from learner.library.format import read_library_json, write_library_json
from learner.library.store import LibraryStore
from tests.learner.fixtures import four_objects


def test_a_columnar_export_imports_back_identical(tmp_path, capsys) -> None:  # noqa: ANN001
    source = tmp_path / "lib.json"
    write_library_json(source, four_objects())
    db, out, again = tmp_path / "a.sqlite", tmp_path / "out.json", tmp_path / "b.sqlite"
    assert main(["library", "--db", str(db), "import", str(source)]) == 0
    assert main(["library", "--db", str(db), "export", "--columnar", str(out)]) == 0
    assert "exported 4 descriptions" in capsys.readouterr().out
    document = json.loads(out.read_text())
    assert document["version"] == 3 and len(document["descriptions"]["id"]) == 4
    assert main(["library", "--db", str(again), "import", str(out)]) == 0
    with LibraryStore(db) as first, LibraryStore(again) as second:
        assert second.descriptions() == first.descriptions()
    assert list(read_library_json(out)) == list(read_library_json(source))


def test_the_default_export_stays_the_readable_version_2(tmp_path) -> None:  # noqa: ANN001
    source, db, out = tmp_path / "lib.json", tmp_path / "a.sqlite", tmp_path / "out.json"
    write_library_json(source, four_objects())
    assert main(["library", "--db", str(db), "import", str(source)]) == 0
    assert main(["library", "--db", str(db), "export", str(out)]) == 0
    assert json.loads(out.read_text())["version"] == 2
