"""`granflow verify plug-flow`: the paper's Tables 1 and 2 recomputed against the 1D solver.

Every cell runs on a strip two cells wide: the structured periodic mesh is invariant by a
one-cell shift, so the discrete solution on the paper's 1.5 m domain is x-periodic with
period dZ and equals the strip's (tests/verification/test_plug_flow.py checks this). Same
numbers, a fraction of the cost.
"""

from __future__ import annotations

import csv
import io
import json
import math
import sys
import time
from dataclasses import asdict, dataclass
from importlib import resources
from pathlib import Path
from typing import Any

from granflow.config import load_config
from granflow.diagnostics.conservation import mesh_area
from granflow.io.run_dir import RunDirError, atomic_write_text
from granflow.scenarios.plug_flow import build_plug_flow

QUICK_CELLS = {  # coarse cells, for CI: (dZ, dt) pairs
    1: [(0.25, 2.5e-2), (0.25, 1.25e-2), (0.25, 6.25e-3)],
    2: [(0.25, 1.56e-3)],
}


BOUND = 2.0          # a cell passes when its error is at most BOUND x the paper's
VOLUME_BOUND = 1e-4  # Table 2: relative volume error at most this


@dataclass(frozen=True)
class CellResult:
    eps: float
    dt: float
    dZ: float
    error: float
    paper_error: float
    ratio: float
    iterations: int
    wall_time_s: float
    volume_error: float | None = None
    paper_volume_error: float | None = None

    @property
    def passed(self) -> bool:
        """Error at most BOUND x the paper's (and, on Table 2, the volume within VOLUME_BOUND)."""
        volume_ok = self.volume_error is None or self.volume_error <= VOLUME_BOUND
        return self.error <= BOUND * self.paper_error and volume_ok


@dataclass(frozen=True)
class Verification:
    """What ``granflow verify`` wrote and which cells missed their bound."""

    path: Path
    results: list[CellResult]

    @property
    def failed(self) -> list[CellResult]:
        return [r for r in self.results if not r.passed]


def paper_table(table: int) -> list[dict[str, float]]:
    """Rows of the paper's Table 1 or 2 (shipped as package data)."""
    text = resources.files("granflow.data").joinpath(f"plug_flow_table{table}.csv").read_text()
    lines = [line for line in text.splitlines() if line and not line.startswith("#")]
    return [{k: float(v) for k, v in row.items()} for row in csv.DictReader(lines)]


def run_cell(eps: float, dt: float, dz: float, moving: bool = False,
             extra: tuple[str, ...] = ()) -> tuple[float, int, float, float]:
    """(velocity error, nonlinear iterations, volume error, wall time) of one table cell."""
    overrides = ["numerics.linearization=picard",   # the paper's iteration (3.2), as tabled
                 f"numerics.eps={eps!r}", f"time.dt={dt!r}", f"mesh.size={dz!r}",
                 f"geometry.length={2 * dz!r}", "mesh.cells_x=2", "time.output_times=[]",
                 f'numerics.mesh_velocity="{"vertical" if moving else "fixed"}"',
                 *extra]
    problem = build_plug_flow(load_config("plug-flow", overrides))
    area0 = mesh_area(problem.mesh)
    start = time.perf_counter()
    result = problem.simulation.run()
    wall = time.perf_counter() - start
    if result.status != "completed":
        raise RuntimeError(f"cell eps={eps} dt={dt} dZ={dz}: {result.message}")
    volume_error = abs(mesh_area(problem.mesh) - area0) / area0
    return problem.velocity_error(result.t_final), result.nonlinear_iterations, volume_error, wall


def table_cells(table: int, cells: str) -> list[dict[str, float]]:
    rows = paper_table(table)
    if cells == "quick":
        keep = set(QUICK_CELLS[table])
        rows = [r for r in rows if (r["dZ"], r["dt"]) in keep]
    return rows


def measure_cell(eps: float, dt: float, dz: float, moving: bool) -> tuple[float, int,
                                                                        float, float, str]:
    """``run_cell`` that reports a failed run as an infinite error (a Dask task never
    raises): (error, iterations, volume error, wall time, message)."""
    try:
        return (*run_cell(eps, dt, dz, moving=moving), "")
    except RuntimeError as exc:
        return math.inf, 0, math.inf, math.nan, str(exc)


def verify_plug_flow(table: int, cells: str, out: Path, progress: bool = True,
                     client: Any = None) -> Verification:
    """Recompute Table ``table`` ('quick' or 'all' cells); write CSV, JSON and a PNG in
    ``out``. With a Dask ``client`` the cells run as tasks on its workers."""
    from tqdm import tqdm

    try:
        out.mkdir(parents=True, exist_ok=True)
        probe = out / ".granflow-write-test"
        probe.write_bytes(b"")
        probe.unlink()
    except OSError as err:
        raise RunDirError(f"--out '{out}' is not a folder granflow can write into: "
                          f"{err.strerror or err}") from None
    results: list[CellResult] = []
    start = time.perf_counter()
    rows = table_cells(table, cells)
    args = [(row.get("eps", 1e-6), row["dt"], row["dZ"], table == 2) for row in rows]
    if client is not None:
        futures = [client.submit(measure_cell, *a, pure=False) for a in args]
        measured = iter(client.gather(futures))
    else:
        measured = (measure_cell(*a) for a in args)
    for row, (eps, *_), (error, iterations, vol_err, wall, message) in tqdm(
            zip(rows, args, measured, strict=True), total=len(rows), disable=not progress,
            desc=f"Table {table}"):
        if message:   # a cell whose run failed misses its bound
            print(f"granflow: {message}", file=sys.stderr)
        paper = row["error"] if table == 1 else row["error_u"]
        results.append(CellResult(
            eps=eps, dt=row["dt"], dZ=row["dZ"], error=error, paper_error=paper,
            ratio=error / paper, iterations=iterations, wall_time_s=wall,
            volume_error=vol_err if table == 2 else None,
            paper_volume_error=row.get("error_volume") if table == 2 else None))
    total = time.perf_counter() - start
    columns = ["eps", "dt", "dZ", "error", "paper_error", "ratio", "iterations", "wall_time_s",
               "passed"]
    if table == 2:
        columns += ["volume_error", "paper_volume_error"]
    text = io.StringIO(newline="")
    writer = csv.writer(text)
    writer.writerow(columns)
    for r in results:
        writer.writerow([getattr(r, c) if c == "passed" else f"{getattr(r, c):.6g}"
                         for c in columns])
    path = out / f"table{table}.csv"
    atomic_write_text(path, text.getvalue())
    atomic_write_text(out / f"table{table}.json", json.dumps(
        {"table": table, "cells": cells, "total_wall_time_s": total, "bound_factor": BOUND,
         "results": [asdict(r) | {"passed": r.passed} for r in results]}, indent=2))
    from granflow.io.plots import plot_convergence_table

    plot_convergence_table(out / f"table{table}.png", results, table)
    return Verification(path, results)
