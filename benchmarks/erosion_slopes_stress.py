"""Benchmark: what carries the shear stress in the band of the bed's first HE metres, over
the erodible layer and over the rigid bed, in the slope study's runs
(``benchmarks/erosion_slopes.py``).

Run: python benchmarks/erosion_slopes_stress.py [--runs hysteretic/rectangle-5mm-22 ...]
         [--out benchmarks/results/erosion_slopes]

The deviatoric stress of (2.13) is sigma' = m Du with m = 2 eta + kappa / |Du|_eps: the
viscous part is 2 eta Du, so 2 eta / m is the share of the stress the viscosity carries
(the rest is the friction's yield stress), and |sigma'| / (sqrt(2) p) the friction the
material exerts (mu in simple shear at yield; the rigid bed's Coulomb friction is
tan 25.5 deg = 0.477). For each field snapshot of a run (the outputs'
times), over the flowing cells whose centroid lies within HE of the bed (the layer's
thickness; the same band for a rigid bed): the cells' area, the median shear rate
gamma_dot = sqrt(2) |Du|, the area-weighted means of 2 eta / m, of the friction (cells
with p > 0) and of the mobilisation s (hysteretic friction). A rigid run's band is its
basal 5 mm. OUT/erosion_slopes_stress.json.
"""

from __future__ import annotations

import argparse
import math
import tomllib
from pathlib import Path

import numpy as np
from common.results import read_results, write_json

from granflow.io.vtk import read_snapshot, snapshots

RUNS = [f"hysteretic/rectangle-{he}mm-{slope}" for slope in (22, 16)
        for he in ("0", "2.5", "5", "10")] + [
    "glass-beads/rectangle-0mm-19", "glass-beads/rectangle-5mm-19",
    "hysteretic-small-eta/rectangle-0mm-16", "hysteretic-small-eta/rectangle-5mm-16"]
BAND = 0.005     # a rigid run's band (m): the thickness of the study's default layer


def areas(points: np.ndarray, triangles: np.ndarray) -> np.ndarray:
    a, b, c = (points[triangles[:, i]] for i in range(3))
    return 0.5 * np.abs((b[:, 0] - a[:, 0]) * (c[:, 1] - a[:, 1])
                        - (c[:, 0] - a[:, 0]) * (b[:, 1] - a[:, 1]))


def band_figures(root: Path) -> list[dict]:
    """Per snapshot, the figures of the module docstring for the run in ``root``."""
    config = tomllib.loads((root / "config.toml").read_text())
    eta = config["material"]["viscosity"]
    band = config["geometry"].get("erodible_thickness") or BAND
    out = []
    for t, _ in snapshots(root):
        if t == 0:
            continue
        f = read_snapshot(root, t)
        z = f.points[f.triangles, 1].mean(axis=1)
        chosen = (z < band) & (f["flowing"] > 0.5)
        if not chosen.any():
            out.append({"t": t, "cells": 0})
            continue
        w = areas(f.points, f.triangles)[chosen]
        share = 2.0 * eta / f["effective_viscosity"][chosen]
        pressure = f["pressure"][f.triangles].mean(axis=1)[chosen]
        loaded = pressure > 0
        friction = f["deviatoric_stress_norm"][chosen][loaded] / (
            math.sqrt(2.0) * pressure[loaded])
        row = {"t": t, "cells": int(chosen.sum()), "area_m2": float(w.sum()),
               "shear_rate_median": float(np.median(math.sqrt(2.0)
                                                    * f["strain_rate_norm"][chosen])),
               "viscous_share": float(np.average(share, weights=w)),
               "friction": float(np.average(friction, weights=w[loaded]))
               if loaded.any() else None}
        if "mobilisation" in f.cell_data:
            row["mobilisation"] = float(np.average(f["mobilisation"][chosen], weights=w))
        out.append(row)
    return out


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--runs", nargs="+", default=RUNS)
    parser.add_argument("--out", type=Path, default=Path("benchmarks/results/erosion_slopes"))
    args = parser.parse_args()
    store = args.out / "erosion_slopes_stress.json"
    found = {name: band_figures(args.out / "runs" / name) for name in args.runs}
    write_json(store, read_results(store) | found)    # the other runs' figures kept
    for name, rows in found.items():
        print(name)
        for r in rows:
            if r["cells"]:
                print(f"  t = {r['t']:.2f} s: {r['cells']} cells, shear rate "
                      f"{r['shear_rate_median']:.1f} 1/s, viscous share "
                      f"{r['viscous_share']:.2f}, friction {r['friction']:.3f}"
                      + (f", s = {r['mobilisation']:.2f}" if "mobilisation" in r else ""))


if __name__ == "__main__":
    main()
