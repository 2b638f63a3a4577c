"""Run directory: creation rules, atomic whole-file writes, append-only CSV logs."""

from __future__ import annotations

import csv
import json
import math
import os
import subprocess
import sys
import textwrap
from pathlib import Path

import numpy as np
import pytest

from granflow.config import config_to_toml, load_config
from granflow.io.run_dir import LOCK_FILE, MANIFEST, CsvLog, RunDir, RunDirError


def read_csv(path: Path) -> list[list[str]]:
    with open(path, newline="") as f:
        return list(csv.reader(f))


def files_in(folder: Path) -> list[str]:
    """The files in ``folder`` but the run's manifest (its own tests read it)."""
    return sorted(str(p.relative_to(folder)) for p in folder.rglob("*")
                  if p.is_file() and p.name != MANIFEST)


# ---------------------------------------------------------------- creation


def test_create_makes_nested_folders(tmp_path: Path) -> None:
    run = RunDir.create(tmp_path / "runs" / "a")
    assert run.root.is_dir()


def test_create_accepts_an_empty_folder_and_replaces_a_previous_run_only_with_force(
        tmp_path: Path) -> None:
    RunDir.create(tmp_path)  # empty
    run = RunDir.create(tmp_path / "run")
    run.write_text("config.toml", config_to_toml(load_config("plug-flow")))
    written = ["summary.json", "diagnostics.csv", "traceback.txt", "profiles/units.json",
               "profiles/free_surface_t0.300.csv", "profiles/velocity_final.csv",
               "fields/fields.pvd", "fields/fields_00012.vtu", "frames/frame_00003.npz",
               "plots/free_surface.png", "plots/speed.gif", "checkpoint/state.npz",
               "fields/.fields.pvd.tmp", ".summary.json.k2j3h4g5.tmp.json"]
    for name in written:
        run.write_text(name, "x\n")
    # the user's files, some named as a run names its own (--force once deleted those)
    mine = ["notes.txt", "profiles/my_analysis.py", "plots/draft.txt", "paper/fig.png",
            "plots/holiday.png", "profiles/my_final.csv", "fields/fields_99999.vtu",
            "frames/frame_99999.npz", "checkpoint/state.pkl"]
    for name in mine:
        (run.root / name).parent.mkdir(parents=True, exist_ok=True)
        (run.root / name).write_text("mine\n")
    assert RunDir.is_run_dir(run.root)
    with pytest.raises(RunDirError, match="already holds a run; use --force"):
        RunDir.create(run.root)
    assert (run.root / "profiles/free_surface_t0.300.csv").exists()
    RunDir.create(run.root, force=True)      # cleared: old and new files never mix
    assert files_in(run.root) == sorted([LOCK_FILE, *mine])   # ... and the user's stay


def test_force_deletes_only_what_the_manifest_lists_inside_the_layout(tmp_path: Path) -> None:
    """A manifest from someone else may list anything: only names of the run's layout
    inside the folder are deleted, never through a link."""
    run = RunDir.create(tmp_path / "run")
    run.write_text("config.toml", config_to_toml(load_config("plug-flow")))
    (tmp_path / "outside.txt").write_text("outside\n")
    (run.root / "notes.txt").write_text("mine\n")
    (run.root / "plots").mkdir()
    (run.root / "elsewhere").symlink_to(tmp_path)
    (run.root / MANIFEST).write_text("\n".join([
        "config.toml", "../outside.txt", "/etc/hostname", "notes.txt", "elsewhere/outside.txt",
        "plots/../notes.txt", "plots"]) + "\n")
    RunDir.create(run.root, force=True)
    assert (tmp_path / "outside.txt").read_text() == "outside\n"
    assert files_in(run.root) == sorted([LOCK_FILE, "notes.txt"])
    assert (run.root / "elsewhere").is_symlink() and not (run.root / "plots").exists()


def test_force_refuses_a_run_of_an_earlier_granflow_without_a_manifest(tmp_path: Path) -> None:
    """Refused as it is; once resumed, its files of the layout are listed as its own."""
    run = RunDir.create(tmp_path / "run")
    run.write_text("config.toml", config_to_toml(load_config("plug-flow")))
    run.write_text("fields/fields_00003.vtu", "x\n")
    (run.root / "notes.txt").write_text("mine\n")
    (run.root / MANIFEST).unlink()
    with pytest.raises(RunDirError, match="kept no list of the files it wrote"):
        RunDir.create(run.root, force=True)
    assert (run.root / "config.toml").exists()
    (run.root / "plots").mkdir()
    (run.root / "plots" / "holiday.png").write_text("mine\n")
    RunDir(run.root).adopt_layout([          # what its own records name, as resume does
        "config.toml", "summary.json", "fields/fields_00003.vtu", "../notes.txt"])
    assert (run.root / MANIFEST).read_text().splitlines() == [
        "config.toml", "fields/fields_00003.vtu"]
    RunDir.create(run.root, force=True)
    assert files_in(run.root) == sorted([LOCK_FILE, "notes.txt", "plots/holiday.png"])


def test_an_empty_or_unwritable_out_is_an_error(tmp_path: Path) -> None:
    with pytest.raises(RunDirError, match="empty path"):
        RunDir.create(Path(""))
    (tmp_path / "file").write_text("x")
    with pytest.raises(RunDirError, match="cannot use output folder"):
        RunDir.create(tmp_path / "file" / "run")          # a parent that is a file
    locked = tmp_path / "ro"
    locked.mkdir()
    locked.chmod(0o500)
    try:
        if not os.access(locked, os.W_OK):                # root ignores permissions
            with pytest.raises(RunDirError, match="cannot use output folder"):
                RunDir.create(locked / "run")
    finally:
        locked.chmod(0o700)


def test_a_second_writer_is_refused_while_the_first_holds_the_lock(tmp_path: Path) -> None:
    run = RunDir.create(tmp_path / "run")
    script = textwrap.dedent(f"""
        from granflow.io.run_dir import RunDir, RunDirError
        try:
            with RunDir({str(run.root)!r}).lock():
                print("acquired")
        except RunDirError as err:
            print("refused:", err)
    """)
    run.write_text("config.toml", config_to_toml(load_config("plug-flow")))
    with run.lock():
        out = subprocess.run([sys.executable, "-c", script], capture_output=True, text=True,
                             timeout=60).stdout
        assert out.startswith("refused:") and "in use by another granflow process" in out
        with pytest.raises(RunDirError, match="in use"):   # --force must not clear it either
            RunDir.create(run.root, force=True)
    assert (run.root / "config.toml").exists()
    out = subprocess.run([sys.executable, "-c", script], capture_output=True, text=True,
                         timeout=60).stdout
    assert out.startswith("acquired")


def test_create_refuses_a_foreign_non_empty_folder_or_a_file(tmp_path: Path) -> None:
    (tmp_path / "notes.txt").write_text("mine")
    with pytest.raises(RunDirError, match="not empty and is not a granflow run directory"):
        RunDir.create(tmp_path)
    (tmp_path / "config.toml").write_text("[tool]\n")  # someone else's config
    with pytest.raises(RunDirError):
        RunDir.create(tmp_path)
    with pytest.raises(RunDirError, match="not a folder"):
        RunDir.create(tmp_path / "notes.txt")
    assert files_in(tmp_path) == ["config.toml", "notes.txt"]


def test_path_creates_parents_and_stays_inside(tmp_path: Path) -> None:
    run = RunDir.create(tmp_path / "run")
    path = run.path("profiles/free_surface_t0.180.csv")
    assert path.parent.is_dir() and not path.exists()
    with pytest.raises(RunDirError, match="outside the run directory"):
        run.path("../escape.txt")


# ---------------------------------------------------------------- atomic writes


def test_writes_leave_only_the_targets(tmp_path: Path) -> None:
    run = RunDir.create(tmp_path)
    run.write_text("config.toml", "# granflow\n")
    run.write_json("summary.json", {"status": "completed"})
    run.write_csv("profiles/free_surface_t0.200.csv", ["x", "z"], [[0.0, 1.0], [0.5, 0.25]])
    run.write_text("config.toml", "# granflow, again\n")  # replacing is atomic too
    assert files_in(tmp_path) == ["config.toml", "profiles/free_surface_t0.200.csv",
                                  "summary.json"]
    assert (tmp_path / MANIFEST).read_text().splitlines() == [   # each once, before written
        "config.toml", "summary.json", "profiles/free_surface_t0.200.csv"]
    assert (tmp_path / "config.toml").read_text() == "# granflow, again\n"
    assert read_csv(tmp_path / "profiles/free_surface_t0.200.csv") == [
        ["x", "z"], ["0.0", "1.0"], ["0.5", "0.25"]]
    assert oct((tmp_path / "summary.json").stat().st_mode & 0o777) == oct(0o644)


def test_json_writes_nan_and_inf_as_null_and_numpy_as_numbers(tmp_path: Path) -> None:
    run = RunDir.create(tmp_path)
    run.write_json("summary.json", {
        "stop_time_s": math.nan, "runout_m": np.float64(0.61), "steps": np.int64(12),
        "bad": [math.inf, -math.inf, np.float32("nan")], "profile": np.array([1.0, 2.0]),
        "nested": {"ok": True, "none": None}})
    text = (tmp_path / "summary.json").read_text()
    assert "NaN" not in text and "Infinity" not in text
    assert text.startswith('{\n  "stop_time_s": null')
    assert json.loads(text) == {
        "stop_time_s": None, "runout_m": 0.61, "steps": 12, "bad": [None, None, None],
        "profile": [1.0, 2.0], "nested": {"ok": True, "none": None}}


def test_a_failed_write_keeps_the_old_file_and_no_temp(tmp_path: Path) -> None:
    run = RunDir.create(tmp_path)
    run.write_json("summary.json", {"status": "running"})
    with pytest.raises(TypeError):
        run.write_json("summary.json", {"status": object()})
    with pytest.raises(RuntimeError), run.atomic_path("plots/front.png") as tmp:
        tmp.write_bytes(b"half a figure")
        raise RuntimeError("plot failed")
    assert files_in(tmp_path) == ["summary.json"]
    assert json.loads((tmp_path / "summary.json").read_text()) == {"status": "running"}


def test_atomic_path_keeps_the_suffix_and_renames_on_success(tmp_path: Path) -> None:
    run = RunDir.create(tmp_path)
    with run.atomic_path("fields/fields_00000.vtu") as tmp:
        assert tmp.suffix == ".vtu" and tmp.parent == tmp_path / "fields"
        tmp.write_text("<VTKFile/>")
    assert files_in(tmp_path) == ["fields/fields_00000.vtu"]


# ---------------------------------------------------------------- CSV logs


HEADER = ["t", "dt", "iterations"]


def test_csv_log_rows_are_readable_while_the_log_is_open(tmp_path: Path) -> None:
    run = RunDir.create(tmp_path)
    log = run.csv_log("diagnostics.csv", HEADER)
    log.append([0.1, 1e-3, 4])
    log.append({"dt": 2e-3, "t": 0.2, "iterations": 3, "ignored": 0})
    assert read_csv(tmp_path / "diagnostics.csv") == [
        HEADER, ["0.1", "0.001", "4"], ["0.2", "0.002", "3"]]
    with pytest.raises(ValueError, match="2 values"):
        log.append([0.3, 1e-3])
    with pytest.raises(ValueError, match="lacks"):
        log.append({"t": 0.3})
    log.close()
    log.close()  # closing twice is harmless


def test_csv_log_starts_afresh_or_resumes_with_the_same_header(tmp_path: Path) -> None:
    path = tmp_path / "diagnostics.csv"
    with CsvLog(path, HEADER) as log:
        log.append([0.1, 1e-3, 4])
    with CsvLog(path, HEADER, resume=True) as log:
        log.append([0.2, 1e-3, 5])
    assert len(read_csv(path)) == 3
    with pytest.raises(RunDirError, match="header"):
        CsvLog(path, ["t", "volume"], resume=True)
    with CsvLog(path, HEADER):
        pass
    assert read_csv(path) == [HEADER]


def test_a_killed_process_leaves_every_finished_file_readable(tmp_path: Path) -> None:
    script = textwrap.dedent(f"""
        import os, signal
        from pathlib import Path
        from granflow.io.run_dir import RunDir
        run = RunDir.create(Path({str(tmp_path)!r}) / "run")
        run.write_json("summary.json", {{"status": "running"}})
        log = run.csv_log("diagnostics.csv", ["t", "volume"])
        for i in range(5):
            log.append([0.1 * i, 1.0])
        os.kill(os.getpid(), signal.SIGKILL)
    """)
    proc = subprocess.run([sys.executable, "-c", script], capture_output=True, timeout=60)
    assert proc.returncode != 0
    run = tmp_path / "run"
    assert files_in(run) == ["diagnostics.csv", "summary.json"]
    assert json.loads((run / "summary.json").read_text()) == {"status": "running"}
    assert len(read_csv(run / "diagnostics.csv")) == 6


# ---------------------------------------------------------------- a directory from someone else


def test_summary_members_of_the_wrong_type_are_left_out(tmp_path: Path) -> None:
    (tmp_path / "summary.json").write_text(json.dumps({
        "status": ["completed"], "final_profiles_t": "0.3", "runout_m": True,
        "outputs_at_rest": [0.5, "x"], "steps": 12, "message": "ok", "custom": {"a": 1}}))
    assert RunDir.summary(tmp_path) == {"steps": 12, "message": "ok", "custom": {"a": 1}}
    assert RunDir.status(tmp_path) is None
    (tmp_path / "summary.json").write_text("[" * 100_000 + "]" * 100_000)
    assert RunDir.summary(tmp_path) == {}


def test_writers_replace_a_planted_link_and_never_follow_it(tmp_path: Path) -> None:
    outside = tmp_path / "outside.txt"
    outside.write_text("mine\n")
    run = RunDir.create(tmp_path / "run")
    for name in ("summary.json", "diagnostics.csv"):
        (run.root / name).symlink_to(outside)
    run.write_json("summary.json", {"status": "running"})
    with CsvLog(run.root / "diagnostics.csv", HEADER, resume=True) as log:
        log.append([0.1, 1e-3, 4])
    assert outside.read_text() == "mine\n"
    assert not (run.root / "summary.json").is_symlink()
    assert read_csv(run.root / "diagnostics.csv") == [HEADER, ["0.1", "0.001", "4"]]
    (tmp_path / "elsewhere").mkdir()
    (run.root / "plots").symlink_to(tmp_path / "elsewhere")
    with pytest.raises(RunDirError, match="leads outside the run directory"):
        run.write_text("plots/front.png", "x")
    with pytest.raises(RunDirError, match="not a folder of the run directory"):
        run.check_layout()
    assert list((tmp_path / "elsewhere").iterdir()) == []


def test_resume_removes_the_temporary_files_a_kill_left_and_nothing_else(
        tmp_path: Path) -> None:
    """Those of the files the manifest lists (io/atomic.py's names, and the fixed names of
    earlier versions); a user's named like them, of files the run never wrote, stay."""
    run = RunDir.create(tmp_path)
    left = ["fields/.fields.pvd.tmp", "fields/.fields_00002.vtu.tmp", "plots/.speed.tmp.gif",
            ".summary.json.ab12cd34.tmp.json", "profiles/.units.json.x1y2z3w4.tmp.json"]
    targets = ["fields/fields.pvd", "fields/fields_00002.vtu", "plots/speed.gif",
               "summary.json", "profiles/units.json"]
    kept = ["notes.tmp.txt", "plots/.hidden", "fields/.keep.tmp/x", ".notes.tmp",
            ".notes.txt.ab12cd34.tmp.txt", "plots/.holiday.png.ab12cd34.tmp.png",
            ".summary.json.ab12cd34.tmp.csv"]
    for name in targets:
        run.write_text(name, "x")
    for name in left + kept:
        (tmp_path / name).parent.mkdir(parents=True, exist_ok=True)
        (tmp_path / name).write_text("x")
    run.remove_temporary_files()
    assert files_in(tmp_path) == sorted([*targets, *kept])
