"""Benchmark: does mu(I), ill posed at every I with the paper's mu_s
(physics/well_posedness.py), converge under mesh refinement like Drucker-Prager?

Run: python benchmarks/mu_i_refinement.py [--shape rectangle] [--levels 3]
         [--out benchmarks/results/mu_i_refinement]

An ill-posed law lets short waves grow at a rate that rises without bound with the wave
number, so its discrete solutions stop converging as the mesh is refined. The check: the
same collapse (section 5.2 set-up: dt = 1e-3 s, tol = 1e-3, to rest) with the regularised
Drucker-Prager law and with mu(I), at mesh sizes h, h/2, h/4 (h = the scenario's), and the
change of each law's result from one size to the next: runout, stop time, and the mean and
largest distance between the free surfaces at the paper's output times. Both laws share
dt, so the changes measure the mesh. Writes OUT/refinement.json and .md.
"""

from __future__ import annotations

import argparse
import json
from pathlib import Path

from common.cases import SCENARIO, SETUP
from common.results import report, write_json, write_markdown
from common.runs import distances_mm

import granflow
from granflow.config import load_config

LAWS = {"drucker-prager": [], "mu-i": ["material.rheology=mu-i"]}
KEYS = ["status", "stop_time_s", "runout_m", "steps", "linear_solves", "wall_time_s",
        "n_triangles", "inertial_number_flowing"]


def run(shape: str, law: str, level: int, out: Path) -> dict:
    base = load_config(SCENARIO[shape], SETUP)
    size = base.mesh.size / 2**level
    config = load_config(SCENARIO[shape], [*SETUP, *LAWS[law], f"mesh.size={size!r}"])
    path = out / "runs" / f"{shape}-{law}-h{level}"
    if not (path / "summary.json").exists():
        granflow.run(config, out=path, force=True)
    summary = json.loads((path / "summary.json").read_text())
    return {"mesh_size_m": size, **{k: summary.get(k) for k in KEYS}}


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__)
    parser.add_argument("--shape", default="rectangle", choices=["rectangle", "trapezoid"])
    parser.add_argument("--levels", type=int, default=3)
    parser.add_argument("--out", type=Path, default=Path("benchmarks/results/mu_i_refinement"))
    args = parser.parse_args()
    rows: dict[str, list[dict]] = {}
    for law in LAWS:
        rows[law] = []
        for level in range(args.levels):
            row = run(args.shape, law, level, args.out)
            if level > 0:
                before = rows[law][-1]
                surfaces = distances_mm(
                    args.out / "runs" / f"{args.shape}-{law}-h{level - 1}",
                    args.out / "runs" / f"{args.shape}-{law}-h{level}")
                row["change_from_coarser"] = {
                    "runout_mm": 1e3 * (row["runout_m"] - before["runout_m"]),
                    "stop_time_s": row["stop_time_s"] - before["stop_time_s"],
                    "free_surface_mean_max_mm": surfaces}
            rows[law].append(row)
            report(f"{law} {level}", row)
    lines = [f"{args.shape}, section 5.2 set-up, mesh size h, h/2, h/4:", "",
             "| law | mesh size (m) | triangles | runout (m) | stop (s) | change of runout "
             "(mm) | change of stop (s) | free surfaces vs coarser, worst mean / max (mm) |",
             "|---|---|---|---|---|---|---|---|"]
    for law, levels in rows.items():
        for r in levels:
            change = r.get("change_from_coarser")
            worst = ("-" if not change else
                     "{:.2f} / {:.2f}".format(
                         max(v[0] for v in change["free_surface_mean_max_mm"].values()),
                         max(v[1] for v in change["free_surface_mean_max_mm"].values())))
            lines.append(
                f"| {law} | {r['mesh_size_m']:.4f} | {r['n_triangles']} | {r['runout_m']:.4f} | "
                f"{r['stop_time_s']:.3f} | "
                f"{'-' if not change else format(change['runout_mm'], '+.1f')} | "
                f"{'-' if not change else format(change['stop_time_s'], '+.3f')} | {worst} |")
    write_json(args.out / "refinement.json", rows)
    write_markdown(args.out / "refinement.md", lines, show=True)


if __name__ == "__main__":
    main()
