"""Loading a library: today's reader against the one it replaced, in the same process.

Synthetic libraries (``synthetic_library`` perturbed from the shipped one) of 1k, 10k
and 100k descriptions are written as JSON and into a SQLite store in a temporary
folder, then loaded by:

- ``baseline``: a copy of the reader before the faster reader (every position parsed and
  validated, every field's error text built, observations sorted by ``__lt__``);
- ``now``: ``read_library_json`` / ``LibraryStore.descriptions`` (the store read through
  its observation codes, docs/library-format.md);

each the median of a few runs, with ``json.loads`` alone timed as the floor any JSON
reader pays, and the memory held by the loaded library (tracemalloc, parse excluded).
Both readers must give equal libraries, or the bench stops. Last, the one-off upgrade
of a store from before observation codes (opening it, codes written), once per size.
"""

from __future__ import annotations

import argparse
import datetime
import gc
import json
import math
import shutil
import sqlite3
import statistics
import sys
import tempfile
import time
import tracemalloc
from collections.abc import Callable
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT))

from executive.defaults import EXAMPLE_LIBRARY, KNOWLEDGE  # noqa: E402
from robot_profile import load_knowledge  # noqa: E402
from learner.appearance import Appearance, appearance_from_json  # noqa: E402
from learner.description import ObjectDescription, Observation  # noqa: E402
from learner.library.format import read_library_json, write_library_json  # noqa: E402
from learner.library.store import LibraryStore  # noqa: E402
from learner.library.synthetic import synthetic_library  # noqa: E402
from learner.position import Position  # noqa: E402

SIZES = (1_000, 10_000, 100_000)


# -- the reader before the faster reader, kept verbatim in spirit for the comparison ----------
def _baseline_slot(value: object, where: str) -> float | None:
    if value == "*" or value is None:
        return None
    if isinstance(value, bool) or not isinstance(value, (int, float)):
        raise ValueError(f"{where}: expected a number or \"*\", got {value!r}")
    if not math.isfinite(value):
        raise ValueError(f"{where}: expected a finite number, got {value!r}")
    return float(value)


def _baseline_position(value: object, where: str) -> Position:
    if not isinstance(value, (list, tuple)) or len(value) != 2:
        raise ValueError(f"{where}: a position is [distance, orientation], got {value!r}")
    p = Position(_baseline_slot(value[0], f"{where}[0]"), _baseline_slot(value[1], f"{where}[1]"))
    if p.distance_in is not None and p.distance_in < 0:
        raise ValueError(f"{where}: distance must not be negative")
    if p.orientation_deg is not None and not 0 <= p.orientation_deg < 360:
        raise ValueError(f"{where}: orientation must be in [0, 360) degrees")
    return p


def _baseline_description(entry: dict, where: str, version: int) -> ObjectDescription:
    keys = {"id", "grasp", "grasp_position", "features"} | ({"appearance"} if version >= 2 else set())
    unknown = sorted(set(entry) - keys)
    if unknown:
        raise ValueError(f"{where}: unknown key {unknown[0]!r}")
    for key in ("id", "grasp"):
        if not isinstance(entry.get(key), str) or not entry[key]:
            raise ValueError(f"{where}: missing or empty string field '{key}'")
    where = f"{where} ({entry['id']})"
    grasp_position = _baseline_position(entry["grasp_position"], f"{where}: grasp_position")
    observations = []
    for j, f in enumerate(entry.get("features", [])):
        fw = f"{where}: features[{j}]"
        unknown = sorted(set(f) - {"feature", "position", "value"})
        if unknown:
            raise ValueError(f"{fw}: unknown key {unknown[0]!r}")
        if not isinstance(f.get("feature"), str) or not f["feature"]:
            raise ValueError(f"{fw}: missing field 'feature'")
        value = f.get("value")
        if isinstance(value, bool) or not isinstance(value, (int, float)) or not math.isfinite(value):
            raise ValueError(f"{fw}: 'value' must be a finite number, got {value!r}")
        observations.append(Observation(f["feature"], _baseline_position(f["position"], f"{fw}: position"),
                                        float(value)))
    appearance = (appearance_from_json(entry["appearance"], f"{where}: appearance")
                  if "appearance" in entry else None)
    return ObjectDescription(entry["id"], entry["grasp"], grasp_position, tuple(sorted(observations)), appearance)


def baseline_read(path: Path) -> list[ObjectDescription]:
    data = json.loads(path.read_text(encoding="utf-8"))
    return [_baseline_description(e, f"{path}: descriptions[{i}]", data["version"])
            for i, e in enumerate(data["descriptions"])]


def baseline_store(store: LibraryStore) -> list[ObjectDescription]:
    db = store._db  # noqa: SLF001 - the bench reads the same tables the old code read
    rows = db.execute("SELECT seq, id, grasp, grasp_distance_in, grasp_orientation_deg, appearance_round,"
                      " appearance_area_in2, appearance_elongation FROM descriptions ORDER BY seq").fetchall()
    obs: dict[int, list[Observation]] = {}
    for seq, feature, d, o, v in db.execute(
            "SELECT description_seq, feature, distance_in, orientation_deg, value FROM observations"):
        obs.setdefault(seq, []).append(Observation(feature, Position(d, o), v))
    return [ObjectDescription(i, g, Position(d, o), tuple(sorted(obs.get(seq, []))),
                              None if r is None else Appearance(bool(r), a, e))
            for seq, i, g, d, o, r, a, e in rows]


def upgrade_seconds(db: Path, library: list[ObjectDescription]) -> float:
    """Open a copy of ``db`` made as the previous csl left it (no codes): the upgrade."""
    old = db.with_name(db.stem + "-before-codes.sqlite")
    shutil.copy(db, old)
    with sqlite3.connect(old) as raw:
        raw.execute("ALTER TABLE descriptions DROP COLUMN observation_codes")
        raw.execute("DROP TABLE observation_codes")
    raw.close()
    began = time.perf_counter()
    with LibraryStore(old) as store:
        took = time.perf_counter() - began
        if store.descriptions() != library:
            sys.exit(f"{len(library)}: the upgraded store differs")
    old.unlink()
    return took


# -- measuring ----------------------------------------------------------------------
def median_time(run: Callable[[], object], repeats: int) -> float:
    times = []
    for _ in range(repeats):
        gc.collect()
        began = time.perf_counter()
        run()
        times.append(time.perf_counter() - began)
    return statistics.median(times)


def held_bytes(load: Callable[[], list[ObjectDescription]]) -> int:
    """Bytes still allocated once the library is loaded (the parsed JSON is freed)."""
    gc.collect()
    tracemalloc.start()
    library = load()
    gc.collect()
    held = tracemalloc.get_traced_memory()[0]
    tracemalloc.stop()
    del library
    return held


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--max", type=int, default=SIZES[-1], help=f"largest size (sizes: {SIZES})")
    ap.add_argument("--repeats", type=int, default=3, help="runs per measure (median)")
    args = ap.parse_args()
    if args.repeats < 1:
        ap.error(f"--repeats must be at least 1, got {args.repeats}")
    knowledge = load_knowledge(KNOWLEDGE)
    base = read_library_json(EXAMPLE_LIBRARY)
    print(f"date: {datetime.date.today().isoformat()}; command: python bench/bench_library_load.py "
          f"--max {args.max} --repeats {args.repeats}")
    print("| descriptions | store | json.loads | baseline s | now s | speed-up | baseline MB | now MB |")
    print("|---|---|---|---|---|---|---|---|")
    upgrades = []
    with tempfile.TemporaryDirectory() as folder:
        for n in (s for s in SIZES if s <= args.max):
            library = synthetic_library(knowledge, n, 0, base=base)
            path = Path(folder) / f"library-{n}.json"
            write_library_json(path, library)
            db = Path(folder) / f"library-{n}.sqlite"
            with LibraryStore(db) as store:
                store.add(library)
            if baseline_read(path) != read_library_json(path) or read_library_json(path) != library:
                sys.exit(f"{n}: the readers disagree")
            parse = median_time(lambda: json.loads(path.read_text(encoding="utf-8")), args.repeats)  # noqa: B023
            rows = [("JSON", lambda: baseline_read(path), lambda: read_library_json(path))]  # noqa: B023
            with LibraryStore(db) as store:
                if baseline_store(store) != store.descriptions():
                    sys.exit(f"{n}: the store readers disagree")
                rows.append(("SQLite", lambda: baseline_store(store), store.descriptions))  # noqa: B023
                for kind, old, new in rows:
                    t_old, t_new = median_time(old, args.repeats), median_time(new, args.repeats)
                    m_old, m_new = held_bytes(old), held_bytes(new)
                    print(f"| {n:,} | {kind} | {parse if kind == 'JSON' else math.nan:.2f} | {t_old:.2f} | "
                          f"{t_new:.2f} | {t_old / t_new:.1f}x | {m_old / 1e6:.0f} | {m_new / 1e6:.0f} |", flush=True)
            upgrades.append((n, upgrade_seconds(db, library)))
            del library
    print()
    print("| descriptions | upgrade of a store from before codes (once) s |")
    print("|---|---|")
    for n, took in upgrades:
        print(f"| {n:,} | {took:.2f} |")


if __name__ == "__main__":
    main()
