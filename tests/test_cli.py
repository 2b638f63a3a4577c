"""The ``granflow`` command: listing, argument and configuration errors (no simulation runs)."""

from __future__ import annotations

from pathlib import Path

import pytest

from granflow import __version__
from granflow.cli import DEFAULT_SCENARIO, main
from granflow.config import builtin_scenarios


def test_default_scenario_is_builtin() -> None:
    assert DEFAULT_SCENARIO in builtin_scenarios()


def test_scenarios_prints_one_line_per_scenario(granflow_cli) -> None:
    proc = granflow_cli("scenarios")
    assert proc.returncode == 0, proc.stderr
    lines = proc.stdout.splitlines()
    assert [line.split()[0] for line in lines] == list(builtin_scenarios())
    for line, description in zip(lines, builtin_scenarios().values(), strict=True):
        assert line.endswith(description)


def test_version(granflow_cli) -> None:
    proc = granflow_cli("--version")
    assert proc.returncode == 0 and proc.stdout.strip() == f"granflow {__version__}"


def test_show_prints_the_resolved_configuration_a_run_accepts(granflow_cli,
                                                               tmp_path: Path) -> None:
    """The scenario's own settings (not the package defaults) and the overrides, as TOML
    that loads back to the same configuration."""
    from granflow.config import load_config

    proc = granflow_cli("show", "rectangle-rigid", "--set", "geometry.height=0.2")
    assert proc.returncode == 0, proc.stderr
    (tmp_path / "shown.toml").write_text(proc.stdout)
    shown = load_config(str(tmp_path / "shown.toml"))
    expected = load_config("rectangle-rigid", ["geometry.height=0.2"])
    assert shown.model_dump(exclude={"scenario"}) == expected.model_dump(exclude={"scenario"})
    assert 'shape = "rectangle"' in proc.stdout and "height = 0.2" in proc.stdout


def test_invalid_set_exits_2_with_one_line_and_creates_nothing(granflow_cli,
                                                               tmp_path: Path) -> None:
    proc = granflow_cli("run", "--set", "numerics.eps=-1")
    assert proc.returncode == 2
    assert proc.stderr.count("\n") == 1 and "Traceback" not in proc.stderr
    assert proc.stderr.startswith("granflow: error: numerics.eps = -1")
    assert proc.stdout == ""
    assert list(tmp_path.iterdir()) == []


@pytest.mark.parametrize("args, expected", [
    (["run", "--set", "numerics.epsilon=1"], "unknown configuration key 'numerics.epsilon'"),
    (["run", "--set", "time.dt=0"], "time.dt = 0: must be"),
    (["run", "--set", "mesh.size=10"], "mesh.size = 10.0 must not exceed"),
    (["run", "--set", "material.friction_angle_deg=90"], "material.friction_angle_deg = 90"),
    (["run", "no-such-scenario"], "unknown scenario 'no-such-scenario'"),
    (["run", "missing.toml"], "scenario file 'missing.toml' not found"),
    (["run", "trapezoid-rigid", "--set", "material.rheology=mu-i", "--set",
      "material.mu_2_deg=20", "--out", "x"], "material.mu_2_deg = 20.0 must be greater than"),
])
def test_config_errors_exit_2_before_creating_anything(
        args: list[str], expected: str, tmp_path: Path, monkeypatch: pytest.MonkeyPatch,
        capsys: pytest.CaptureFixture[str]) -> None:
    monkeypatch.chdir(tmp_path)
    assert main(args) == 2
    err = capsys.readouterr().err
    assert err.startswith("granflow: error: ") and expected in err and err.count("\n") == 1
    assert list(tmp_path.iterdir()) == []


def test_toml_file_with_a_misspelt_key(granflow_cli, tmp_path: Path) -> None:
    (tmp_path / "mine.toml").write_text('scenario = "plug-flow"\n[time]\nt_ned = 0.1\n')
    proc = granflow_cli("run", "mine.toml")
    assert proc.returncode == 2
    assert "unknown configuration key 'time.t_ned'" in proc.stderr
    assert sorted(p.name for p in tmp_path.iterdir()) == ["mine.toml"]


def test_run_refuses_a_foreign_output_folder(tmp_path: Path, monkeypatch: pytest.MonkeyPatch,
                                             capsys: pytest.CaptureFixture[str]) -> None:
    monkeypatch.chdir(tmp_path)
    (tmp_path / "out").mkdir()
    (tmp_path / "out" / "thesis.tex").write_text("precious")
    assert main(["run", "--out", "out", "--quiet"]) == 2
    assert "is not empty and is not a granflow run directory" in capsys.readouterr().err
    assert [p.name for p in (tmp_path / "out").iterdir()] == ["thesis.tex"]


@pytest.mark.parametrize("args", [
    ["verify", "plug-flow", "--table", "3"],
    ["verify", "plug-flow", "--cells", "some"],
    ["verify", "collapse"],
    ["run", "--set"],
    [],
])
def test_argument_errors_exit_2(args: list[str], tmp_path: Path,
                                monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.chdir(tmp_path)
    with pytest.raises(SystemExit) as info:
        main(args)
    assert info.value.code == 2
    assert list(tmp_path.iterdir()) == []


def test_argument_errors_are_one_line(tmp_path: Path, monkeypatch: pytest.MonkeyPatch,
                                      capsys: pytest.CaptureFixture[str]) -> None:
    monkeypatch.chdir(tmp_path)
    with pytest.raises(SystemExit):
        main(["verify", "collapse"])
    err = capsys.readouterr().err
    assert err.startswith("granflow: error: ") and err.count("\n") == 1


@pytest.mark.slow
def test_verify_exits_non_zero_when_a_cell_misses_its_bound(
        tmp_path: Path, monkeypatch: pytest.MonkeyPatch,
        capsys: pytest.CaptureFixture[str]) -> None:
    import granflow.verify as verify

    monkeypatch.setitem(verify.QUICK_CELLS, 1, [(0.25, 2.5e-2)])   # 3 cheap cells
    assert main(["verify", "plug-flow", "--out", str(tmp_path / "ok"), "--quiet"]) == 0
    capsys.readouterr()
    monkeypatch.setattr(verify, "BOUND", 1e-3)       # no cell can meet this bound
    assert main(["verify", "plug-flow", "--out", str(tmp_path / "bad"), "--workers", "2",
                 "--quiet"]) == 1                   # the same cells, as Dask tasks
    assert capsys.readouterr().err.count("missed its bound") == 3
    columns = slice(0, 7)   # the cells' figures (not the wall time, not the verdict)
    assert [r.split(",")[columns] for r in (tmp_path / "ok/table1.csv").read_text().split()] == [
        r.split(",")[columns] for r in (tmp_path / "bad/table1.csv").read_text().split()]


def test_dropped_output_times_get_one_note_line(granflow_cli) -> None:
    proc = granflow_cli("show", "rectangle-rigid", "--set", "time.t_end=0.4")
    assert proc.returncode == 0, proc.stderr
    assert proc.stderr == ("granflow: note: time.output_times [0.42, 0.5, 0.78, 1.06] of the "
                           "scenario come after time.t_end = 0.4 s and are not written (set "
                           "time.output_times to choose others)\n")
