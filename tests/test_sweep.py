"""`granflow sweep` on Dask: a LocalCluster of 2 worker processes, a failing
run recorded as a row, reruns skipping finished runs, and an external scheduler."""

from __future__ import annotations

import csv
import json
import os
import subprocess
import sys
import time
from pathlib import Path

import pytest

from granflow.config import load_config
from granflow.sweep import builtin_studies, load_sweep

TINY = """base = "rectangle-rigid"
[set]
"geometry.width" = 0.1
"mesh.size" = 0.05
"time.t_end" = 0.01
"time.output_times" = []
[vary]
"geometry.height" = [0.05, 0.1]
"geometry.slope_deg" = [0, 10]
"""
ENV = {**os.environ, "OPENBLAS_NUM_THREADS": "1", "MPLBACKEND": "Agg"}


def sweep_cli(*args: str | Path, cwd: Path) -> subprocess.CompletedProcess[str]:
    return subprocess.run([sys.executable, "-m", "granflow", "sweep", *map(str, args),
                           "--quiet"], cwd=cwd, env=ENV, capture_output=True, text=True,
                          timeout=600)


def rows(path: Path) -> list[dict[str, str]]:
    with open(path, newline="") as fh:
        return list(csv.DictReader(fh))


def test_a_tiny_sweep_on_two_workers_then_a_rerun_skips_it(tmp_path: Path) -> None:
    (tmp_path / "tiny.toml").write_text(TINY)
    done = sweep_cli("tiny.toml", "--workers", "2", "--out", "out", cwd=tmp_path)
    assert done.returncode == 0, done.stderr
    table = rows(tmp_path / "out" / "sweep.csv")
    assert len(table) == 4 and {r["status"] for r in table} == {"completed"}
    assert {(r["geometry.height"], r["geometry.slope_deg"]) for r in table} == {
        ("0.05", "0"), ("0.05", "10"), ("0.1", "0"), ("0.1", "10")}
    for r in table:   # each row is its run directory's summary
        summary = json.loads((tmp_path / "out" / r["run"] / "summary.json").read_text())
        assert float(r["runout_m"]) == summary["runout_m"]
    again = sweep_cli("tiny.toml", "--workers", "2", "--out", "out", cwd=tmp_path)
    assert again.returncode == 0 and "4 of 4 runs already finished, skipped" in again.stdout
    assert rows(tmp_path / "out" / "sweep.csv") == table


def test_a_failing_run_is_a_row_and_the_others_complete(tmp_path: Path) -> None:
    text = TINY.replace('"geometry.slope_deg" = [0, 10]', '"mesh.size" = [0.05, 0.5]')
    text = text.replace('"mesh.size" = 0.05\n', "")
    (tmp_path / "fail.toml").write_text(text)
    done = sweep_cli("fail.toml", "--workers", "2", "--out", "out", cwd=tmp_path)
    assert done.returncode == 1
    table = rows(tmp_path / "out" / "sweep.csv")
    failed = [r for r in table if r["status"] == "failed"]
    assert len(table) == 4 and len(failed) == 2          # mesh.size 0.5 > the column
    assert all("mesh.size = 0.5 must not exceed" in r["message"] for r in failed)
    assert "failed" in done.stderr


@pytest.mark.slow
def test_an_external_scheduler_with_two_workers(tmp_path: Path) -> None:
    (tmp_path / "tiny.toml").write_text(TINY)
    dask = Path(sys.executable).with_name("dask")
    file = tmp_path / "scheduler.json"
    procs = [subprocess.Popen([dask, "scheduler", "--scheduler-file", file, "--port", "0",
                               "--dashboard-address", ":0"], env=ENV, cwd=tmp_path,
                              stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)]
    try:
        deadline = time.monotonic() + 60
        while not file.exists() and time.monotonic() < deadline:
            time.sleep(0.2)
        address = json.loads(file.read_text())["address"]
        procs += [subprocess.Popen([dask, "worker", address, "--nworkers", "1", "--nthreads",
                                    "1"], env=ENV, cwd=tmp_path, stdout=subprocess.DEVNULL,
                                   stderr=subprocess.DEVNULL) for _ in range(2)]
        done = sweep_cli("tiny.toml", "--scheduler", address, "--out", "out", cwd=tmp_path)
        assert done.returncode == 0, done.stderr
        assert f"on {address}" in done.stdout
        assert len(rows(tmp_path / "out" / "sweep.csv")) == 4
    finally:
        for p in procs:
            p.terminate()
        for p in procs:
            p.wait(timeout=30)


def test_the_built_in_study_loads_and_a_bad_sweep_file_is_one_line(tmp_path: Path) -> None:
    for name in builtin_studies():     # every run of every built-in study is valid
        study = load_sweep(name)
        assert len(study.runs()) >= 6 and study.base in ("rectangle-rigid", "cylinder-rigid")
        for run in study.runs():
            load_config(run.base, run.overrides)
    (tmp_path / "bad.toml").write_text('base = "rectangle-rigid"\n[vary]\n"mesh.sise" = [1]\n')
    done = sweep_cli("bad.toml", cwd=tmp_path)
    assert done.returncode == 2 and done.stderr.count("\n") == 1
    assert "unknown configuration key 'mesh.sise'" in done.stderr
    with pytest.raises(Exception, match="not found"):
        load_sweep(str(tmp_path / "missing.toml"))


def test_a_dashboard_address_is_given_only_where_one_exists(
        monkeypatch: pytest.MonkeyPatch) -> None:
    """Without bokeh where the scheduler runs, Dask serves a page asking for it: no address
    is printed then (an external scheduler's, asked; a local cluster's, known here)."""
    from distributed import LocalCluster

    import granflow.sweep as sweep

    def scheduler(dashboard: str | None) -> LocalCluster:
        return LocalCluster(n_workers=0, processes=False, protocol="tcp://",
                            dashboard_address=dashboard)

    with scheduler(":0") as local, sweep.Cluster(local.scheduler_address, 1) as cluster:
        assert bool(cluster.dashboard) == sweep._has_bokeh()
        monkeypatch.setattr(sweep, "_has_bokeh", lambda: True)
        assert cluster.dashboard.startswith("http://")
        monkeypatch.setattr(sweep, "_has_bokeh", lambda: False)
        assert cluster.dashboard == ""


def test_a_runs_notes_are_one_line_in_its_worker(tmp_path: Path,
                                                 capfd: pytest.CaptureFixture[str]) -> None:
    """What a run prints in its Dask worker: granflow's note as the command line prints it,
    not a Python warning with the worker's source line (two lines a run)."""
    from granflow.sweep import SweepRun, run_one

    run = SweepRun("a", "rectangle-rigid", ["mesh.size=0.05", "time.t_end=0.002",
                                            "output.progress=false"], {})
    row = run_one(run, str(tmp_path))
    assert row["status"] == "completed", row
    err = [line for line in capfd.readouterr().err.splitlines() if line.strip()]
    assert err and all(line.startswith("granflow: note: ") for line in err), err
