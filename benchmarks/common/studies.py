"""Running a built-in study on a Dask LocalCluster and recording its wall time."""

from __future__ import annotations

from pathlib import Path

from common.results import report, write_json
from granflow.sweep import Cluster, load_sweep, run_sweep


def run_study(study: str, out: Path, workers: int) -> dict:
    """`granflow sweep STUDY` into OUT/sweep; OUT/timing_N_workers.json gets its wall time."""
    with Cluster(None, workers) as cluster:
        result = run_sweep(load_sweep(study), out / "sweep", cluster.client, progress=False)
    timing = {"workers": workers, "wall_time_s": result.wall_time_s, "runs": len(result.rows),
              "skipped": result.skipped, "failed": len(result.failed)}
    report("", timing)
    write_json(out / f"timing_{workers}_workers.json", timing)
    return timing
