"""Running a case into a run directory through ``granflow.run`` and comparing two runs'
profiles (``granflow.io.profiles``)."""

from __future__ import annotations

import json
import shutil
from pathlib import Path

import granflow
from common.results import write_json
from granflow.config import load_config
from granflow.io import profiles
from granflow.io.run_dir import RunDir

COLLAPSE_KEYS = ["status", "message", "t_final", "steps", "rejected_steps",
                 "nonlinear_iterations", "linear_solves", "wall_time_s", "stop_time_s",
                 "front_stop_time_s", "front_settle_time_s", "runout_m", "wall_height_m",
                 "volume_relative_error", "n_triangles", "n_dofs", "runout_1mm_m",
                 "surface_edge_spread", "remeshes", "history_restarts"]
SPEED_KEYS = ["status", "message", "t_final", "steps", "rejected_steps", "rejections",
              "nonlinear_iterations", "linear_solves", "wall_time_s",
              "stop_time_s", "all_cells_static_s", "runout_m", "volume_relative_error",
              "n_triangles", "remeshes", "min_triangle_quality",
              "velocity_relative_error_l2", "outputs_at_rest", "linear_solver"]


def run_variant(tag: str, scenarios: list[str], overrides: list[str], out: Path) -> dict:
    """Run each scenario with ``overrides`` into OUT/TAG/SCENARIO; write OUT/TAG.json."""
    results = {}
    for name in scenarios:
        config = load_config(name, overrides)
        run_dir = granflow.run(config, out=out / tag / name, force=True)
        summary = RunDir.summary(run_dir.root)
        results[name] = {k: summary.get(k) for k in COLLAPSE_KEYS} | {"overrides": overrides}
        print(tag, name, json.dumps(results[name], indent=1), flush=True)
    write_json(out / f"{tag}.json", results)
    return results


def run_summary(scenario: str, overrides: list[str], out: Path) -> dict:
    """Run ``scenario`` with ``overrides`` into a fresh ``out``; its summary's SPEED_KEYS."""
    config = load_config(scenario, [*overrides, "output.progress=false"])
    shutil.rmtree(out, ignore_errors=True)     # never mix the files of two runs
    run_dir = granflow.run(config, out=out, force=True)
    summary = RunDir.summary(run_dir.root)
    return {k: summary.get(k) for k in SPEED_KEYS} | {"overrides": overrides}


def surfaces_m(first: Path, second: Path) -> dict[str, dict[str, float]]:
    """Mean and max distance (m) between two runs' free surfaces, by output time "T.TTT"."""
    return {f"{t:.3f}": {"mean_m": mean, "max_m": worst}
            for t, (mean, worst) in profiles.surface_distances(first, second).items()}


def distances_mm(first: Path, second: Path, kind: str = "free_surface",
                 common_extent: bool = False) -> dict[str, list]:
    """Mean and max distance (mm, 2 decimals) between two runs' ``kind`` curves, by time
    (``common_extent``: only as far in X as both reach, ``profiles.surface_distances``)."""
    return {f"{t:g}": [round(1e3 * x, 2) for x in d] for t, d in
            profiles.surface_distances(first, second, kind, common_extent=common_extent).items()}


FINISHED = ("completed", "stopped")


def run_or_continue(scenario: str, overrides: list[str], out: Path) -> dict:
    """The summary of the run in ``out``: kept when finished, continued from its checkpoint
    when it has one (an interrupted or killed run: a long study goes on across invocations),
    else run afresh. Long runs should set ``output.checkpoint_every``."""
    summary = RunDir.summary(out) if RunDir.is_run_dir(out) else {}
    if summary.get("status") in FINISHED:
        return summary
    if (out / "checkpoint" / "state.npz").is_file():
        granflow.resume(out)
    else:
        config = load_config(scenario, [*overrides, "output.progress=false"])
        shutil.rmtree(out, ignore_errors=True)     # never mix the files of two runs
        granflow.run(config, out=out, force=True)
    return RunDir.summary(out)


def flow_duration(root: Path, fraction: float = 0.01) -> float | None:
    """When the flow ends, from diagnostics.csv (``granflow.diagnostics.front``)."""
    from granflow.diagnostics.front import flow_duration as duration
    from granflow.io.diagnostics import read_diagnostics

    diag = read_diagnostics(root)
    if not len(diag):
        return None
    return duration(diag["t"].to_numpy(), diag["flowing_fraction"].to_numpy(), fraction)


def collected(out: Path) -> dict | None:
    """The summary of the run in ``out`` for a table, or None when there is none yet or it
    is still running (a live run is not collected)."""
    if not RunDir.is_run_dir(out):
        return None
    summary = RunDir.summary(out)
    return None if summary.get("status") == "running" else summary
