"""Fuzz every input surface of csl with many cases, outside the suite.

    python bench/fuzz.py [--cases 10000] [--surface NAME ...] [--seed N]

Runs the surfaces of ``tests/fuzz/surfaces.py`` (knowledge profile, world file,
library, episode log, CLI arguments, driver verb payloads, learner requests) in this
process, each against its real parser or handler, ``--cases`` hostile cases each (the
suite runs a few hundred). A case that breaks the property is counted, its first
case is printed (on stderr when first seen, and again at the end), and the surface
goes on; cases that hit a finding already reduced
to a regression test (``tests/fuzz/test_findings.py``) are counted under it. Prints a
Markdown table of counts with the machine and date; ``docs/reliability.md`` keeps the
counts of record. Exit status 1 when a new finding turned up.
"""

from __future__ import annotations

import argparse
import datetime
import logging
import platform
import re
import sys
import tempfile
import time
from collections import Counter
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT))

from hypothesis import HealthCheck, Phase, given, seed, settings  # noqa: E402

from tests.fuzz.surfaces import BY_NAME, SURFACES, Finding, Surface, Workbench  # noqa: E402

KINDS = re.compile(r"[A-Z][A-Za-z]*Error|exit \d+ without an error line|one non-empty line|printed a traceback|"
                   r"non-finite|outside the")


def _kind(finding: str) -> str:
    """What a finding is, without the case's own text: the surface's check, then its
    kind of failure, so one finding seen 500 times with different bytes is one row."""
    check = finding.split(":", 1)[0] if not finding.startswith("csl ") else "csl"
    kinds = KINDS.findall(finding)
    return f"{check}: {kinds[0]}" if kinds else re.sub(r"/\S+|\d+", "#", finding)[:70]


def fuzz(surface: Surface, cases: int, folder: Path, seed_value: int) -> tuple[Counter[str], dict[str, str], float]:
    """(outcome counts, the first case of each new finding by its kind, seconds) for
    one surface. A new finding is counted and the fuzzing goes on, so one finding
    does not hide the next; its first case is kept, unshrunk, for reducing by hand."""
    bench = Workbench(folder / surface.name)
    seen: Counter[str] = Counter()
    first: dict[str, str] = {}

    @seed(seed_value)
    @settings(max_examples=cases, deadline=None, database=None, suppress_health_check=list(HealthCheck),
              phases=[Phase.generate])
    @given(surface.cases)
    def one_case(case: object) -> None:
        try:
            seen[surface.run(case, bench)] += 1
        except Finding as exc:
            kind = _kind(str(exc))
            seen[f"new:{kind}"] += 1
            if kind not in first:  # at once, on stderr: a later crash must not lose it
                first[kind] = f"{str(exc)[:800]} <- {case!r:.300}"
                print(f"{surface.name}: new finding, {kind}: {first[kind]}", file=sys.stderr, flush=True)

    started = time.perf_counter()
    try:
        one_case()
    finally:
        bench.close()
    return seen, first, time.perf_counter() - started


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--cases", type=int, default=10_000, help="cases per surface (default 10000)")
    parser.add_argument("--surface", action="append", choices=sorted(BY_NAME), help="only this surface (repeatable)")
    parser.add_argument("--seed", type=int, default=0, help="Hypothesis seed (default 0)")
    args = parser.parse_args(argv)
    logging.disable(logging.WARNING)  # a refused case's reason in a node's log is expected: the table is the output
    if args.cases < 1:
        parser.error("--cases must be at least 1")
    chosen = [BY_NAME[name] for name in args.surface] if args.surface else list(SURFACES)
    print(f"fuzz: {args.cases} cases per surface, seed {args.seed}, {platform.machine()} "
          f"{platform.python_implementation()} {platform.python_version()}, "
          f"{datetime.datetime.now(datetime.timezone.utc):%Y-%m-%d %H:%M} UTC\n")
    print("| surface | cases | accepted | refused | known findings (cases) | new findings (cases) | seconds |")
    print("|---|---:|---:|---:|---|---|---:|")
    found: dict[str, str] = {}
    with tempfile.TemporaryDirectory(prefix="csl-fuzz-") as folder:
        for surface in chosen:
            seen, first, seconds = fuzz(surface, args.cases, Path(folder), args.seed)
            listed = {prefix: ", ".join(f"{k.removeprefix(prefix)} ({n})" for k, n in sorted(seen.items())
                                        if k.startswith(prefix)) or "-" for prefix in ("known:", "new:")}
            print(f"| {surface.name} | {sum(seen.values())} | {seen['accepted']} | {seen['refused']} | "
                  f"{listed['known:']} | {listed['new:'].replace('|', '/')} | {seconds:.0f} |", flush=True)
            found.update({f"{surface.name}: {kind}": case for kind, case in first.items()})
    for kind, case in found.items():
        print(f"\nnew finding, {kind}\n  first case: {case}")
    return 1 if found else 0


if __name__ == "__main__":
    sys.exit(main())
