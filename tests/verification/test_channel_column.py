"""The column in a channel in 3D (``geometry.dimension = 3``): a coarse run with its outputs,
what 3D refuses, and the column between frictionless side walls against the 2D plane-strain
run of the same section (the independent solution: the section's own solver and mover).

The plane-strain check follows the acceptance of the 3D work: runout within 2 % and the
free surface along the centre line within 2 mm, coarse (mesh.size 0.03 m) and over the
first part of the collapse (0.2 s, the front still moving)."""

import json
from pathlib import Path

import numpy as np
import pytest

from granflow.app.api import Run, run
from granflow.config import ConfigError, load_config

COARSE = ["geometry.dimension=3", "mesh.size=0.04", "time.t_end=0.02",
          "time.output_times=[0.01]", "boundary.channel_width=0.1"]


@pytest.fixture(scope="module")
def channel(tmp_path_factory: pytest.TempPathFactory) -> Run:
    out = tmp_path_factory.mktemp("channel") / "run"
    return run("rectangle-rigid", COARSE, out=out, progress=False)


def test_a_coarse_3d_column_runs_with_its_outputs(channel: Run) -> None:
    """Completed, the mass spreading along the bed with its volume kept; the centre-line
    and side-wall surfaces at the output time and at the end; VTU of tetrahedra."""
    summary = json.loads((channel.root / "summary.json").read_text())
    assert summary["status"] == "completed", summary["message"]
    assert summary["runout_m"] > 0.2                 # the front has left x = l0
    assert abs(summary["volume_relative_error"]) < 1e-9
    assert summary["channel_span_m"] == [0.0, 0.05]   # half the channel: the centre plane
    for kind in ("free_surface", "free_surface_wall"):
        for t in (0.01, None):
            profile = channel.profile(kind, t)
            assert len(profile) >= 3 and profile["z"].max() > 0.1
    vtu = sorted((channel.root / "fields").glob("*.vtu"))
    assert vtu and b"UnstructuredGrid" in vtu[-1].read_bytes()[:400]


@pytest.mark.parametrize("setting, words", [
    ("material.rheology=nonlocal", "not verified in 3D"),
    ("numerics.method=augmented-lagrangian", "2 x 2 tensors"),
    ("gate.enabled=true", "not available in 3D"),
    ("geometry.erodible_thickness=0.005", "not available in 3D")])
def test_3d_column_refuses_what_is_not_verified(setting: str, words: str) -> None:
    with pytest.raises(ConfigError, match=words):
        load_config("rectangle-rigid", ["geometry.dimension=3", setting])


PLANE = ["mesh.size=0.03", "time.t_end=0.2", "time.output_times=[0.1, 0.2]",
         "time.stop_at_rest=false"]
RUNOUT_REL, SURFACE_M = 0.02, 0.002


def _surface_gap(a: Run, b: Run, t: float) -> float:
    """The largest vertical distance between two centre-line surfaces at time t (m)."""
    p, q = a.profile("free_surface", t), b.profile("free_surface", t)
    x = np.linspace(0.0, min(p["x"].max(), q["x"].max()), 400)
    zp = np.interp(x, *(p.sort_values("x")[k].to_numpy() for k in ("x", "z")))
    zq = np.interp(x, *(q.sort_values("x")[k].to_numpy() for k in ("x", "z")))
    return float(np.abs(zp - zq).max())


@pytest.mark.slow
def test_between_frictionless_walls_the_column_is_the_plane_strain_one(
        tmp_path: Path) -> None:
    plane = run("rectangle-rigid", PLANE, out=tmp_path / "2d", progress=False)
    slab = run("rectangle-rigid", [*PLANE, "geometry.dimension=3",
                                   "boundary.channel_width=none"],
               out=tmp_path / "3d", progress=False)
    for r in (plane, slab):
        assert r.summary.status == "completed", r.summary.message
    assert slab.summary.runout_m == pytest.approx(plane.summary.runout_m, rel=RUNOUT_REL)
    for t in (0.1, 0.2):
        assert _surface_gap(plane, slab, t) <= SURFACE_M, t
