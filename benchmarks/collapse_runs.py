"""Benchmark: full collapse runs over a rigid bed at the paper's parameters (section 5).

Run: python benchmarks/collapse_runs.py [--scenarios trapezoid-rigid rectangle-rigid]
         [--set key=value ...] [--tag NAME] [--out benchmarks/results/collapse]
Each run goes to OUT/TAG/SCENARIO (a normal run directory); OUT/TAG.json collects status,
stop time, front stop time, runout, volume error, wall time, steps and linear solves.
"""

from __future__ import annotations

import argparse
import json
from pathlib import Path

import granflow
from granflow.config import load_config
from granflow.io.run_dir import RunDir, atomic_write_text

KEYS = ["status", "message", "t_final", "steps", "rejected_steps", "nonlinear_iterations",
        "linear_solves", "wall_time_s", "stop_time_s", "front_stop_time_s",
        "front_settle_time_s", "runout_m",
        "wall_height_m", "volume_relative_error", "n_triangles", "n_dofs", "runout_1mm_m",
        "surface_edge_spread", "remeshes"]


def run_variant(tag: str, scenarios: list[str], overrides: list[str], out: Path) -> dict:
    """Run each scenario with ``overrides`` into OUT/TAG/SCENARIO; write OUT/TAG.json."""
    results = {}
    for name in scenarios:
        config = load_config(name, overrides)
        run_dir = granflow.run(config, out=out / tag / name, force=True)
        summary = RunDir.summary(run_dir.root)
        results[name] = {k: summary.get(k) for k in KEYS} | {"overrides": overrides}
        print(tag, name, json.dumps(results[name], indent=1), flush=True)
    atomic_write_text(out / f"{tag}.json", json.dumps(results, indent=2))
    return results


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
