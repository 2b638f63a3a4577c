"""Benchmark: full collapse runs over a rigid bed at the paper's parameters (section 5).

Run: python benchmarks/collapse_runs.py [--scenarios trapezoid-rigid rectangle-rigid]
         [--set key=value ...] [--tag NAME] [--out benchmarks/results/collapse]
Each run goes to OUT/TAG/SCENARIO (a normal run directory); OUT/TAG.json collects status,
stop time, front stop time, runout, volume error, wall time, steps and linear solves.
"""

from __future__ import annotations

import argparse
from pathlib import Path

from common.runs import run_variant


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__)
    parser.add_argument("--scenarios", nargs="+", default=["trapezoid-rigid", "rectangle-rigid"])
    parser.add_argument("--set", dest="overrides", action="append", default=[])
    parser.add_argument("--tag", default="paper")
    parser.add_argument("--out", type=Path, default=Path("benchmarks/results/collapse"))
    args = parser.parse_args()
    run_variant(args.tag, args.scenarios, args.overrides, args.out)


if __name__ == "__main__":
    main()
