"""Benchmark: where a run's cells still flow after its front has settled, from its VTU
snapshots (``output.vtk_every``) and diagnostics.csv: what holds off the rest stop of the
3D column in a channel, beside the 2D run with depth-averaged side walls.

Run: python benchmarks/three_d_creep.py RUN_DIR [RUN_DIR ...] [--from 0.4] [--to 1.0]
         [--out benchmarks/results/three_d_collapse/creep]
(the run folders of ``benchmarks/three_d_collapse.py channel``, which writes VTU every 5
steps, or any 2D or 3D column run with snapshots).

For each snapshot between ``--from`` and ``--to``: the cells the rest rule counts as
flowing (mean |u| over the cell above 1 mm/s, ``diagnostics/state.py``), their share of the
volume (of the section's area in 2D) against ``time.rest_fraction``, the largest cell's
share (a single cell above the rule's fraction holds the stop off alone), the share of the
flowing volume in cells that touch the free surface, the bed, the back wall, the side wall
and the centre plane (3D), and that lie within one mesh.size of the front; the largest
speed, where it is, the across-channel share of the flowing cells' speed and their mean
velocity across (towards the side wall positive); the flowing cells' mean pressure and
yield ratio. From diagnostics.csv in the same window: nonlinear iterations per
step, the relative volume (area) restored per step by the free-surface fix and its rate
as the mean normal speed of the free surface that restores it, the front's mean speed; and
the summary's status, stop time, steps and runouts. Writes OUT.json and OUT.md.
"""

from __future__ import annotations

import argparse
import json
import tomllib
from pathlib import Path
from typing import Any

import numpy as np
import pandas as pd
from common.results import write_json, write_markdown
from meshio import vtu

from granflow.io.vtk import FOLDER, snapshots

FLOWING = 1e-3      # m/s, the rest rule's threshold (simulation/rest.py)
ON_PLANE = 1e-9     # m


def boundary_facets(cells: np.ndarray) -> np.ndarray:
    """The facets (faces of tetrahedra, edges of triangles) that belong to one cell only,
    as rows of vertex indices, and for each the cell it bounds (last column)."""
    k = cells.shape[1]
    facets = np.concatenate([np.delete(cells, j, axis=1) for j in range(k)])
    owner = np.tile(np.arange(len(cells)), k)
    key = np.sort(facets, axis=1)
    _, index, counts = np.unique(key, axis=0, return_index=True, return_counts=True)
    once = index[counts == 1]
    return np.column_stack([facets[once], owner[once]])


def cell_sizes(points: np.ndarray, cells: np.ndarray) -> np.ndarray:
    """Volumes of tetrahedra, or areas of triangles (points (n, 2))."""
    if cells.shape[1] == 4:
        a, b, c, d = (points[cells[:, j]] for j in range(4))
        return np.abs(np.einsum("ij,ij->i", b - a, np.cross(c - a, d - a))) / 6.0
    a, b, c = (points[cells[:, j]] for j in range(3))
    return 0.5 * np.abs((b - a)[:, 0] * (c - a)[:, 1] - (b - a)[:, 1] * (c - a)[:, 0])


def free_surface_size(points: np.ndarray, cells: np.ndarray) -> float:
    """The free surface's area (3D) or length (2D): the boundary facets on no plane."""
    three = cells.shape[1] == 4
    planes = [(2 if three else 1, 0.0), (0, 0.0)]
    if three:
        planes += [(1, points[:, 1].min()), (1, points[:, 1].max())]
    nodes = boundary_facets(cells)[:, :-1]
    planar = np.zeros(len(nodes), dtype=bool)
    for axis, value in planes:
        planar |= np.all(np.abs(points[nodes, axis] - value) < ON_PLANE, axis=1)
    free = points[nodes[~planar]]
    if three:
        return float(0.5 * np.linalg.norm(np.cross(free[:, 1] - free[:, 0],
                                                   free[:, 2] - free[:, 0]), axis=1).sum())
    return float(np.linalg.norm(free[:, 1] - free[:, 0], axis=1).sum())


def where(points: np.ndarray, cells: np.ndarray, size: float) -> dict[str, np.ndarray]:
    """Per cell: whether it has a facet on the free surface, the bed, the back wall, the
    side wall and the centre plane (3D), and whether its centroid lies within ``size`` of
    the front."""
    three = cells.shape[1] == 4
    up = 2 if three else 1
    facets = boundary_facets(cells)
    nodes, owner = facets[:, :-1], facets[:, -1]
    on = {"bed": (up, 0.0), "back_wall": (0, 0.0)}
    if three:
        on |= {"centre_plane": (1, points[:, 1].min()), "side_wall": (1, points[:, 1].max())}
    flags: dict[str, np.ndarray] = {}
    planar = np.zeros(len(nodes), dtype=bool)
    for name, (axis, value) in on.items():
        lies = np.all(np.abs(points[nodes, axis] - value) < ON_PLANE, axis=1)
        planar |= lies
        flags[name] = np.zeros(len(cells), dtype=bool)
        flags[name][owner[lies]] = True
    flags["free_surface"] = np.zeros(len(cells), dtype=bool)
    flags["free_surface"][owner[~planar]] = True
    centroid_x = points[cells, 0].mean(axis=1)
    flags["front"] = centroid_x > points[:, 0].max() - size
    return flags


def snapshot_row(root: Path, t: float, name: str, size: float) -> dict[str, Any]:
    mesh = vtu.read(str(root / FOLDER / name))
    kind = "tetra" if any(c.type == "tetra" for c in mesh.cells) else "triangle"
    cells = next(c.data for c in mesh.cells if c.type == kind)
    points = mesh.points if kind == "tetra" else mesh.points[:, :2]
    data = {k: np.asarray(v[0]) for k, v in mesh.cell_data.items()}
    speed, sizes = data["speed"], cell_sizes(points, cells)
    flowing = speed > FLOWING
    total, moving = sizes.sum(), sizes[flowing].sum()
    row: dict[str, Any] = {"t": t, "cells": len(cells), "flowing_cells": int(flowing.sum()),
                           "volume": float(total),
                           "free_surface": free_surface_size(points, cells),
                           "flowing_share": float(moving / total),
                           "largest_cell_share": float(sizes.max() / total),
                           "max_speed_m_s": float(speed.max())}
    if not flowing.any():
        return row
    for name, flag in where(points, cells, size).items():
        row[f"on_{name}"] = float(sizes[flowing & flag].sum() / moving)
    fastest = int(np.argmax(speed))
    row["fastest_at_m"] = [round(float(v), 4) for v in points[cells[fastest]].mean(axis=0)]
    velocity = np.asarray(mesh.point_data["velocity"])
    cell_velocity = velocity[cells[flowing]].mean(axis=1)
    norm = np.linalg.norm(cell_velocity, axis=1)
    if kind == "tetra":
        row["across_share"] = float(np.mean(np.abs(cell_velocity[:, 1]) / norm))
        # the mean across-channel velocity, positive towards the side wall (the high plane)
        row["across_mean_m_s"] = float(np.mean(cell_velocity[:, 1]))
    if "pressure" in mesh.point_data:
        row["pressure_mean_pa"] = float(np.mean(np.asarray(mesh.point_data["pressure"])[
            cells[flowing]]))
    if "yield_ratio" in data:
        row["yield_ratio_mean"] = float(np.mean(data["yield_ratio"][flowing]))
    return row


def creep(root: Path, start: float, end: float) -> dict[str, Any]:
    config = tomllib.loads((root / "config.toml").read_text())
    size = config["mesh"]["size"]
    rows = [snapshot_row(root, t, name, size) for t, name in snapshots(root)
            if start <= t <= end]
    diag = pd.read_csv(root / "diagnostics.csv")
    window = diag[(diag["t"] >= start) & (diag["t"] <= end)]
    summary = json.loads((root / "summary.json").read_text())
    out: dict[str, Any] = {"rest_fraction": config["time"]["rest_fraction"], "size": size,
                           **{k: summary.get(k) for k in ("status", "stop_time_s", "steps",
                                                          "runout_m", "runout_wall_m")},
                           "snapshots": rows}
    if len(window) > 1:
        t, x = window["t"].to_numpy(), window["front_x"].to_numpy()
        out["window"] = {"steps": len(window),
                         "iterations_per_step": float(window["iterations"].mean()),
                         "dt_mean_s": float(window["dt"].mean()),
                         "front_speed_mean_m_s": float((x[-1] - x[0]) / (t[-1] - t[0]))}
        fix = "volume_correction" if "volume_correction" in window else "area_correction"
        if fix in window and rows:
            # the free-surface fix's relative volume (area in 2D) per second, and as the
            # mean normal speed of the free surface that restores it
            rate = float((window[fix].abs() / window["dt"]).mean())
            out["window"]["volume_correction_per_s"] = rate
            out["window"]["volume_correction_surface_speed_m_s"] = (
                rate * rows[-1]["volume"] / rows[-1]["free_surface"])
    return out


def table(results: dict[str, dict[str, Any]]) -> list[str]:
    lines = ["| run | t (s) | flowing share | largest cell | max speed (mm/s) | surface | bed "
             "| side wall | centre plane | front | across |",
             "|" + "---|" * 11]

    def pct(row: dict[str, Any], key: str) -> str:
        return f"{100 * row[key]:.0f} %" if key in row else "-"

    for label, result in results.items():
        for row in result["snapshots"]:
            if row["flowing_cells"] == 0:
                continue
            lines.append(
                f"| {label} | {row['t']:.3f} | {row['flowing_share']:.4f} | "
                f"{row['largest_cell_share']:.4f} | {1e3 * row['max_speed_m_s']:.2f} | "
                + " | ".join(pct(row, f"on_{k}") for k in (
                    "free_surface", "bed", "side_wall", "centre_plane", "front"))
                + f" | {pct(row, 'across_share')} |")
    return lines


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("runs", type=Path, nargs="+")
    parser.add_argument("--from", dest="start", type=float, default=0.4)
    parser.add_argument("--to", dest="end", type=float, default=1.0)
    parser.add_argument("--out", type=Path,
                        default=Path("benchmarks/results/three_d_collapse/creep"))
    args = parser.parse_args()
    results = {root.name: creep(root, args.start, args.end) for root in args.runs}
    write_json(args.out.with_suffix(".json"), results, end="\n")
    write_markdown(args.out.with_suffix(".md"), "\n".join(table(results)) + "\n")
    print("\n".join(table(results)))


if __name__ == "__main__":
    main()
