"""Errors from a remesh in a real run: the mesher's own failures are of the types the
scenarios hand the loop (``geometry/mesh.py: MESHER_FAILURES``), a degenerate boundary
shapely cannot read is wrapped into ``MeshingFailed`` where it is read, and a defect ends
the run at once with a failed summary, a checkpoint and the way to continue."""

from __future__ import annotations

import json
from pathlib import Path

import ngsolve as ngs
import numpy as np
import pytest
from netgen.occ import OCCGeometry, Pnt, Segment, ThruSections, Wire

import granflow
from granflow.fem.locator import PointLocator
from granflow.geometry.mesh import MESHER_FAILURES
from granflow.scenarios.column_remesher import ColumnRemesher
from granflow.simulation.outcomes import MeshingFailed
from granflow.simulation.remesh_errors import mesher_failed


def test_netgen_failing_on_a_degenerate_loft_is_a_mesher_failure() -> None:
    """Two equal sections: OCC makes a flat loft, Netgen cannot triangulate it."""
    points = [Pnt(0, 0, 0), Pnt(1, 0, 0), Pnt(0, 0, 1)]
    wire = Wire([Segment(points[i], points[(i + 1) % 3]) for i in range(3)])
    with pytest.raises(Exception) as raised:
        OCCGeometry(ThruSections([wire, wire])).GenerateMesh(maxh=0.5)
    assert mesher_failed(raised.value, MESHER_FAILURES)
    assert not isinstance(raised.value, RuntimeError)   # Netgen's own type, listed apart


def test_a_boundary_shapely_cannot_read_is_a_meshing_failure() -> None:
    mesh = ngs.Mesh(ngs.unit_square.GenerateMesh(maxh=0.5))
    locator = PointLocator(mesh)
    locator.loop = locator.loop[:2]                 # a boundary of two vertices
    with pytest.raises(MeshingFailed, match="not a polygon"):
        locator.locate(np.array([[2.0, 2.0]]))      # outside: the boundary is read


def test_a_run_whose_remesh_raises_a_defect_fails_at_once_with_a_readable_folder(
        tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    calls = []

    def broken(self: ColumnRemesher) -> None:
        calls.append(self.simulation.step)
        raise AttributeError("'ColumnDiscretisation' object has no attribute 'mover2'")

    monkeypatch.setattr(ColumnRemesher, "needs_remesh", lambda self: self.simulation.step == 3)
    monkeypatch.setattr(ColumnRemesher, "remesh", broken)
    out = tmp_path / "run"
    run = granflow.run("rectangle-rigid", ["mesh.size=0.04", "time.t_end=0.05",
                                           "time.output_times=[0.05]"], out,
                       progress=False)
    summary = json.loads((out / "summary.json").read_text())
    assert calls == [3]
    assert summary["status"] == "failed" and summary["steps"] == 3
    assert summary["remesh_failures"] == {"AttributeError": 1}
    for part in ("after step 3 at t = ", "remeshing raised AttributeError in broken",
                 "a defect in granflow", "continue with `granflow resume"):
        assert part in summary["message"]
    assert run.summary.status == "failed" and (out / "checkpoint").is_dir()
    assert len(run.diagnostics["t"]) == 3           # the step that asked for it is kept


def test_the_loops_retry_what_their_meshers_raise() -> None:
    """The column's loop retries Netgen's and the geometry checks' failures; the channel's
    also OCC's (a loft OCC cannot build); neither a defect."""
    from netgen.occ import OCCException

    from granflow.config import load_config
    from granflow.scenarios.channel_column import build_channel_column
    from granflow.scenarios.column import build_column

    column = build_column(load_config("rectangle-rigid", ["mesh.size=0.04"])).simulation
    channel = build_channel_column(load_config("rectangle-rigid", [
        "mesh.size=0.04", "geometry.dimension=3", "boundary.channel_width=0.1"])).simulation
    for error in (MeshingFailed("x"), RuntimeError("x")):
        assert mesher_failed(error, column.mesher_failures)
        assert mesher_failed(error, channel.mesher_failures)
    assert mesher_failed(OCCException("x"), channel.mesher_failures)
    for defect in (TypeError("x"), AttributeError("x"), NotImplementedError("x")):
        assert not mesher_failed(defect, channel.mesher_failures)
