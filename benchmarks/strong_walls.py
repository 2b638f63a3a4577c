"""Benchmark: two 3D column runs compared step by step, the walls' u.N = 0 by the penalty
(2.7) and held strongly (``boundary.non_penetration = "strong"``), as far as both ran (a
run may be stopped: the figures are read from its diagnostics and profiles, not its
summary).

Run: python benchmarks/strong_walls.py PENALTY_RUN STRONG_RUN [--out FILE]

Writes (and prints) for the times both runs' diagnostics reach: each run's steps to
there, the largest difference (the strong run interpolated linearly in t to the penalty
run's steps) of the front along the centre line and at the side wall (m, relative to the
front's largest displacement from its start, and up to each output time), of the kinetic
energy and of the volume; each run's last row (time, fronts, largest speed, flowing
fraction); and the mean and largest distance between the free surfaces along the centre
line and at the wall at each output time both wrote. The runs are made by
benchmarks/collapse_runs.py (docs/three_d.md gives the commands).
"""

from __future__ import annotations

import argparse
import json
from pathlib import Path

import numpy as np

from granflow.io.profiles import read_profile, surface_distances


def compare(penalty: Path, strong: Path) -> dict:
    a, b = (read_profile(run / "diagnostics.csv") for run in (penalty, strong))
    end = min(a["t"][-1], b["t"][-1])
    mine = a["t"] <= end
    out: dict = {"t_compared_s": float(end), "steps": [int(mine.sum()),
                                                      int((b["t"] <= end).sum())]}
    times = a["t"][mine]
    for key in ("front_x_centre", "front_x_side", "kinetic_energy", "volume"):
        other = np.interp(times, b["t"], b[key])    # the strong run at the same t
        diff = np.abs(a[key][mine] - other)
        out[f"{key}_max_difference"] = float(diff.max())
        if key.startswith("front"):
            moved = np.abs(a[key][mine] - a[key][0]).max()
            out[f"{key}_max_difference_relative_to_displacement"] = float(diff.max() / moved)
            out[f"{key}_max_difference_by_time"] = {
                f"{t:.3f}": float(diff[times <= t + 1e-12].max())
                for t in (*_output_times(penalty), float(end))}
    out["last_rows"] = {name: {key: float(d[key][-1]) for key in (
        "t", "front_x_centre", "front_x_side", "max_speed", "flowing_fraction")}
        for name, d in (("penalty", a), ("strong", b))}
    for kind in ("free_surface", "free_surface_wall"):
        out[kind] = {f"{t:.3f}": {"mean_m": mean, "max_m": worst} for t, (mean, worst)
                     in surface_distances(penalty, strong, kind).items()}
    return out


def _output_times(run: Path) -> list[float]:
    """The output times of a run's centre-line profiles."""
    names = sorted((run / "profiles").glob("free_surface_t*.csv"))
    return [float(n.stem.removeprefix("free_surface_t")) for n in names]


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("penalty", type=Path)
    parser.add_argument("strong", type=Path)
    parser.add_argument("--out", type=Path)
    args = parser.parse_args()
    result = compare(args.penalty, args.strong)
    print(json.dumps(result, indent=1))
    if args.out:
        args.out.parent.mkdir(parents=True, exist_ok=True)
        args.out.write_text(json.dumps(result, indent=1) + "\n", encoding="utf-8")


if __name__ == "__main__":
    main()
