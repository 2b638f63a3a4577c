"""Benchmark: the effect of a channel's side-wall friction on the collapses.

Run: python benchmarks/side_walls.py [--width 0.1] [--angle 10.2]
         [--out benchmarks/results/side_walls]

The default trapezoid (and the rectangle) on the rigid bed, run to rest
(time.stop_at_rest), without and with side walls (boundary.channel_width = --width, the
paper's 10 cm channel; boundary.side_wall_friction_deg = --angle, the paper's wall friction
of the left wall), side by side: runout, stop time (all cells slower than 1 mm/s), the
time the front stops, the deposit's height at the wall. Writes OUT/side_walls.json, .md.
"""

from __future__ import annotations

import argparse
from pathlib import Path

import numpy as np
from common.results import report, write_results
from common.runs import distances_mm

import granflow
from granflow.config import load_config
from granflow.io import profiles
from granflow.io.run_dir import RunDir

KEYS = ["status", "stop_time_s", "front_stop_time_s", "runout_m", "wall_height_m", "steps",
        "wall_time_s"]


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__)
    parser.add_argument("--width", type=float, default=0.1)
    parser.add_argument("--angle", type=float, default=10.2)
    parser.add_argument("--scenarios", nargs="+", default=["trapezoid-rigid", "rectangle-rigid"])
    parser.add_argument("--out", type=Path, default=Path("benchmarks/results/side_walls"))
    args = parser.parse_args()
    walls = [f"boundary.channel_width={args.width!r}",
             f"boundary.side_wall_friction_deg={args.angle!r}"]
    rows = []
    for scenario in args.scenarios:
        for label, extra in (("no side walls", []), ("side walls", walls)):
            config = load_config(scenario, ["time.stop_at_rest=true", "time.t_end=2.0",
                                            *extra])
            name = f"{scenario}_{'walls' if extra else 'plain'}"
            run_dir = granflow.run(config, out=args.out / "runs" / name, force=True)
            summary = RunDir.summary(run_dir.root)
            rows.append({"scenario": scenario, "case": label,
                         **{k: summary.get(k) for k in KEYS}})
            report("", rows[-1])
        plain, walled = (args.out / "runs" / f"{scenario}_{k}" for k in ("plain", "walls"))
        rows[-1]["free_surface_vs_plain_mm"] = distances_mm(plain, walled)
        interfaces = (profiles.curves(plain, "interface"),
                      profiles.curves(walled, "interface"))
        rows[-1]["interface_vs_plain_mm"] = distances_mm(plain, walled, "interface")
        rows[-1]["interface_rise_mm"] = rise(*interfaces)
        report("", rows[-1])
    write(args.out, rows, args.width, args.angle)


def rise(plain: dict[float, np.ndarray], walled: dict[float, np.ndarray]) -> dict[str, float]:
    """Mean of z_walls - z_plain (mm) of the interfaces over the stations both define."""
    out = {}
    for t in plain:
        if t in walled:
            a, b = plain[t], walled[t]
            lo, hi = max(a[0, 0], b[0, 0]), min(a[-1, 0], b[-1, 0])
            x = np.linspace(lo, hi, 200)
            out[f"{t:g}"] = round(1e3 * float(np.mean(np.interp(x, *b.T) - np.interp(x, *a.T))),
                                  2)
    return out


def write(out: Path, rows: list[dict], width: float, angle: float) -> None:
    def fmt(x: float | None, digits: int) -> str:
        return "-" if x is None else f"{x:.{digits}f}"

    lines = [f"Channel width {width} m, side-wall friction {angle} deg:", "",
             "| scenario | case | runout (m) | stop (s) | front stops (s) | height at wall (m) |",
             "|---|---|---|---|---|---|"]
    lines += [f"| {r['scenario']} | {r['case']} | {fmt(r['runout_m'], 4)} | "
              f"{fmt(r['stop_time_s'], 3)} | {fmt(r['front_stop_time_s'], 3)} | "
              f"{fmt(r['wall_height_m'], 4)} |" for r in rows]
    for r in rows:
        if r.get("interface_vs_plain_mm"):
            lines += ["", f"{r['scenario']}, with against without side walls, mean/max (mm) "
                      "at the output times:"]
            for key in ("free_surface_vs_plain_mm", "interface_vs_plain_mm"):
                lines.append(f"- {key[:-12]}: " + ", ".join(
                    f"{t} s: {a}/{b}" for t, (a, b) in r[key].items()))
            lines.append("- interface rise with walls (mean, mm): " + ", ".join(
                f"{t} s: {v}" for t, v in r["interface_rise_mm"].items()))
    write_results(out, "side_walls", rows, lines, show=True)


if __name__ == "__main__":
    main()
