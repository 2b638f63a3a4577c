"""The last lines of a run (io/report.py) and the progress bar's end."""

from __future__ import annotations

from pathlib import Path
from types import SimpleNamespace

import pytest

from granflow.io.report import final_lines, headline
from granflow.simulation.callbacks import ProgressBar

STOPPED = {"status": "stopped", "t_final": 0.93817, "stop_time_s": 0.88775, "steps": 956,
           "runout_m": 0.664562, "wall_height_m": 0.214334, "volume_relative_error": 2.2e-16,
           "wall_time_s": 48.78}


@pytest.mark.parametrize("summary, expected", [
    (STOPPED, "stopped: at rest from t = 0.888 s (run to t = 0.938 s, 956 steps)"),
    ({"status": "completed", "t_final": 1.02, "stop_time_s": None, "steps": 10},
     "completed: still moving at t_end = 1.02 s, 10 steps"),
    ({"status": "completed", "t_final": 1.02, "stop_time_s": 0.9, "steps": 10},
     "completed: at rest from t = 0.900 s, run to t_end = 1.02 s, 10 steps"),
    ({"status": "failed", "t_final": 0.31, "steps": 7, "message": "the mesh folded"},
     "failed at t = 0.31 s, 7 steps: the mesh folded"),
    ({"status": "failed", "message": "ValueError while building the problem: x"},
     "failed: ValueError while building the problem: x"),
])
def test_the_headline_says_how_the_run_ended(summary: dict, expected: str) -> None:
    assert headline(summary) == expected


def test_the_lines_give_the_results_and_where_the_figures_are(tmp_path: Path,
                                                              monkeypatch) -> None:
    root = tmp_path / "runs" / "r1"
    (root / "plots").mkdir(parents=True)
    monkeypatch.chdir(tmp_path)
    lines = final_lines(STOPPED, root)
    assert lines[1:] == ["  runout              0.6646 m",
                         "  height at the wall  0.2143 m",
                         "  volume error        2.2e-16",
                         "  wall time           48.8 s",
                         "  figures             runs/r1/plots",
                         "  run directory       runs/r1"]
    cylinder = final_lines(STOPPED | {"axis_height_m": 0.07}, root)
    assert "  height on the axis  0.0700 m" in cylinder
    (root / "plots" / "error.txt").write_text("OSError: disk full\n")
    assert "not drawn: see runs/r1/plots/error.txt" in final_lines(STOPPED, root)[5]


def test_the_volume_line_shows_the_correction_that_made_it_right(tmp_path: Path) -> None:
    """Restoring the area after each move makes the volume error round-off by
    construction: the line says how much was restored, in all and net."""
    corrected = STOPPED | {"area_correction_total": 0.0074096, "area_correction_net": -0.004645}
    assert final_lines(corrected, tmp_path)[3] == (
        "  volume error        2.2e-16 after corrections of 0.74 % in all (net -0.46 %)")
    drifted = STOPPED | {"volume_relative_error": 3.1e-4, "area_correction_total": 0.0}
    assert final_lines(drifted, tmp_path)[3] == "  volume error        0.00031"


def test_a_run_at_rest_ends_its_bar_at_100_percent(capsys: pytest.CaptureFixture) -> None:
    bar = ProgressBar(1.02, enabled=True)
    sim = SimpleNamespace(t=0.0, dt=0.01, last_report=None)
    for _ in range(94):
        sim.t += sim.dt
        bar(sim)
    bar.close("at rest from t = 0.888 s", complete=True)
    last = capsys.readouterr().err.replace("\r", "\n").strip().splitlines()[-1]
    assert last.startswith("100%") and "at rest from t = 0.888 s" in last


def test_a_notebook_counts_as_watched_and_gets_a_bar_it_can_show(monkeypatch) -> None:
    import sys
    import types

    from tqdm import tqdm

    from granflow.api import watched
    from granflow.simulation import callbacks

    monkeypatch.setitem(sys.modules, "ipykernel", types.ModuleType("ipykernel"))
    assert watched()
    try:
        import ipywidgets  # noqa: F401
    except ImportError:             # no widgets: the text bar, which a notebook shows too
        assert callbacks._bar_class() is tqdm
    else:
        from tqdm.notebook import tqdm as notebook_bar

        assert callbacks._bar_class() is notebook_bar
