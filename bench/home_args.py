"""The arguments the onboard benches share: which homes, presets and seeds, how many at once.

``bench_onboard.py`` and ``bench_exploration.py`` run the same grid of episodes (home x
noise preset x seed) and check it the same way; only their default presets differ.
"""

from __future__ import annotations

import argparse
import sys

from experiments.conditions import noise_names  # the benches put the repository on sys.path first


def add_home_arguments(parser: argparse.ArgumentParser, presets: str) -> None:
    """``--homes``, ``--presets`` (default ``presets``), ``--seeds``, ``--jobs``."""
    parser.add_argument("--homes", default="apartment,apartment-2", help="homes, comma-separated")
    parser.add_argument("--presets", default=presets, help=f"noise presets, comma-separated (default {presets})")
    parser.add_argument("--seeds", type=int, default=2, help="seeds 0..N-1 (default 2)")
    parser.add_argument("--jobs", type=int, default=1, help="episodes run at once, each in a process (default 1)")


def home_presets(args: argparse.Namespace, bench: str) -> list[str] | None:
    """The presets asked for; None, after one line on stderr, when a preset is unknown or
    ``--seeds``/``--jobs`` is below 1 (the bench then exits 2)."""
    presets: list[str] = args.presets.split(",")
    unknown = [p for p in presets if p not in noise_names()]
    if unknown or args.seeds < 1 or args.jobs < 1:
        print(f"{bench}: bad arguments: presets {unknown or 'ok'} (valid: {', '.join(noise_names())}), "
              f"--seeds {args.seeds} and --jobs {args.jobs} must be >= 1", file=sys.stderr)
        return None
    return presets
