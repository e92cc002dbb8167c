"""How long ``csl --help`` (and a command's ``--help``, and ``csl bt``) takes, and which
imports pay for it.

    python bench/bench_cli_startup.py [--repeat 9] [--top 12] [-- ARGS ...]

Each command line (default: ``--help``, ``run --help``, ``library --help``, ``driver
call --help``, ``bt``: printing the behaviour tree, which builds it) runs ``--repeat`` times as ``python -m csl_cli ARGS`` in a fresh
process; the table gives the median wall time and the median user CPU of those runs.
Then ``python -X importtime -m csl_cli --help`` once: the modules with the largest
cumulative import time, and whether numpy was imported at all. Run it from the
repository root; BENCHMARKS.md, "Start-up", records its figures.
"""

from __future__ import annotations

import argparse
import datetime
import os
import platform
import resource
import statistics
import subprocess
import sys
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
DEFAULT_COMMANDS = ("--help", "run --help", "library --help", "driver call --help", "bt")


def timed(args: list[str]) -> tuple[float, float]:
    """Wall and user-CPU seconds of one ``python -m csl_cli ARGS`` run."""
    before = resource.getrusage(resource.RUSAGE_CHILDREN).ru_utime
    start = time.perf_counter()
    subprocess.run([sys.executable, "-m", "csl_cli", *args], cwd=ROOT, stdout=subprocess.DEVNULL, check=True)
    wall = time.perf_counter() - start
    return wall, resource.getrusage(resource.RUSAGE_CHILDREN).ru_utime - before


def import_times(args: list[str]) -> list[tuple[int, str]]:
    """(cumulative microseconds, module) for every import ``-X importtime`` reports."""
    run = subprocess.run([sys.executable, "-X", "importtime", "-m", "csl_cli", *args], cwd=ROOT,
                         stdout=subprocess.DEVNULL, stderr=subprocess.PIPE, text=True, check=True)
    found = []
    for line in run.stderr.splitlines():
        if not line.startswith("import time:") or "cumulative" in line:
            continue
        _self, cumulative, name = line.removeprefix("import time:").split("|")
        found.append((int(cumulative), name.strip()))
    return found


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--repeat", type=int, default=9, help="runs per command line (default 9)")
    parser.add_argument("--top", type=int, default=12, help="import offenders to list (default 12)")
    parser.add_argument("commands", nargs="*", help="command lines to time (default: %(default)s)",
                        default=list(DEFAULT_COMMANDS))
    options = parser.parse_args()
    print(f"{datetime.date.today()}, {platform.processor() or platform.machine()}, {os.cpu_count()} CPUs, "
          f"Python {platform.python_version()}, {options.repeat} runs each\n")
    print("| command | wall (median) | CPU user (median) |\n|---|---|---|")
    for command in options.commands:
        args = command.split()
        runs = [timed(args) for _ in range(options.repeat)]
        print(f"| `csl {command}` | {statistics.median(w for w, _ in runs):.2f} s | "
              f"{statistics.median(u for _, u in runs):.2f} s |")
    imports = import_times(["--help"])
    print(f"\n`python -X importtime -m csl_cli --help`: {len(imports)} modules; numpy imported: "
          f"{'yes' if any(name == 'numpy' for _, name in imports) else 'no'}; the largest (cumulative):\n")
    for micros, name in sorted(imports, reverse=True)[:options.top]:
        print(f"- {name}: {micros / 1000:.0f} ms")


if __name__ == "__main__":
    main()
