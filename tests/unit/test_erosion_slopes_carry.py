"""benchmarks/erosion_slopes.py's rows carried past the study's 3 s (``--t-end``), without
running anything: the runs and the resume are stood in for. A row carried further is kept
by the default invocation (never run again, never shortened), a fresh clone's rows (no run
folders) are kept, and a carried row keeps its 3 s figures."""

from __future__ import annotations

import importlib.util
import sys
from pathlib import Path
from types import ModuleType

import pytest

BENCHMARKS = Path(__file__).resolve().parents[2] / "benchmarks"


def _module(name: str) -> ModuleType:
    if str(BENCHMARKS) not in sys.path:
        sys.path.insert(0, str(BENCHMARKS))      # the scripts import common.*
    spec = importlib.util.spec_from_file_location(name, BENCHMARKS / f"{name}.py")
    assert spec is not None and spec.loader is not None
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


SLOPES = _module("erosion_slopes")
CARRY = sys.modules["common.carry"]
VARIANT = "glass-beads-no-slip-small-eta-walls"
ARGS = (VARIANT, "rectangle", 0.0, 22.0, None)


def found() -> list[str]:
    return SLOPES.overrides(*ARGS)


def row(status: str, t_final: float, runout: float, **more: object) -> dict:
    return {"status": status, "t_final": t_final, "runout_m": runout, "overrides": found(),
            "front_history": {"3": 1.721}} | more


@pytest.fixture
def no_runs(monkeypatch: pytest.MonkeyPatch) -> list:
    """Every run, resume and summary the script would start, recorded instead (a stand-in
    run folder: ``state`` holds its summary)."""
    calls: list = []
    state: dict = {"summary": {"status": "completed", "t_final": 3.0, "runout_m": 1.721}}

    def run_or_continue(scenario: str, overrides: list[str], out: Path) -> dict:
        calls.append(("run_or_continue", out))
        return dict(state["summary"])

    def resume(out: Path, overrides: dict) -> None:
        calls.append(("resume", overrides))
        state["summary"] = {"status": "completed", "t_final": overrides["time.t_end"],
                            "runout_m": 1.95}

    def row_of(summary: dict, out: Path) -> dict:
        return dict(summary) | {"t_end": summary["t_final"],
                                "front_history": {"3": 1.721, "6": summary["runout_m"]}}

    monkeypatch.setattr(SLOPES, "run_or_continue", run_or_continue)
    monkeypatch.setattr(SLOPES, "row_of", row_of)
    monkeypatch.setattr(CARRY.granflow, "resume", resume)
    monkeypatch.setattr(CARRY.RunDir, "summary", lambda out: dict(state["summary"]))
    return calls


def test_the_default_keeps_a_row_of_3_s_and_one_carried_further(no_runs: list) -> None:
    at_3 = row("completed", 3.0, 1.721)          # recorded before rows kept their end
    at_6 = row("completed", 6.0, 1.95, t_end=6.0)
    assert SLOPES.run(*ARGS, Path("nowhere"), done=at_3) is at_3
    assert SLOPES.run(*ARGS, Path("nowhere"), done=at_6) is at_6
    assert SLOPES.run(*ARGS, Path("nowhere"), done=at_6, t_end=4.0) is at_6   # not shortened
    assert no_runs == []        # no folder needed: a fresh clone keeps its rows


def test_a_row_at_rest_is_not_carried(no_runs: list) -> None:
    rest = row("stopped", 1.1, 0.45)
    assert SLOPES.run(*ARGS, Path("nowhere"), done=rest, t_end=6.0) is rest
    assert no_runs == []


def test_a_row_moving_at_3_s_is_resumed_to_the_later_end(no_runs: list) -> None:
    at_3 = row("completed", 3.0, 1.721, front_speed_end_m_s=0.106)
    carried = SLOPES.run(*ARGS, Path("folder"), done=at_3, t_end=6.0)
    assert no_runs == [("run_or_continue", Path("folder")), ("resume", {"time.t_end": 6.0})]
    assert (carried["t_end"], carried["runout_m"]) == (6.0, 1.95)
    assert carried["overrides"] == found()      # the study's overrides: the default keeps it
    earlier = carried["earlier"]["3"]
    assert (earlier["runout_m"], earlier["front_speed_end_m_s"]) == (1.721, 0.106)
    assert "overrides" not in earlier
    assert SLOPES.run(*ARGS, Path("folder"), done=carried) is carried   # then kept
    assert len(no_runs) == 2


def test_a_run_already_at_the_later_end_is_not_resumed(no_runs: list) -> None:
    assert CARRY.carried({"status": "completed", "t_final": 6.0}, Path("f"), 6.0)[
        "t_final"] == 6.0
    assert CARRY.carried({"status": "stopped", "t_final": 4.2}, Path("f"), 6.0)[
        "t_final"] == 4.2
    assert no_runs == []


def test_an_interrupted_carry_keeps_the_3_s_figures() -> None:
    at_3 = row("completed", 3.0, 1.721)
    stopped_short = CARRY.with_earlier(row("interrupted", 4.4, 1.82, t_end=6.0), at_3)
    assert stopped_short["earlier"]["3"]["runout_m"] == 1.721
    resumed = CARRY.with_earlier(row("completed", 6.0, 1.95, t_end=6.0), stopped_short)
    assert resumed["earlier"] == stopped_short["earlier"]


def test_fronts_of_different_ends_are_compared_at_the_earlier() -> None:
    rigid = row("completed", 6.0, 1.95, t_end=6.0, front_history={"3": 1.721, "6": 1.95})
    layer = row("completed", 3.0, 2.197) | {"variant": VARIANT, "shape": "rectangle",
                                            "slope": 22.0, "he": 0.005}
    results = {SLOPES.rigid_key(VARIANT, "rectangle", 22.0): rigid}
    value, bound = SLOPES.ratio(results, layer)
    assert bound == "≈" and value == pytest.approx(2.197 / 1.721)
    value, _ = SLOPES.ratio(results, layer | {"runout_m": 2.5, "t_end": 6.0, "t_final": 6.0})
    assert value == pytest.approx(2.5 / 1.95)


def test_an_end_before_the_studys_is_refused(monkeypatch: pytest.MonkeyPatch,
                                             capsys: pytest.CaptureFixture[str]) -> None:
    monkeypatch.setattr(sys, "argv", ["erosion_slopes.py", "--t-end", "2"])
    with pytest.raises(SystemExit):
        SLOPES.main()
    assert "--t-end must be between the study's 3 s and 60 s, not 2" in capsys.readouterr().err


LAYER = (f"{VARIANT}-fine", "rectangle", 0.005, 19.0)     # its layer's length by its twin


def bed(overrides: list[str]) -> float:
    return next(float(o.split("=")[1]) for o in overrides if o.startswith(CARRY.BED_LENGTH))


def test_a_longer_bed_is_the_same_run() -> None:
    slope_bed = SLOPES.overrides(*LAYER, None)           # the twin unfinished: 1.95 m
    twin_bed = SLOPES.overrides(*LAYER, 1.3)             # 1.3 x 1.3 m = 1.69 m
    assert (bed(slope_bed), bed(twin_bed)) == pytest.approx((1.95, 1.69))
    assert CARRY.same_run(slope_bed, twin_bed)
    assert not CARRY.same_run(twin_bed, slope_bed)       # a shorter bed is another run
    assert not CARRY.same_run(SLOPES.overrides(*LAYER[:3], 16.0, None), twin_bed)


def test_an_interrupted_row_continues_as_it_began(no_runs: list,
                                                  monkeypatch: pytest.MonkeyPatch) -> None:
    began = SLOPES.overrides(*LAYER, None)
    used: list = []

    def run_or_continue(scenario: str, overrides: list[str], out: Path) -> dict:
        used.append(overrides)
        return {"status": "completed", "t_final": 3.0, "runout_m": 1.5}

    monkeypatch.setattr(SLOPES, "run_or_continue", run_or_continue)
    done = row("interrupted", 1.2, 1.1) | {"overrides": began}
    row_ = SLOPES.run(*LAYER, 1.3, Path("folder"), done=done)
    assert used == [began] and row_["overrides"] == began


def _folder(root: Path) -> Path:
    (root / "checkpoint").mkdir(parents=True)
    (root / "checkpoint" / "state.npz").write_bytes(b"state")
    (root / "config.toml").write_text("[time]\nt_end = 3.0\n")
    (root / ".granflow.lock").write_text("")
    (root / "frames").mkdir()
    (root / "frames" / "frame_00000.npz").write_bytes(b"frame")
    (root / "fields").mkdir()
    (root / "fields" / "fields_00000.vtu").write_text("<VTKFile/>")
    return root


def test_an_interrupted_run_travels_in_an_archive(tmp_path: Path) -> None:
    archive = tmp_path / "carried" / "variant" / "row.tar.gz"
    CARRY.pack(_folder(tmp_path / "run"), archive)
    clone = tmp_path / "clone" / "run"
    assert CARRY.unpack(archive, clone)
    assert (clone / "checkpoint" / "state.npz").read_bytes() == b"state"
    assert (clone / "config.toml").read_text() == "[time]\nt_end = 3.0\n"
    assert not (clone / ".granflow.lock").exists()          # never another process's lock
    assert not (clone / "frames").exists() and not (clone / "fields").exists()   # outputs
    (clone / "checkpoint" / "state.npz").write_bytes(b"later")
    assert not CARRY.unpack(archive, clone)                  # a folder's own checkpoint wins
    assert (clone / "checkpoint" / "state.npz").read_bytes() == b"later"
    assert not CARRY.unpack(tmp_path / "none.tar.gz", tmp_path / "other")


def test_an_archive_leaving_its_folder_is_refused(tmp_path: Path) -> None:
    import tarfile

    archive = tmp_path / "evil.tar.gz"
    (tmp_path / "outside").write_text("x")
    with tarfile.open(archive, "w:gz") as tar:
        tar.add(tmp_path / "outside", arcname="../escaped")
    with pytest.raises(tarfile.OutsideDestinationError):
        CARRY.unpack(archive, tmp_path / "run")
    assert not (tmp_path / "escaped").exists()


def test_a_layer_row_is_also_taken_against_the_twin_with_the_tension() -> None:
    where = {"shape": "rectangle", "slope": 10.0, "cells": 2}
    layer = {"variant": VARIANT, "he": 0.005, "status": "stopped", "runout_m": 0.69} | where
    rigid = {"variant": VARIANT, "he": 0.0, "status": "stopped", "runout_m": 0.60} | where
    results = {"layer": layer, SLOPES.rigid_key(VARIANT, "rectangle", 10.0): rigid}
    assert "(rigid:" not in SLOPES.ratio_table(results)
    tension = rigid | {"variant": f"{VARIANT}-tension", "runout_m": 0.5}
    results[SLOPES.rigid_key(f"{VARIANT}-tension", "rectangle", 10.0)] = tension
    table = SLOPES.ratio_table(results)
    assert f"| {VARIANT} | rectangle | 5 | 2 | 0.690 (1.15) |" in table
    assert f"| {VARIANT} (rigid: {VARIANT}-tension) | rectangle | 5 | 2 | 0.690 (1.38) |" in table


@pytest.mark.filterwarnings("ignore::granflow.config.schema.ConfigNote")   # mu-i's 25.5 deg
@pytest.mark.parametrize("variant", sorted(sys.modules["common.erosion_variants"].VARIANTS))
def test_every_variant_is_a_valid_configuration(variant: str) -> None:
    """Each of the study's variants loads, rigid and over 5 mm at 19 degrees, with the
    bed it names (a misspelt key or value would fail a row hours into the study)."""
    from granflow.config import load_config

    for he in (0.0, 0.005):
        config = load_config(SLOPES.SCENARIO["rectangle"],
                             SLOPES.overrides(variant, "rectangle", he, 19.0, 1.0))
        assert config.geometry.slope_deg == 19.0
        assert config.geometry.erodible_thickness == he
        named = [o.split("=")[1] for o in SLOPES.VARIANTS[variant]
                 if o.startswith("boundary.bed=")]
        assert config.boundary.bed == (named[-1] if named else "coulomb")


def test_a_rigid_twin_is_also_read_at_the_layer_rows_front() -> None:
    """A layer row's front stands 1 mm above the layer; a rigid twin whose record reads its
    front 1 mm above the bed gives a line with that ratio too, its thin tongue left out."""
    where = {"shape": "rectangle", "slope": 19.0, "cells": 2}
    layer = {"variant": VARIANT, "he": 0.005, "status": "stopped", "runout_m": 1.40} | where
    rigid = {"variant": VARIANT, "he": 0.0, "status": "stopped", "runout_m": 1.75} | where
    results = {"layer": layer, SLOPES.rigid_key(VARIANT, "rectangle", 19.0): rigid}
    assert "at 1 mm" not in SLOPES.ratio_table(results)
    rigid["runout_1mm_m"] = 1.40 / 0.9
    table = SLOPES.ratio_table(results)
    assert f"| {VARIANT} | rectangle | 5 | 2 | 1.400 (0.80) |" in table
    assert f"| {VARIANT} (rigid: at 1 mm) | rectangle | 5 | 2 | 1.400 (0.90) |" in table
    assert SLOPES.ratio(results, layer, thick=True) == (pytest.approx(0.9), "")
