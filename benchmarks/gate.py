"""Benchmark: a gate withdrawn at a finite speed against the instantaneous release.

Run: python benchmarks/gate.py [--cases default tall] [--set key=value ...]
         [--out benchmarks/results/gate]

Two columns: the default collapse (trapezoid-rigid, to t = 2 s at most: the gate lies on its
70-degree front, as the laboratory reservoir's) and a tall rectangle, h0/l0 = 4 (l0 = 10 cm,
h0 = 40 cm, rectangle-rigid otherwise, the gate normal to the bed). Each is run to rest
released at once, with the door of Rousseau et al. (2023), U_inf (1 - exp(-t/tau)) with 0.7
m/s and 0.13 s, and with a constant 0.7 m/s; the gate's friction is the wall's (10.2
degrees).
OUT/gate.json holds each run's status, stop time, runout, the runout's change against the
instantaneous release and the time the gate clears the column; OUT/gate.md the table.
"""

from __future__ import annotations

import argparse
from pathlib import Path

from common.results import read_results, report, write_json, write_markdown

import granflow
from granflow.config import load_config
from granflow.geometry.scene import build_scene
from granflow.io.run_dir import RunDir

CASES = {
    "default": ("trapezoid-rigid", ["time.t_end=2.0"]),   # a gated mass rests after 1.02 s
    "tall": ("rectangle-rigid", ["geometry.width=0.1", "geometry.height=0.4",
                                 "time.t_end=3.0"]),
}
RELEASES = {
    "instantaneous": [],
    "exponential": ["gate.enabled=true", "gate.speed_law=exponential", "gate.speed=0.7",
                    "gate.tau=0.13"],
    "constant": ["gate.enabled=true", "gate.speed_law=constant", "gate.speed=0.7"],
}
KEYS = ["status", "t_final", "steps", "stop_time_s", "runout_m", "wall_height_m", "remeshes",
        "wall_time_s", "volume_relative_error"]


def table(results: dict[str, dict]) -> str:
    lines = ["| column | release | status | stop (s) | runout (m) | runout change | "
             "gate clears the face (s) | wall (s) |", "|---|---|---|---|---|---|---|---|"]
    for r in results.values():
        stop, change, clear = r["stop_time_s"], r.get("runout_change"), r.get("gate_clear_s")
        lines.append(
            f"| {r['case']} | {r['release']} | {r['status']} | "
            f"{'-' if stop is None else f'{stop:.3f}'} | {r['runout_m']:.4f} | "
            f"{'-' if change is None else f'{100 * change:+.1f} %'} | "
            f"{'-' if clear is None else f'{clear:.3f}'} | {r['wall_time_s']:.0f} |")
    return "\n".join(lines) + "\n"


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__)
    parser.add_argument("--cases", nargs="+", default=list(CASES), choices=list(CASES))
    parser.add_argument("--set", dest="extra", action="append", default=[])
    parser.add_argument("--out", type=Path, default=Path("benchmarks/results/gate"))
    args = parser.parse_args()
    store = args.out / "gate.json"
    results = read_results(store)
    for case in args.cases:
        scenario, base = CASES[case]
        for release, door in RELEASES.items():
            overrides = [*base, *door, *args.extra]
            config = load_config(scenario, overrides)
            run_dir = granflow.run(config, out=args.out / "runs" / f"{case}_{release}",
                                   force=True)
            summary = RunDir.summary(run_dir.root)
            entry = {k: summary.get(k) for k in KEYS} | {
                "case": case, "release": release, "scenario": scenario,
                "overrides": overrides}
            gate = build_scene(config.geometry, config.gate).gate
            if gate is not None:              # its opening reaches the top of the face
                entry["gate_clear_s"] = gate.law.open_time(gate.height)
            results[f"{case}_{release}"] = entry
            instant = results.get(f"{case}_instantaneous")
            for r in results.values():
                if r["case"] == case and instant is not None:
                    r["runout_change"] = r["runout_m"] / instant["runout_m"] - 1.0
            report(f"{case} {release}", entry)
            write_json(store, results)
            write_markdown(args.out / "gate.md", table(results))
    print(table(results))


if __name__ == "__main__":
    main()
