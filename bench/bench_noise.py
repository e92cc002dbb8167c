"""Success and robot time per object under each noise preset (docs/simulator.md, Noise).

The built-in lab's 7 unseen test objects, the shipped library (trained in the simulator
on Table 3), the default criterion and control strategies, the same seeds for every
preset. ``--scale`` sweeps one preset's noise level instead (NoiseConfig.scaled);
``--ablate`` starts from ``mild`` and sets one field at a time to a preset's value, to
see which effect costs what.
The paper: over 80% success, about 12 minutes of robot time per object.

    python bench/bench_noise.py [--seeds 4] [--presets clean,mild,paper,harsh] [--jobs 2]
    python bench/bench_noise.py --scale paper:0,0.5,1,2
    python bench/bench_noise.py --ablate harsh
"""

from __future__ import annotations

import argparse
import dataclasses
import statistics
import sys
import tempfile
from concurrent.futures import ProcessPoolExecutor
from dataclasses import dataclass, fields
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT))

from executive.defaults import EXAMPLE_LIBRARY  # noqa: E402
from executive.executive import Executive  # noqa: E402
from reporting.report import Truth, rows  # noqa: E402
from hero_driver.sim.noise import NOISE_PRESETS, NoiseConfig  # noqa: E402
from hero_driver.sim_driver import SimulatedHero  # noqa: E402
from learner.library.format import read_library_json  # noqa: E402
from learner.service.local import LocalLearner  # noqa: E402


@dataclass(frozen=True)
class Outcome:
    """One episode's objects under one noise setting."""

    label: str
    seed: int
    correct: int
    objects: int
    robot_s: float  # summed over the objects' ledgers (moving + sensing + grasping)
    drift_in: float  # the dead-reckoning offset at the end of the episode


def episode(label: str, noise: NoiseConfig, seed: int) -> Outcome:
    hero = SimulatedHero("bench", world="lab", seed=seed, noise=noise)
    start = hero.truth()
    with tempfile.TemporaryDirectory() as tmp:
        learner = LocalLearner(Path(tmp) / "lib.sqlite", seed_library=read_library_json(EXAMPLE_LIBRARY))
        ex = Executive(hero, learner)
        result = ex.run()
        ex.shutdown()
    now = hero.truth()
    truths = [Truth(n.entry_id, tuple(g.procedure for g in n.grasps), s.x_in, s.y_in) for s, n in zip(start, now)]
    table = rows(result.objects, truths)
    return Outcome(label, seed, sum(bool(r.correct) for r in table), len(start),
                   sum(r.robot_s for r in table), hero.world.drift.size_in)


def _settings(args: argparse.Namespace) -> list[tuple[str, NoiseConfig]]:
    if args.scale:
        name, _, factors = args.scale.partition(":")
        base = NoiseConfig.preset(name)
        return [(f"{name} x{f}", base.scaled(float(f))) for f in factors.split(",")]
    if args.ablate:
        mild, target = NoiseConfig.preset("mild"), NoiseConfig.preset(args.ablate)
        changed = [f.name for f in fields(NoiseConfig) if getattr(target, f.name) != getattr(mild, f.name)]
        return [("mild", mild)] + [(f"mild + {args.ablate} {name}={getattr(target, name)}",
                                    dataclasses.replace(mild, **{name: getattr(target, name)})) for name in changed]
    return [(name, NoiseConfig.preset(name)) for name in args.presets.split(",")]


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--seeds", type=int, default=4)
    ap.add_argument("--presets", default=",".join(NOISE_PRESETS))
    ap.add_argument("--scale", default=None, metavar="PRESET:F1,F2,...")
    ap.add_argument("--ablate", default=None, metavar="PRESET")
    ap.add_argument("--jobs", type=int, default=2)
    args = ap.parse_args()
    try:
        settings = _settings(args)
    except ValueError as exc:
        ap.error(str(exc))
    jobs = [(label, noise, seed) for label, noise in settings for seed in range(args.seeds)]
    with ProcessPoolExecutor(max_workers=args.jobs) as pool:
        outcomes = list(pool.map(episode, *zip(*jobs)))
    print(f"lab, 7 test objects x {args.seeds} seeds per setting, shipped library, default criterion")
    print("| noise | correct | robot min / object (mean) | per-episode range | drift at end (in) |")
    print("|---|---|---|---|---|")
    for label, _ in settings:
        mine = [o for o in outcomes if o.label == label]
        ok, n = sum(o.correct for o in mine), sum(o.objects for o in mine)
        per_object = [o.robot_s / o.objects / 60 for o in mine]
        print(f"| {label} | {ok}/{n} ({100 * ok / n:.0f}%) | {sum(o.robot_s for o in mine) / n / 60:.1f} | "
              f"{min(per_object):.1f}-{max(per_object):.1f} | {statistics.mean(o.drift_in for o in mine):.1f} |")


if __name__ == "__main__":
    main()
