"""Benchmark: full collapse runs at the paper's parameters (section 5), and two checkouts'
runs compared.

Run: python benchmarks/collapse_runs.py [--scenarios trapezoid-rigid rectangle-rigid]
         [--set key=value ...] [--tag NAME] [--out benchmarks/results/collapse]
     python benchmarks/collapse_runs.py --compare BEFORE AFTER [--scenarios ...]
Each run goes to OUT/TAG/SCENARIO (a normal run directory); OUT/TAG.json collects status,
stop time, front stop time, runout, volume error, wall time, steps and linear solves. Run
with another checkout's source first (``PYTHONPATH=OLD/src``) to tag its runs; --compare
then runs nothing and writes OUT/BEFORE-vs-AFTER.json: both summaries' figures and the
mean and max distance between the two runs' free surfaces at every output time.
"""

from __future__ import annotations

import argparse
import json
from pathlib import Path

from common.results import write_json
from common.runs import COLLAPSE_KEYS, flow_duration, run_variant, surfaces_m

from granflow.io.run_dir import RunDir

LAYER_KEYS = ["layer_displaced_area_m2", "layer_mobilised_area_max_m2",
              "layer_displaced_volume_m3", "layer_mobilised_volume_max_m3"]


def compare(before: str, after: str, scenarios: list[str], out: Path) -> dict:
    """OUT/BEFORE/SCENARIO against OUT/AFTER/SCENARIO, into OUT/BEFORE-vs-AFTER.json."""
    result = {}
    for name in scenarios:
        first, second = out / before / name, out / after / name
        figures = {tag: {k: RunDir.summary(root).get(k) for k in COLLAPSE_KEYS + LAYER_KEYS}
                   | {"duration_s": flow_duration(root)}
                   for tag, root in ((before, first), (after, second))}
        changes = {k: figures[after][k] / figures[before][k] - 1
                   for k in ("runout_m", "duration_s", *LAYER_KEYS)
                   if figures[before].get(k) and figures[after].get(k) is not None}
        result[name] = figures | {"relative_changes": changes,
                                  "free_surfaces": surfaces_m(first, second)}
        print(name, json.dumps(result[name], indent=1), flush=True)
    write_json(out / f"{before}-vs-{after}.json", result)
    return result


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__)
    parser.add_argument("--scenarios", nargs="+", default=["trapezoid-rigid", "rectangle-rigid"])
    parser.add_argument("--set", dest="overrides", action="append", default=[])
    parser.add_argument("--tag", default="paper")
    parser.add_argument("--compare", nargs=2, metavar=("BEFORE", "AFTER"))
    parser.add_argument("--out", type=Path, default=Path("benchmarks/results/collapse"))
    args = parser.parse_args()
    if args.compare:
        compare(*args.compare, args.scenarios, args.out)
    else:
        run_variant(args.tag, args.scenarios, args.overrides, args.out)


if __name__ == "__main__":
    main()
