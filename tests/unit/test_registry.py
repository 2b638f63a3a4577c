"""The problem kinds (``scenarios/registry.py``): the runner builds a run and draws its
figures by the kind's registration alone, and a part added to the loop as a named callback
brings its own outputs into the run directory's files without the runner or the files'
writers being told about it."""

from __future__ import annotations

import json
import re
from pathlib import Path
from typing import Any

import numpy as np
import pytest

from granflow.config import load_config
from granflow.io.diagnostics import COLUMNS, read_diagnostics
from granflow.io.profiles import final_profile, profile_at
from granflow.io.run_dir import RunDir
from granflow.io.vtk import read_snapshot
from granflow.runner import run_simulation
from granflow.scenarios import registry
from granflow.scenarios.plug_flow import build_plug_flow
from granflow.simulation.callbacks import EveryNSteps, add_callback
from granflow.simulation.outputs import Outputs

SOURCE = Path(__file__).resolve().parents[2] / "src" / "granflow"
TINY = ["time.t_end=0.01248", "time.output_times=[0.00624]"]   # 4 steps of 3.12 ms


class Probe(Outputs):
    """A new part's outputs: a column, a profile, cell data, a summary member, a figure."""

    columns = ("probe_steps",)

    def __init__(self, problem: Any) -> None:
        self.problem, self.steps = problem, 0

    def __call__(self, sim: Any) -> None:
        self.steps += 1

    def diagnostics(self, sim: Any, cell_speed: np.ndarray) -> dict[str, float]:
        return {"probe_steps": float(self.steps)}

    def profiles(self, t: float) -> dict[str, tuple[list[str], np.ndarray]]:
        return {"probe": (["x", "z"], np.array([[0.0, t], [1.0, 2 * t]]))}

    def fields(self) -> dict[str, np.ndarray]:
        return {"probe_cells": np.full(self.problem.mesh.ne, float(self.steps))}

    def summary(self, result: Any) -> dict[str, Any]:
        return {"probe_steps": self.steps}


def probe_figure(run_dir: RunDir, config: Any) -> None:
    """A figure from the files alone: the profile's rows, as text."""
    profile = final_profile(run_dir.root, "probe")
    if profile is not None:
        run_dir.write_text("plots/probe.txt", f"{len(profile['x'])} rows\n")


def build_probed(config: Any) -> Any:
    """The periodic layer, with the probe counting every other step."""
    problem = build_plug_flow(config)
    add_callback(problem.simulation, Probe(problem), "probe", schedule=EveryNSteps(2))
    return problem


def test_a_kind_is_built_and_drawn_by_its_registration(tmp_path: Path,
                                                       monkeypatch: pytest.MonkeyPatch) -> None:
    registry.problem_kind("periodic-layer")           # the built-in kinds registered
    monkeypatch.setitem(registry.KINDS, "periodic-layer", registry.ProblemKind(
        "periodic-layer", build_probed, (probe_figure,)))
    config = load_config("plug-flow", TINY)
    run_dir = RunDir.create(tmp_path / "run")
    with run_dir.lock():
        run_dir.write_text("config.toml", "")
        summary = run_simulation(config, run_dir, progress=False)
    assert summary["status"] == "completed" and summary["steps"] == 4
    assert summary["probe_steps"] == 2                      # steps 2 and 4
    assert json.loads((tmp_path / "run" / "summary.json").read_text())["probe_steps"] == 2
    table = read_diagnostics(tmp_path / "run")
    assert list(table.columns) == [*COLUMNS, "probe_steps"]
    assert table["probe_steps"].tolist() == [0.0, 1.0, 1.0, 2.0]
    assert profile_at(tmp_path / "run", "probe", 0.00624)["z"][1] == pytest.approx(0.01248)
    assert read_snapshot(tmp_path / "run", 0.01248).cell_data["probe_cells"].max() == 2.0
    assert (tmp_path / "run" / "plots" / "probe.txt").read_text() == "2 rows\n"
    assert not (tmp_path / "run" / "plots" / "velocity_profile.png").exists()


def test_an_unknown_kind_is_named_with_the_known_ones() -> None:
    with pytest.raises(ValueError, match=r"'sandpile' is not a registered problem kind; "
                                         r"known: column, periodic-layer, slab"):
        registry.problem_kind("sandpile")


def test_neither_the_runner_nor_the_output_modules_ask_for_the_kind_or_the_layer() -> None:
    """What a run writes comes from its kind's registration and the loop's callbacks: no
    test of geometry.kind, of the erodible layer or of a layer's material in them."""
    asks = re.compile(r"geometry\.kind|\.kind ?[!=]=|erodible_thickness ?[<>]|layer ?=|"
                      r"layer is (not )?None|TwoMaterials|mobilisation_cells")
    files = [SOURCE / "app" / "run.py", *sorted((SOURCE / "io").glob("*.py")),
             SOURCE / "scenarios" / "column_measures.py"]
    found = [f"{f.name}:{i}" for f in files
             for i, line in enumerate(f.read_text(encoding="utf-8").splitlines(), 1)
             if asks.search(line)]
    assert found == []
    assert asks.search("if config.geometry.erodible_thickness > 0:")   # the pattern bites
