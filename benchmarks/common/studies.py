"""Running a built-in study on a Dask LocalCluster and recording its wall time."""

from __future__ import annotations

import json
from pathlib import Path

from granflow.io.run_dir import atomic_write_text
from granflow.sweep import Cluster, load_sweep, run_sweep


def run_study(study: str, out: Path, workers: int) -> dict:
    """`granflow sweep STUDY` into OUT/sweep; OUT/timing_N_workers.json gets its wall time."""
    with Cluster(None, workers) as cluster:
        result = run_sweep(load_sweep(study), out / "sweep", cluster.client, progress=False)
    timing = {"workers": workers, "wall_time_s": result.wall_time_s, "runs": len(result.rows),
              "skipped": result.skipped, "failed": len(result.failed)}
    print(json.dumps(timing))
    atomic_write_text(out / f"timing_{workers}_workers.json", json.dumps(timing, indent=2))
    return timing
