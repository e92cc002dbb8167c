"""A library as a JSON file: the row layout (version 2) against the columnar one (3).

Synthetic libraries (``synthetic_library`` perturbed from the shipped one) are written
both ways into a temporary folder and read back with ``read_library_json``; per size
and layout: the file's size, ``json.loads`` alone (the floor any reader pays), the whole
read (wall and CPU medians: the machine is shared, so CPU time is the steadier figure)
and the memory the loaded library holds (tracemalloc, parse freed). Both layouts must
read back equal to the library written, or the bench stops.

    python bench/bench_library_json.py [--max 100000] [--repeats 3]
"""

from __future__ import annotations

import argparse
import datetime
import gc
import json
import statistics
import sys
import tempfile
import time
from collections.abc import Callable
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT))

from executive.defaults import EXAMPLE_LIBRARY, KNOWLEDGE  # noqa: E402
from robot_profile import load_knowledge  # noqa: E402
from learner.library.format import read_library_json, write_library_json  # noqa: E402
from learner.library.synthetic import synthetic_library  # noqa: E402

from bench_library_load import held_bytes  # noqa: E402  (bench/ is the script's folder)

SIZES = (1_000, 10_000, 100_000)


def medians(run: Callable[[], object], repeats: int) -> tuple[float, float]:
    """Median wall and CPU seconds of ``run`` (its result freed outside the timing)."""
    wall, cpu = [], []
    for _ in range(repeats):
        gc.collect()
        began, began_cpu = time.perf_counter(), time.process_time()
        result = run()
        wall.append(time.perf_counter() - began)
        cpu.append(time.process_time() - began_cpu)
        del result
    return statistics.median(wall), statistics.median(cpu)


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--max", type=int, default=SIZES[-1], help=f"largest size (sizes: {SIZES})")
    ap.add_argument("--repeats", type=int, default=3, help="runs per measure (median)")
    args = ap.parse_args()
    if args.repeats < 1:
        ap.error(f"--repeats must be at least 1, got {args.repeats}")
    knowledge = load_knowledge(KNOWLEDGE)
    base = read_library_json(EXAMPLE_LIBRARY)
    print(f"date: {datetime.date.today().isoformat()}; command: python bench/bench_library_json.py "
          f"--max {args.max} --repeats {args.repeats}")
    print("| descriptions | layout | file MB | json.loads s (CPU) | read s wall | read s CPU | ratio (CPU) | held MB |")
    print("|---|---|---:|---:|---:|---:|---:|---:|")
    with tempfile.TemporaryDirectory() as folder:
        for n in (s for s in SIZES if s <= args.max):
            library = synthetic_library(knowledge, n, 0, base=base)
            rows = []
            for layout, columnar in (("rows (v2)", False), ("columnar (v3)", True)):
                path = Path(folder) / f"library-{n}-{'v3' if columnar else 'v2'}.json"
                write_library_json(path, library, columnar=columnar)
                if read_library_json(path) != library:
                    sys.exit(f"{n}: the {layout} file reads back different")
                _, parse = medians(lambda: json.loads(path.read_text(encoding="utf-8")), args.repeats)  # noqa: B023
                wall, cpu = medians(lambda: read_library_json(path), args.repeats)  # noqa: B023
                rows.append((layout, path.stat().st_size, parse, wall, cpu, held_bytes(lambda: read_library_json(path))))  # noqa: B023
                path.unlink()
            for layout, size, parse, wall, cpu, held in rows:
                print(f"| {n:,} | {layout} | {size / 1e6:.1f} | {parse:.2f} | {wall:.2f} | {cpu:.2f} "
                      f"| {rows[0][4] / cpu:.1f}x | {held / 1e6:.0f} |", flush=True)
            del library


if __name__ == "__main__":
    main()
