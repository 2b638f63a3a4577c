"""The stress fields of the VTU snapshots against a layer at rest on an incline gentler than
its friction: whatever the law, the momentum balance of a uniform layer gives
sigma_xz = rho g sin(theta) (h - z) and sigma_zz = -rho g cos(theta) (h - z), and the yield
ratio |sigma'| / (sqrt(2) mu_s p) of simple shear is tan(theta) / mu_s everywhere. The
discrete layer holds both to round-off (cell means of fields linear in z); the tolerance,
1e-6 of the scale, leaves room for the regularised creep. Coarse: 16 cells across the 1 cm
layer, five steps of 2 ms (about a second)."""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np
import pytest

from granflow.config import load_config
from granflow.diagnostics.flow_fields import FlowSnapshot
from granflow.io.fields import FieldSnapshots
from granflow.io.run_dir import RunDir
from granflow.io.vtk import read_snapshot
from granflow.scenarios.plug_flow import build_plug_flow

SLOPE, HEIGHT, RHO, G = 15.0, 0.01, 1500.0, 9.81


@pytest.mark.parametrize("law", ["mu-i", "drucker-prager"])
def test_a_layer_at_rest_carries_its_weight(tmp_path: Path, law: str) -> None:
    config = load_config("incline-mu-i", [
        f"geometry.slope_deg={SLOPE}", f"material.rheology={law}", "time.t_end=0.01",
        "time.output_times=[]"])
    problem = build_plug_flow(config)
    problem.simulation.run()
    run_dir = RunDir.create(tmp_path / "run")
    FieldSnapshots(run_dir, FlowSnapshot(problem)).write(problem.simulation.t)
    fields = read_snapshot(run_dir.root, problem.simulation.t)

    z = fields.points[fields.triangles][:, :, 1].mean(axis=1)     # cell centroids
    depth = HEIGHT - z
    theta = math.radians(SLOPE)
    shear = RHO * G * math.sin(theta) * depth
    normal = -RHO * G * math.cos(theta) * depth
    scale = RHO * G * HEIGHT
    assert np.max(np.abs(fields["stress_xz"] - shear)) < 1e-6 * scale
    assert np.max(np.abs(fields["stress_zz"] - normal)) < 1e-6 * scale
    assert np.max(np.abs(fields["stress_xx"] - normal)) < 1e-6 * scale
    # |sigma'| = sqrt(2) tau in simple shear
    assert np.allclose(fields["deviatoric_stress_norm"], math.sqrt(2) * shear,
                       atol=1e-6 * scale)
    ratio = math.tan(theta) / config.material.mu_s       # 0.70: at rest, below yield
    assert np.allclose(fields["yield_ratio"], ratio, rtol=1e-6)
    assert np.nanmax(fields["yield_ratio"]) < 1.0
    assert np.max(np.abs(fields["velocity"])) < 1e-4     # and it is at rest
