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
