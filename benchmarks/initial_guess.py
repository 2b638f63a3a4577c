"""Benchmark: the first iterate of each step near rest on a slope.

Run: python benchmarks/initial_guess.py [--guesses extrapolated auto] [--t-end 0.5]
         [--out benchmarks/results/initial_guess]

The column that made the 10 deg aspect-ratio study stall (rectangle l0 = 10 cm,
h0 = 5 cm, 8 cells across, bed at 10 deg, friction load from the penalty's reaction),
run with the fixed-point iteration (3.2) from each initial guess: the linear extrapolation
of the last two steps (the scenarios' choice) and "auto" (the better of it and (u^n, p^n)
on the last step). Prints and writes OUT/initial_guess.json: nonlinear iterations per
phase (flowing, decelerating, near rest), the largest speed and the flowing fraction at
the same times, the front and the wall time.
"""

from __future__ import annotations

import argparse
import json
from pathlib import Path

import numpy as np
from common.results import report, write_json

import granflow
from granflow.config import load_config

COLUMN = ["geometry.width=0.1", "geometry.height=0.05", "geometry.slope_deg=10.0",
          "boundary.normal_load=reaction", "mesh.cells_across=8", "time.output_times=[]",
          "numerics.linearization=picard"]
PHASES = ((0.0, 0.3), (0.3, 0.45), (0.45, 10.0))
PROBES = (0.3, 0.4, 0.42, 0.45, 0.5)


def measure(run: Path) -> dict:
    d = np.genfromtxt(run / "diagnostics.csv", delimiter=",", names=True)
    summary = json.loads((run / "summary.json").read_text())
    phases = {}
    for a, b in PHASES:
        sel = (d["t"] >= a) & (d["t"] < b)
        phases[f"{a:g}-{b:g} s"] = {"steps": int(sel.sum()),
                                    "iterations": int(d["iterations"][sel].sum())}
    probes = {}
    for t in PROBES:
        if t <= d["t"][-1] + 1e-9:
            i = int(np.argmin(abs(d["t"] - t)))
            probes[f"{t:g}"] = {"max_speed_mm_s": round(1e3 * float(d["max_speed"][i]), 3),
                                "flowing_fraction": round(float(d["flowing_fraction"][i]), 5),
                                "front_x_m": round(float(d["front_x"][i]), 5)}
    return {"status": summary["status"], "t_final": summary["t_final"],
            "wall_time_s": round(summary["wall_time_s"], 1),
            "nonlinear_iterations": summary["nonlinear_iterations"], "phases": phases,
            "probes": probes}


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__)
    parser.add_argument("--guesses", nargs="+", default=["extrapolated", "auto"])
    parser.add_argument("--t-end", type=float, default=0.5)
    parser.add_argument("--out", type=Path, default=Path("benchmarks/results/initial_guess"))
    args = parser.parse_args()
    results = {}
    for guess in args.guesses:
        config = load_config("rectangle-rigid", [*COLUMN, f"numerics.initial_guess={guess}",
                                                 f"time.t_end={args.t_end!r}"])
        run_dir = granflow.run(config, out=args.out / "runs" / guess, force=True)
        results[guess] = measure(run_dir.root)
        report(guess, results[guess])
    write_json(args.out / "initial_guess.json", results)


if __name__ == "__main__":
    main()
