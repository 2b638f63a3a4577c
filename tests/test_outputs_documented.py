"""Every key, column, field and profile a run writes is in a table of docs/outputs.md, with
its unit: one short run of each kind of output (a rigid column, a layer of its own
hysteretic material meshed ahead of the flow, the nonlocal and mu(I) laws, an erodible
cylinder, the periodic layer), each a few steps on a coarse mesh."""

from __future__ import annotations

import json
import re
import warnings
from pathlib import Path

import pytest

import granflow
from granflow.io.profiles import list_profiles

PAGE = Path(__file__).resolve().parents[1] / "docs" / "outputs.md"
SHORT = {"time.t_end": 0.004, "time.output_times": [0.004], "time.stop_at_rest": False,
         "output.progress": False}
CASES = {
    "rigid column": ("trapezoid-rigid", {"mesh.size": 0.06, "surface_tension.enabled": True}),
    "two-material layer": ("trapezoid-erodible", {
        "mesh.size": 0.06, "layer.friction": "hysteretic", "layer.friction_angle_deg": 24.0,
        "layer.start_friction_angle_deg": 26.0, "mesh.layer_ahead": 0.1}),
    "nonlocal": ("rectangle-rigid", {"mesh.size": 0.04, "material.rheology": "nonlocal",
                                     "material.preset": "glass-beads"}),
    "mu(I)": ("rectangle-rigid", {"mesh.size": 0.04, "material.rheology": "mu-i",
                                  "material.preset": "glass-beads"}),
    "erodible cylinder": ("cylinder-erodible", {"mesh.size": 0.04}),
    "packing": ("rectangle-rigid", {"mesh.size": 0.04, "material.packing": "critical-state"}),
    "periodic layer": ("plug-flow", {"time.t_end": 0.02, "time.output_times": [0.02],
                                     "time.stop_at_rest": None}),
}


def documented(section: str) -> set[str]:
    """The names in the first column of the tables under ``## section`` of the page."""
    text = PAGE.read_text(encoding="utf-8")
    body = text.split(f"\n## {section}\n", 1)[1].split("\n## ", 1)[0]
    rows = [" ".join(line.split("|")[1:3]) for line in body.splitlines()
            if line.startswith("| `")]      # a profile's columns are in its second cell
    return {name.strip() for cell in rows for names in re.findall(r"`([^`]+)`", cell)
            for name in names.split(",")}


@pytest.fixture(scope="module")
def runs(tmp_path_factory: pytest.TempPathFactory) -> dict[str, granflow.Run]:
    out = {}
    for name, (scenario, overrides) in CASES.items():
        settings = {k: v for k, v in (SHORT | overrides).items() if v is not None}
        with warnings.catch_warnings():
            warnings.simplefilter("ignore", granflow.config.ConfigNote)
            run = granflow.run(scenario, settings, progress=False,
                               out=tmp_path_factory.mktemp("run") / "r")
        assert run.summary.status == "completed", (name, run.summary.message)
        out[name] = run
    return out


def test_the_page_has_its_tables() -> None:
    assert {"status", "stop_time_s", "runout_m"} <= documented("`summary.json`")
    assert {"t", "front_x", "fluidity_mean"} <= documented("`diagnostics.csv`")
    assert {"velocity", "yield_ratio", "fluidity"} <= documented("The fields")


def test_every_summary_key_is_documented(runs: dict[str, granflow.Run]) -> None:
    known = documented("`summary.json`")
    for name, run in runs.items():
        keys = json.loads((run.root / "summary.json").read_text(encoding="utf-8"))
        assert set(keys) <= known, f"{name}: {sorted(set(keys) - known)} not in docs/outputs.md"


def test_every_diagnostics_column_is_documented(runs: dict[str, granflow.Run]) -> None:
    known = documented("`diagnostics.csv`")
    for name, run in runs.items():
        columns = set(run.diagnostics.columns)
        assert columns <= known, f"{name}: {sorted(columns - known)} not in docs/outputs.md"


def test_every_field_is_documented(runs: dict[str, granflow.Run]) -> None:
    known = documented("The fields")
    for name, run in runs.items():
        fields = run.fields(run.output_times[-1])
        written = set(fields.point_data) | set(fields.cell_data)
        assert written <= known, f"{name}: {sorted(written - known)} not in docs/outputs.md"


def test_every_profile_and_its_columns_are_documented(runs: dict[str, granflow.Run]) -> None:
    known = documented("Profiles")
    for name, run in runs.items():
        kinds = {path.name.rsplit("_", 1)[0] for path in (run.root / "profiles").glob("*.csv")}
        assert kinds, name
        for kind in kinds:
            assert kind in known, f"{name}: profile {kind} not in docs/outputs.md"
            columns = set(list_profiles(run.root, kind)[0].read()) - {"t"}
            assert columns <= known, f"{name}: {kind}'s {sorted(columns - known)}"
