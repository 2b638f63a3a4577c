"""Every configuration key either changes a result or is rejected.

The test walks the schema for two tiny cases, a column over an erodible layer and the plug
flow: each key is set to another valid value, and the run (a few steps, in-process) must
differ from the baseline in its summary, its diagnostics, the files it writes or what it
prints, or the value must be refused with a ConfigError (``granflow.config.inert_keys``).
Some keys only act in a situation a few steps cannot reach; their ``CONTEXT`` sets it up
(the same context on both sides of the comparison).
"""

from __future__ import annotations

import contextlib
import io
import json
import math
import tempfile
from pathlib import Path
from typing import Any, Literal, get_args, get_origin

import pytest

from granflow.config import SECTIONS, Config, ConfigError, load_config, parse_value
from granflow.config.kinds import kind_names
from granflow.io.run_dir import RunDir
from granflow.runner import run_simulation

TINY = {
    "column": ("trapezoid-erodible", [
        "mesh.size=0.06", "geometry.erodible_thickness=0.02", "mesh.layer_cells=1",
        "geometry.bed_length=0.35", "geometry.height=0.27", "time.t_end=1e-3",
        "time.output_times=[]", "surface_tension.trigger_angle_deg=60",
        "surface_tension.release_angle_deg=30"]),
    "slab": ("slab", [
        "time.t_end=0.01", "geometry.erodible_thickness=0.005", "mesh.size=0.0025",
        "time.output_times=[]", "initial.slab_speed=0.5"]),
    "plug": ("plug-flow", [
        "mesh.size=0.5", "time.dt=0.02", "time.t_end=0.06", "time.output_times=[]",
        "numerics.eps=1e-2", "numerics.mesh_velocity=vertical"]),
}
# Other valid values where "the next value" is not one a short run can tell apart.
ALTERNATIVE = {
    "numerics.max_iterations": 4, "mesh.remesh_quality": 0.0, "numerics.velocity_floor": 10.0,
    "numerics.penalty": 1e6, "boundary.penalty": 1e6, "numerics.mesh_penalty": 1e4,
    "time.output_times": "[1e-3]", "output.vtk_every": 1, "output.checkpoint_every": 1,
    "surface_tension.trigger_angle_deg": 0, "surface_tension.delta": 2,
    "surface_tension.gamma0": 100.0, "time.dt": 5e-4,
    "mesh.failure_remesh_quality": 0.95, "time.error_tol": 0.5, "time.error_floor": 1.0,
    "geometry.bed_length": 0.5, "geometry.erodible_thickness": 0.03, "time.dt_max": 1e-4,
    "numerics.tol": 1e-2, "numerics.eps_friction": 1e-2, "numerics.al_r": 100.0,
    "layer.rheology": '"mu-i"', "layer.density": 1400.0, "layer.viscosity": 0.5,
    "mesh.layer_ahead": 0.1,
    "layer.grain_diameter": 1e-8, "material.grain_diameter": 1e-8,   # any creep is "displaced"
    "material.initial_mobilisation": 0.5, "layer.friction": '"hysteretic"',
    "layer.packing": '"critical-state"', "material.packing_slope": 0.2,
    "numerics.anderson_depth": 0,   # a few steps never fill a history deeper than three
    "material.fluidity_time": 0.01,   # its only other literal is the current "inertial"
    "initial.fluidity": 0.5,
    "mesh.layer_rest_coarsening": 1.0,   # larger ones are capped by mesh.size on this mesh
}
CONTEXT = {   # both runs: failing solves, so that the failure remesh has something to do;
    "mesh.failure_remesh_quality": ["numerics.max_iterations=4"],
    "mesh.remesh_quality": ["time.t_end=0.15"],   # long enough for the mesh to degrade
    "mesh.layer_ahead": ["geometry.bed_length=0.5"],   # longer than the column + 0.1 m
    # the adaptive mesh's sizes at rest act from the first remesh, over a layer long enough
    # to rest beyond the flow's reach
    "mesh.rest_coarsening": ["time.t_end=0.1"],
    "mesh.layer_rest_coarsening": ["geometry.bed_length=0.8"],
    "mesh.flow_margin": ["geometry.bed_length=0.8"],
    # the glass-bead preset's constants for Drucker-Prager are the defaults; for mu(I) it
    # sets the angle that goes with mu_2 and I0 (20.9 degrees instead of 25.5)
    "material.preset": ['material.rheology="mu-i"'],
    # a flow at rest at the start may step up to dt_max_slow: dt_max caps it without one
    "time.dt_max": ['time.dt_max_slow="none"'],
}
# A case's own context: the plug's packing (0.4) far below phi_c fails every halved step,
# each within 50 iterations here instead of the plug flow's 1,000 (its steps need about 4).
CASE_CONTEXT = {"plug": {"material.packing": ["numerics.max_iterations=50"]}}
# Keys whose effect needs a run to rest or a fold that releases: a few steps cannot show
# it, so a test of the part they drive shows it instead (named here).
ELSEWHERE = {
    "time.rest_fraction": "tests/unit/test_timestep.py (RestCriterion)",
    "time.rest_duration": "tests/unit/test_timestep.py (RestCriterion)",
    "surface_tension.release_angle_deg": "tests/unit/test_surface_tension.py (hysteresis)",
    "time.stop_at_rest": "tests/verification/test_collapse.py (the stalled column stops)",
    "output.figure_format": "tests/test_figures.py (the figures' files)",   # figures are
    "output.dpi": "tests/test_figures.py (the figures' files)",   # not drawn here (fixture)
    # the cap rises only once the flow is slow and the controller's steps have grown to it
    "time.dt_max_slow": "tests/unit/test_timestep.py (the slow flow's cap)",
    "time.slow_courant": "tests/unit/test_timestep.py (the slow flow's cap)",
}


def other_value(config: Config, section: str, key: str) -> Any:
    """A valid value of ``section.key`` different from the one in ``config``."""
    dotted = f"{section}.{key}"
    value = getattr(getattr(config, section), key)
    if dotted in ALTERNATIVE and parse_value(str(ALTERNATIVE[dotted])) != value:
        return ALTERNATIVE[dotted]
    tp = SECTIONS[section].model_fields[key].annotation
    literals = [a for t in (tp, *get_args(tp)) if get_origin(t) is Literal for a in get_args(t)]
    if dotted == "geometry.kind":       # the registered kinds
        literals = kind_names()
    if literals:
        choice = next(c for c in literals if c != value)
        return f'"{choice}"'
    if isinstance(value, bool):
        return str(not value).lower()
    if isinstance(value, int):
        return value + 1
    if isinstance(value, float):
        if key.endswith("_deg"):
            return min(value + 5.0, 80.0) if value < 80 else value - 5.0
        return value * (0.8 if 0 < value < 1 else 1.25)
    if value is None:
        return 1e-4 if key == "dt" else 0.5
    raise AssertionError(f"no alternative for {dotted} = {value!r}")


def fingerprint(scenario: str, overrides: list[str]) -> str:
    """Everything a user can see of a short run: summary, diagnostics, files, terminal."""
    config = load_config(scenario, overrides)
    with tempfile.TemporaryDirectory() as tmp:
        run_dir = RunDir.create(Path(tmp) / "run")
        err = io.StringIO()
        with contextlib.redirect_stderr(err), run_dir.lock():
            summary = run_simulation(config, run_dir, progress=config.output.progress)
        summary = {k: v for k, v in summary.items() if k not in ("wall_time_s",)}
        diagnostics = (run_dir.root / "diagnostics.csv").read_text()
        files = sorted(str(p.relative_to(run_dir.root)) for p in run_dir.root.rglob("*")
                       if p.is_file() and p.suffix != ".lock")
    return json.dumps([summary, diagnostics, files, bool(err.getvalue().strip())],
                      default=lambda x: None if isinstance(x, float) and math.isnan(x) else x)


@pytest.fixture(autouse=True)
def no_figures(monkeypatch: pytest.MonkeyPatch) -> None:
    """Figures are drawn from the files compared here; skipping them saves most of the time."""
    from granflow import runner

    monkeypatch.setattr(runner, "draw_figures", lambda run_dir, config: None)


@pytest.mark.parametrize("case", [pytest.param(c, marks=pytest.mark.slow) if c != "plug"
                                  else c for c in sorted(TINY)])
def test_every_key_changes_a_result_or_is_rejected(case: str) -> None:
    scenario, base = TINY[case]
    config = load_config(scenario, base)
    baselines: dict[tuple[str, ...], str] = {}
    silent = []
    for section, model in SECTIONS.items():
        for key in model.model_fields:
            dotted = f"{section}.{key}"
            if dotted in ELSEWHERE or key == "linear_solver":   # one solver without MKL
                continue
            context = [*CONTEXT.get(dotted, []), *CASE_CONTEXT.get(case, {}).get(dotted, [])]
            changed = [*base, *context, f"{dotted}={other_value(config, section, key)}"]
            try:
                load_config(scenario, changed)
            except ConfigError:
                continue                                  # rejected: fine
            ctx = tuple(context)
            if ctx not in baselines:
                baselines[ctx] = fingerprint(scenario, [*base, *context])
            if fingerprint(scenario, changed) == baselines[ctx]:
                silent.append(dotted)
    assert silent == [], f"keys that neither change a result nor are rejected: {silent}"
