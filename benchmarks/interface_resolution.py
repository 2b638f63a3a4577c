"""How finely the static/flowing interface is resolved: the 1 mm/s level of the speed as the
figure draws it (the contour of the vertex speeds, linear on each triangle) and of the log
of the speed, against the finite-element velocity's own level, sampled finely (600 points
on each of 60 verticals: the lowest point faster than 1 mm/s), in the default collapse at
t = 0.3 s. All three step with the mesh: the interface is resolved to a cell, and the
figure says so (plots/interface.png). Expected, from a first probe of the same run: the
vertex speeds' level within about 3 mm of the field's on average and 8 mm at most (a
third of a 2.1 cm cell), the log's further (about 5 and 12 mm), the field's own level
jumping by about a cell between neighbouring verticals.

Run: python benchmarks/interface_resolution.py [--t 0.3]
Writes benchmarks/results/interface_resolution/interface_resolution.json.
"""

from __future__ import annotations

import argparse
import sys
from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import matplotlib.tri as mtri  # noqa: E402
import numpy as np  # noqa: E402
from common.results import report, write_json  # noqa: E402

from granflow.config import load_config  # noqa: E402
from granflow.diagnostics.state import FLOWING_SPEED  # noqa: E402
from granflow.fem.sampling import point_values, triangles, vertex_samples  # noqa: E402
from granflow.scenarios.column import build_column  # noqa: E402

OUT = Path(__file__).resolve().parent / "results" / "interface_resolution"


def lowest_crossing(segments: list[np.ndarray], x: float) -> float:
    """The lowest z where a contour's segments cross the vertical at x (NaN: none)."""
    best = np.nan
    for seg in segments:
        for (x0, z0), (x1, z1) in zip(seg[:-1], seg[1:], strict=True):
            if min(x0, x1) <= x <= max(x0, x1) and x0 != x1:
                z = z0 + (z1 - z0) * (x - x0) / (x1 - x0)
                best = z if np.isnan(best) else min(best, z)
    return best


def main(argv: list[str]) -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--t", type=float, default=0.3)
    args = parser.parse_args(argv)
    problem = build_column(load_config("trapezoid-rigid", [
        f"time.t_end={args.t}", "time.output_times=[]", "time.stop_at_rest=false"]))
    problem.simulation.run()
    mesh, velocity = problem.mesh, problem.solver.velocity
    xy = mesh.ngmesh.Coordinates()
    tri = mtri.Triangulation(xy[:, 0], xy[:, 1], triangles(mesh))
    speed = np.linalg.norm(vertex_samples(mesh, velocity), axis=1)
    fig, ax = plt.subplots(figsize=(9, 4.5), layout="constrained")
    levels = {
        "vertex_speed": ax.tricontour(tri, speed, levels=[FLOWING_SPEED], colors="tab:red"),
        "vertex_log_speed": ax.tricontour(tri, np.log10(np.maximum(speed, 1e-12)),
                                          levels=[np.log10(FLOWING_SPEED)], colors="tab:blue"),
    }
    stations = np.linspace(0.005, 0.95 * xy[:, 0].max(), 60)
    field = []
    for x in stations:
        z, u = point_values(mesh, velocity, x, np.linspace(0.0, xy[:, 1].max(), 600))
        fast = np.flatnonzero(np.linalg.norm(u, axis=1) > FLOWING_SPEED)
        field.append(z[fast[0]] if len(fast) else np.nan)
    field_z = np.array(field)
    ax.plot(stations, field_z, "k.", ms=3, label="the P2 speed's level, sampled")
    ax.triplot(tri, lw=0.2, color="0.75")
    ax.set(aspect="equal", xlabel="x (m)", ylabel="z (m)",
           title=f"The 1 mm/s level at t = {args.t:g} s: vertex speeds (red), their log "
                 "(blue), the field (dots)")
    ax.legend(loc="upper left", bbox_to_anchor=(1.01, 1.0), fontsize=8)
    OUT.mkdir(parents=True, exist_ok=True)
    fig.savefig(OUT / "interface_resolution.png", dpi=130)
    out = {"t": args.t, "mesh_size_m": problem.config.mesh.size, "stations": len(stations),
           "station_spacing_m": float(stations[1] - stations[0]),
           "triangles": int(mesh.ne)}
    for name, contour in levels.items():
        distance = np.array([lowest_crossing(contour.allsegs[0], x) for x in stations]) - field_z
        out[name] = {"mean_distance_m": float(np.nanmean(np.abs(distance))),
                     "max_distance_m": float(np.nanmax(np.abs(distance)))}
    # how much the field's own level steps: its largest jump between neighbouring stations
    out["field_level_largest_jump_m"] = float(np.nanmax(np.abs(np.diff(field_z))))
    report("interface", out)
    write_json(OUT / "interface_resolution.json", out)


if __name__ == "__main__":
    main(sys.argv[1:])
