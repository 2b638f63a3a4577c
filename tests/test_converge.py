"""`granflow converge`: the levels of each mode, the observed order, the verdict from run
directories written by hand, bad input, and one tiny study end to end on Dask."""

from __future__ import annotations

import csv
import json
import math
from pathlib import Path
from types import SimpleNamespace

import numpy as np
import pytest

from granflow.cli import main
from granflow.config import load_config
from granflow.converge import (
    DEFAULT_TOLERANCES,
    ConvergeError,
    Study,
    analyse,
    format_table,
    level_overrides,
    observed_order,
    orders,
    parse_tolerances,
    write_report,
)

# ------------------------------------------------------------------ levels (no runs)


def test_time_levels_of_adaptive_steps_halve_the_step_per_level() -> None:
    config = load_config("rectangle-rigid")          # adaptive, implicit Euler (q = 1)
    t = config.time
    assert level_overrides(config, "time", 0) == {
        "time.error_tol": t.error_tol, "time.dt_max": t.dt_max, "time.dt_init": t.dt_init}
    assert level_overrides(config, "time", 2) == pytest.approx({
        "time.error_tol": t.error_tol / 16, "time.dt_max": t.dt_max / 4,
        "time.dt_init": t.dt_init})
    bdf2 = SimpleNamespace(time=SimpleNamespace(**{**t.model_dump(), "scheme": "bdf2"}),
                           mesh=config.mesh, geometry=config.geometry)
    assert level_overrides(bdf2, "time", 2)["time.error_tol"] == pytest.approx(
        t.error_tol / 64)                           # 2^(k (q + 1)), q = 2
    coarse = load_config("rectangle-rigid", ["time.dt_init=1e-3"])
    assert level_overrides(coarse, "time", 1)["time.dt_init"] == 5e-4   # capped at dt_max
    slow = load_config("trapezoid-erodible")     # a slow flow's larger cap halves too
    assert level_overrides(slow, "time", 1)["time.dt_max_slow"] == pytest.approx(
        slow.time.dt_max_slow / 2)


def test_time_levels_of_a_fixed_step_and_of_the_paper_ramp() -> None:
    plug = load_config("plug-flow")
    assert level_overrides(plug, "time", 3) == {"time.dt": plug.time.dt / 8}
    ramp = load_config("rectangle-rigid", ["time.adaptive=false"])
    assert level_overrides(ramp, "time", 1) == {"time.dt_max": ramp.time.dt_max / 2,
                                                "time.dt_init": ramp.time.dt_init / 2}


def test_space_levels_halve_the_mesh_and_double_the_layer_cells() -> None:
    rigid = load_config("rectangle-rigid")
    assert level_overrides(rigid, "space", 2) == {"mesh.size": rigid.mesh.size / 4}
    erodible = load_config("trapezoid-erodible")
    assert level_overrides(erodible, "space", 1) == {"mesh.size": erodible.mesh.size / 2,
                                                     "mesh.layer_cells": 4}
    across = load_config("rectangle-rigid", ["mesh.cells_across=4"])
    assert level_overrides(across, "space", 1) == {"mesh.cells_across": 8}
    both = level_overrides(rigid, "both", 1)
    assert both == {**level_overrides(rigid, "time", 1), **level_overrides(rigid, "space", 1)}


def test_margin_levels_widen_the_adaptive_mesh_s_fine_region() -> None:
    erodible = load_config("trapezoid-erodible", ["mesh.flow_margin=1.5",
                                                  "mesh.layer_rest_coarsening=8"])
    assert level_overrides(erodible, "margin", 2) == {"mesh.flow_margin": 6.0,
                                                      "mesh.layer_rest_coarsening": 2.0}
    rigid = load_config("trapezoid-rigid", ["mesh.rest_coarsening=2"])
    assert level_overrides(rigid, "margin", 1) == {"mesh.flow_margin": 6.0}
    uniform = load_config("trapezoid-erodible", ["mesh.adaptive=false"])
    with pytest.raises(ConvergeError, match="mesh.adaptive = false"):
        level_overrides(uniform, "margin", 1)


def test_a_study_s_levels_are_explicit_overrides_on_the_user_s() -> None:
    study = Study("rectangle-rigid", "space", 3, ("mesh.size=0.04",))
    runs = study.runs()
    assert [r.name for r in runs] == ["level-0", "level-1", "level-2"]
    assert runs[2].overrides == ["mesh.size=0.04", "mesh.size=0.01"]
    assert load_config(runs[2].base, runs[2].overrides).mesh.size == 0.01


# ------------------------------------------------------------------ order and verdict


def test_observed_order_on_synthetic_differences() -> None:
    assert observed_order(4e-3, 1e-3) == (pytest.approx(2.0), "")
    assert observed_order(-4e-3, -2e-3)[0] == pytest.approx(1.0)
    for first, second, note in [(4e-3, 0.0, "is 0"), (4e-3, -1e-3, "sign alternates"),
                                (None, 1e-3, "missing")]:
        p, why = observed_order(first, second)
        assert math.isnan(p) and note in why
    assert observed_order(4e-3, -1e-3, signed=False)[0] == pytest.approx(2.0)  # distances
    diffs = [{"levels": [0, 1], "stop_time_s": 0.04, "runout_m": 8e-3,
              "surfaces": {0.1: {"mean_m": 2e-3, "max_m": 8e-3}}},
             {"levels": [1, 2], "stop_time_s": 0.01, "runout_m": 4e-3,
              "surfaces": {0.1: {"mean_m": 5e-4, "max_m": 1e-3}}}]
    fitted = {o["quantity"]: o["p"] for o in orders(diffs)}
    assert fitted == pytest.approx({"stop_time_s": 2.0, "runout_m": 1.0,
                                    "surface_mean_t0.100": 2.0, "surface_max_t0.100": 3.0})


def write_level(folder: Path, stop: float | None, runout: float, shift: float,
                status: str = "stopped") -> None:
    """A run directory as the runner leaves it: summary.json and two (flat) free surfaces."""
    (folder / "profiles").mkdir(parents=True)
    (folder / "summary.json").write_text(json.dumps({
        "status": status, "message": "", "stop_time_s": stop, "runout_m": runout,
        "steps": 100, "wall_time_s": 1.0}))
    x = np.linspace(0.0, 0.3, 31)
    for t in (0.1, 0.5):
        rows = "\n".join(f"{a},{0.1 + shift}" for a in x)   # flat: distance = shift
        (folder / "profiles" / f"free_surface_t{t:.3f}.csv").write_text(f"x,z\n{rows}\n")


def test_the_verdict_from_run_directories(tmp_path: Path) -> None:
    study = Study("rectangle-rigid", "space", 3)
    runs = study.runs()
    for k, (stop, runout, shift) in enumerate([(0.80, 0.300, 4e-3), (0.82, 0.308, 1e-3),
                                               (0.825, 0.310, 2.5e-4)]):
        write_level(tmp_path / f"level-{k}", stop, runout, shift)
    report = analyse(study, tmp_path, runs)
    assert report.converged, report.verdict
    assert report.differences[1]["surfaces"][0.5]["mean_m"] == pytest.approx(7.5e-4)
    p = {o["quantity"]: o["p"] for o in report.orders}
    assert p["runout_m"] == pytest.approx(2.0) and p["surface_max_t0.500"] == pytest.approx(2.0)
    write_report(tmp_path, report)
    with open(tmp_path / "converge.csv", newline="") as fh:
        table = list(csv.DictReader(fh))
    assert [r["level"] for r in table] == ["0", "1", "2"]
    assert float(table[2]["runout_diff_m"]) == pytest.approx(0.002)
    assert float(table[2]["mesh.size"]) == pytest.approx(study.runs()[0].varied["mesh.size"] / 4)
    saved = json.loads((tmp_path / "converge.json").read_text())
    assert saved["verdict"]["converged"] and len(saved["levels"]) == 3
    assert (tmp_path / "converge.png").stat().st_size > 0

    strict = Study("rectangle-rigid", "space", 3,
                   tolerances=parse_tolerances("surface_mean=5e-4,stop_time_rel=0.001"))
    failed = [c["criterion"] for c in analyse(strict, tmp_path, runs).verdict["checks"]
              if c["ok"] is False]
    assert failed == ["stop_time_rel", "surface_mean at t = 0.100 s",
                      "surface_mean at t = 0.500 s"]


def test_a_level_that_failed_or_never_stopped_is_not_converged(tmp_path: Path) -> None:
    study = Study("rectangle-rigid", "time", 2)
    write_level(tmp_path / "level-0", 0.8, 0.3, 0.0)
    write_level(tmp_path / "level-1", None, 0.3, 0.0, status="failed")
    checks = analyse(study, tmp_path, study.runs()).verdict["checks"]
    assert {c["criterion"] for c in checks if c["ok"] is False} == {
        "level 1 status", "stop_time_rel"}


# ------------------------------------------------------------------ bad input


def test_tolerances_syntax() -> None:
    assert parse_tolerances("runout=0.01") == {**DEFAULT_TOLERANCES, "runout": 0.01}
    assert parse_tolerances("") == DEFAULT_TOLERANCES
    for bad in ("runout", "speed=1", "runout=-1", "runout=x"):
        with pytest.raises(ConvergeError, match="--tolerances"):
            parse_tolerances(bad)


@pytest.mark.parametrize("args, expected", [
    (["--levels", "1"], "--levels: must be a whole number 2..6, got '1'"),
    (["--levels", "7"], "must be a whole number 2..6"),
    (["--levels", "two"], "must be a whole number 2..6"),
    (["--in", "space-time"], "--in: invalid choice"),
    (["--tolerances", "speed=1"], "unknown entry 'speed=1'"),
    (["--tolerances", "runout=0"], "runout = '0' must be a number > 0"),
])
def test_argument_errors_exit_2_in_one_line(args: list[str], expected: str, tmp_path: Path,
                                            monkeypatch: pytest.MonkeyPatch,
                                            capsys: pytest.CaptureFixture[str]) -> None:
    monkeypatch.chdir(tmp_path)
    with pytest.raises(SystemExit) as info:
        main(["converge", "rectangle-rigid", *args])
    err = capsys.readouterr().err
    assert info.value.code == 2 and expected in err and err.count("\n") == 1
    assert list(tmp_path.iterdir()) == []


@pytest.mark.parametrize("args, expected", [
    (["no-such-case"], "unknown scenario 'no-such-case'"),
    (["rectangle-rigid", "--set", "mesh.sise=1"], "unknown configuration key 'mesh.sise'"),
    (["trapezoid-erodible", "--in", "space", "--levels", "5"],
     "level 4 of --levels 5 (--in space): mesh.layer_cells = 32: must be an integer in "
     "[1, 16]"),
])
def test_invalid_cases_exit_2_before_any_run(args: list[str], expected: str, tmp_path: Path,
                                             monkeypatch: pytest.MonkeyPatch,
                                             capsys: pytest.CaptureFixture[str]) -> None:
    monkeypatch.chdir(tmp_path)
    assert main(["converge", *args]) == 2
    err = capsys.readouterr().err
    assert err.startswith("granflow: error: ") and expected in err and err.count("\n") == 1
    assert list(tmp_path.iterdir()) == []


# ------------------------------------------------------------------ end to end


def test_a_tiny_study_end_to_end_then_a_rerun_skips_it(granflow_cli, tmp_path: Path) -> None:
    case = ["rectangle-rigid", "--in", "time", "--levels", "2", "--set", "time.t_end=0.02",
            "--set", "mesh.size=0.05", "--set", "time.output_times=[0.01]"]
    done = granflow_cli("converge", *case, "--workers", "1", "--out", "out", "--quiet")
    assert done.returncode == 0, done.stderr
    assert "verdict: converged" in done.stdout
    out = tmp_path / "out"
    assert {p.name for p in out.iterdir()} >= {"level-0", "level-1", "converge.csv",
                                               "converge.json", "converge.png"}
    saved = json.loads((out / "converge.json").read_text())
    assert [lv["status"] for lv in saved["levels"]] == ["completed", "completed"]
    assert saved["levels"][1]["overrides"]["time.dt_max"] == pytest.approx(5e-4)
    assert list(saved["differences"][0]["surfaces"]) == ["0.010"]
    assert saved["verdict"]["converged"]
    again = granflow_cli("converge", *case, "--workers", "1", "--out", "out", "--quiet")
    assert again.returncode == 0 and "2 of 2 runs already finished, skipped" in again.stdout
    other = granflow_cli("converge", *case, "--set", "mesh.size=0.04", "--out", "out")
    assert other.returncode == 2 and "holds a run of another configuration" in other.stderr


# ------------------------------------------------------------------ a tightened parameter


def test_tolerance_and_rest_levels_tighten_their_parameters() -> None:
    config = load_config("rectangle-rigid", ["numerics.tol=1e-3"])
    tols = [level_overrides(config, "tolerance", k)["numerics.tol"] for k in range(5)]
    assert tols == pytest.approx([1e-3, 3.162e-4, 1e-4, 3.162e-5, 1e-5])
    t = config.time
    assert level_overrides(config, "rest", 2) == pytest.approx({
        "time.rest_fraction": t.rest_fraction / 4, "time.rest_duration": 4 * t.rest_duration})
    ramp = load_config("rectangle-rigid", ["time.adaptive=false", "numerics.tol=1e-4"])
    assert level_overrides(ramp, "tolerance", 0)["numerics.tol_init"] == pytest.approx(
        min(ramp.numerics.tol_init, 1e-4))
    held = load_config("rectangle-rigid", ["time.adaptive=false", "numerics.tol=1e-4",
                                           "numerics.tol_init=none"])  # the ramp holds tol
    assert level_overrides(held, "tolerance", 2)["numerics.tol_init"] == pytest.approx(1e-5)


def test_each_tolerance_level_is_judged_against_the_tightest(tmp_path: Path) -> None:
    """Levels 0..3 against level 3: level 0 is 6 mm off in runout (> 5 mm), levels 1 and
    2 within every tolerance, so level 1 is the loosest that stays within them."""
    study = Study("rectangle-rigid", "tolerance", 4, ("numerics.tol=1e-3",))
    runs = study.runs()
    for k, (runout, shift) in enumerate([(0.316, 5e-4), (0.3115, 2e-4), (0.3102, 1e-4),
                                         (0.310, 0.0)]):
        write_level(tmp_path / f"level-{k}", 0.8, runout, shift)
    report = analyse(study, tmp_path, runs)
    assert [j["converged"] for j in report.against_reference] == [False, True, True]
    assert report.loosest == 1
    text = format_table(report)
    assert "loosest within the tolerances of the reference: level 1 (numerics.tol = " \
           "0.0003162)" in text
    assert "level 0 (numerics.tol = 0.001) against the reference: not within: runout" in text
    write_report(tmp_path, report)
    assert json.loads((tmp_path / "converge.json").read_text())["loosest_level"] == 1


def test_a_tiny_tolerance_study_end_to_end(granflow_cli, tmp_path: Path) -> None:
    """Three tolerances on a coarse column: the report judges each against the tightest
    and names the loosest within the tolerances."""
    case = ["trapezoid-rigid", "--in", "tolerance", "--levels", "3", "--set",
            "numerics.tol=1e-3", "--set", "time.t_end=0.05", "--set", "mesh.size=0.06",
            "--set", "time.output_times=[0.05]"]
    done = granflow_cli("converge", *case, "--workers", "1", "--out", "out", "--quiet")
    assert done.returncode in (0, 1), done.stderr
    assert "loosest within the tolerances of the reference: level" in done.stdout
    saved = json.loads((tmp_path / "out" / "converge.json").read_text())
    assert [lv["overrides"]["numerics.tol"] for lv in saved["levels"]] == pytest.approx(
        [1e-3, 3.162e-4, 1e-4])
    assert len(saved["against_reference"]) == 2
