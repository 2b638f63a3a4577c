"""The column in a channel in 3D (``geometry.dimension = 3``): a coarse run with its outputs,
what 3D refuses, and the column between frictionless side walls against the 2D plane-strain
run of the same section (the independent solution: the section's own solver and mover).

The plane-strain check: runout within 2 % and the free surface along the centre line within
2 mm, coarse (mesh.size 0.02 m) over the first part of the collapse (0.2 s, the front still
moving). The surfaces meet it behind the front's last mesh.size; at the front's foot they do
not (an expected failure, kept so that it is seen when it changes)."""

import json
import shutil
from pathlib import Path

import numpy as np
import pytest

from granflow.app.api import Run, resume, run
from granflow.config import ConfigError, load_config
from granflow.geometry.polylines import point_to_polyline
from granflow.io.profiles import curves

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


def test_a_3d_run_extended_from_its_checkpoint_is_the_uninterrupted_one(
        channel: Run, tmp_path: Path) -> None:
    """The coarse run, copied and extended to 0.03 s from its checkpoint (mesh, fields,
    mover and remesh record restored), against the run made to 0.03 s at once: the same
    steps, the runout within 1e-5 (the nonlinear tolerance's order)."""
    copy = tmp_path / "extended"
    shutil.copytree(channel.root, copy)
    extended = resume(copy, {"time.t_end": 0.03})
    straight = run("rectangle-rigid", [*COARSE[:2], "time.t_end=0.03", *COARSE[3:]],
                   out=tmp_path / "straight", progress=False)
    assert extended.summary.status == straight.summary.status == "completed"
    assert extended.summary.steps == straight.summary.steps
    assert extended.summary.runout_m == pytest.approx(straight.summary.runout_m, rel=1e-5)


@pytest.mark.parametrize("setting, words", [
    ("material.rheology=nonlocal", "not verified in 3D"),
    ("material.packing=critical-state", "not verified in 3D"),
    ("numerics.method=augmented-lagrangian", "2 x 2 tensors"),
    ("gate.enabled=true", "not available in 3D"),
    ("geometry.erodible_thickness=0.005", "not available in 3D"),
    ("boundary.bed=no-slip", "not verified in 3D")])
def test_3d_column_refuses_what_is_not_verified(setting: str, words: str) -> None:
    with pytest.raises(ConfigError, match=words):
        load_config("rectangle-rigid", ["geometry.dimension=3", setting])


PLANE = ["mesh.size=0.02", "time.t_end=0.2", "time.output_times=[0.1, 0.2]",
         "time.stop_at_rest=false"]
SIZE, TIMES, RUNOUT_REL, SURFACE_M = 0.02, (0.1, 0.2), 0.02, 0.002


@pytest.fixture(scope="module")
def plane_pair(tmp_path_factory: pytest.TempPathFactory) -> tuple[Run, Run]:
    """The rectangle in 2D and between two frictionless planes in 3D, to 0.2 s."""
    root = tmp_path_factory.mktemp("plane_strain")
    plane = run("rectangle-rigid", PLANE, out=root / "2d", progress=False)
    slab = run("rectangle-rigid", [*PLANE, "geometry.dimension=3",
                                   "boundary.channel_width=none"],
               out=root / "3d", progress=False)
    for r in (plane, slab):
        assert r.summary.status == "completed", r.summary.message
    return plane, slab


def _distances(pair: tuple[Run, Run], t: float, behind: float) -> np.ndarray:
    """Distances from the points of each centre-line surface lying more than ``behind``
    behind the nearer front to the other surface (symmetric, ``geometry/polylines.py``)."""
    a, b = (curves(r.root, "free_surface", [t])[t] for r in pair)
    end = min(a[:, 0].max(), b[:, 0].max()) - behind
    return np.concatenate([point_to_polyline(a[a[:, 0] <= end], b),
                           point_to_polyline(b[b[:, 0] <= end], a)])


@pytest.mark.slow
def test_between_frictionless_walls_the_runout_is_the_plane_strain_one(
        plane_pair: tuple[Run, Run]) -> None:
    plane, slab = plane_pair
    assert slab.summary.runout_m == pytest.approx(plane.summary.runout_m, rel=RUNOUT_REL)


@pytest.mark.slow
@pytest.mark.parametrize("t", TIMES)
def test_between_frictionless_walls_the_surface_is_the_plane_strain_one(
        plane_pair: tuple[Run, Run], t: float) -> None:
    """Within 2 mm at each output time, the front's foot (its last mesh.size) left out."""
    assert _distances(plane_pair, t, SIZE).max() <= SURFACE_M, t


@pytest.mark.slow
@pytest.mark.xfail(strict=True, reason="the front's foot: the 2D run's thin tongue (under "
                   "1 mm thick) against the 3D slab's blunter front (docs/three_d.md)")
def test_between_frictionless_walls_the_front_foot_is_the_plane_strain_one(
        plane_pair: tuple[Run, Run]) -> None:
    for t in TIMES:
        assert _distances(plane_pair, t, 0.0).max() <= SURFACE_M, t


# mu(I) and the trapezoid between frictionless walls, against their plane-strain runs with
# the same criteria (the trapezoid, 1.5 times the rectangle's size, at 1.5 times the mesh).
# Neither meets them at these coarse sizes: expected failures, strict, so that a change
# shows. Both gaps are the discretisation's: they shrink at about second order with the
# mesh size (``benchmarks/three_d_collapse.py plane-strain``, docs/three_d.md)
OTHERS = {"mu-i": ("rectangle-rigid", ["material.rheology=mu-i"], SIZE),
          "trapezoid": ("trapezoid-rigid", [], 0.03)}
MISSES = {"mu-i": "the 3D runout 2.5 % short of the plane-strain one (0.3034 m against "
                  "0.3111 m at 0.2 s), the Drucker-Prager rectangle's 1.0 %",
          "trapezoid": "the surfaces 5.4 mm apart behind the front's last mesh.size at "
                       "0.1 s (runout within 2 %)"}


@pytest.fixture(scope="module", params=[
    pytest.param(case, marks=pytest.mark.xfail(strict=True, reason=MISSES[case]))
    for case in sorted(OTHERS)])
def other_pair(request: pytest.FixtureRequest,
               tmp_path_factory: pytest.TempPathFactory) -> tuple[Run, Run, float]:
    scenario, extra, size = OTHERS[request.param]
    root = tmp_path_factory.mktemp(f"plane_strain_{request.param}")
    sets = [*extra, f"mesh.size={size!r}", *PLANE[1:]]
    plane = run(scenario, sets, out=root / "2d", progress=False)
    slab = run(scenario, [*sets, "geometry.dimension=3", "boundary.channel_width=none"],
               out=root / "3d", progress=False)
    for r in (plane, slab):
        assert r.summary.status == "completed", r.summary.message
    return plane, slab, size


@pytest.mark.slow
def test_mu_i_and_the_trapezoid_between_frictionless_walls_are_plane_strain(
        other_pair: tuple[Run, Run, float]) -> None:
    """Runout within 2 % and the centre-line surface within 2 mm behind the front's foot at
    both output times, as the Drucker-Prager rectangle above."""
    plane, slab, size = other_pair
    assert slab.summary.runout_m == pytest.approx(plane.summary.runout_m, rel=RUNOUT_REL)
    for t in TIMES:
        assert _distances((plane, slab), t, size).max() <= SURFACE_M, t
