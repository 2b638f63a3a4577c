"""Diagnosis: a packed run of the erosion study (``OUT/carried/VARIANT/ROW.tar.gz``, an
interrupted or failed row) resumed in a temporary folder with the deposition's step limit
logged (section 3.3: the step is cut so that the first free-surface node to reach the bed
lands on it). For every cut step: the step the controller proposed and the one the landing
allows, the landing node's height above the bed and its mesh velocity; whether each remesh
succeeded, and at the first that failed the boundary around the foremost vertex (the
front), which shows what the remesher was given. A failing row's cascade (steps falling
towards 1e-14 s, the mesh velocity of the landing nodes exploding on a mesh the remesher
could not replace) is read off in seconds.

Run: python benchmarks/landing_probe.py ARCHIVE [--until T] [--out DIR]

Writes DIR/landing_probe.json (the cut steps, the remeshes, the run's status and message)
and prints the cut steps below 1e-6 s. The probe wraps ``limit_step`` where the column's
mesh mover calls it and ``Simulation._remeshed``; nothing of the run's result changes.
"""

from __future__ import annotations

import argparse
import json
import sys
import tempfile
from pathlib import Path
from typing import Any

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parent))
from common.carry import unpack  # noqa: E402

import granflow  # noqa: E402
import granflow.ale.column_mover as column_mover  # noqa: E402
from granflow.ale import deposition  # noqa: E402
from granflow.ale.free_surface import BoundaryChain  # noqa: E402
from granflow.ale.remesh import boundary_loop  # noqa: E402
from granflow.config import load_config  # noqa: E402
from granflow.io.run_dir import RunDir  # noqa: E402
from granflow.simulation import simulation  # noqa: E402

TINY = 1e-6   # s: the cut steps printed
AROUND = 8    # boundary vertices recorded on each side of the front at a failed remesh


def probe(folder: Path, until: float) -> dict[str, Any]:
    """Resume the run in ``folder`` to ``until`` with the landing cuts and remeshes logged."""
    cuts: list[dict[str, Any]] = []
    remeshes: list[bool] = []
    front: list[dict[str, Any]] = []
    limit, remeshed = column_mover.limit_step, simulation.Simulation._remeshed

    def logged_limit(xy: np.ndarray, w: np.ndarray, candidates: np.ndarray, dt: float,
                     support: deposition.Support = deposition.LEVEL) -> tuple[float, np.ndarray]:
        allowed, landed = limit(xy, w, candidates, dt, support)
        if allowed < dt:
            node = int(candidates[np.argmin(deposition.landing_time(xy, w, candidates,
                                                                     support))])
            cuts.append({"proposed_s": dt, "allowed_s": allowed, "node": node,
                         "height_m": float(support.bed.height(xy[node:node + 1])[0]),
                         "w_m_s": [float(c) for c in w[node]], "landed": landed.tolist()})
        return allowed, landed

    def logged_remesh(self: simulation.Simulation) -> bool:
        done = remeshed(self)
        remeshes.append(done)
        if not done and not front and self.mesh_motion is not None:
            front.extend(around_front(self.mesh_motion.mesh))
        return done

    column_mover.limit_step = logged_limit   # type: ignore[assignment]
    simulation.Simulation._remeshed = logged_remesh   # type: ignore[method-assign]
    try:
        outputs = [t for t in load_config(folder / "config.toml").time.output_times
                   if t <= until]
        granflow.resume(folder, {"time.t_end": until, "time.output_times": outputs})
    finally:
        column_mover.limit_step = limit
        simulation.Simulation._remeshed = remeshed   # type: ignore[method-assign]
    summary = RunDir.summary(folder)
    return {"status": summary.get("status"), "message": summary.get("message"),
            "t_final": summary.get("t_final"), "cut_steps": cuts,
            "remeshes": len(remeshes), "remesh_failures": remeshes.count(False),
            "front_at_failed_remesh": front}


def around_front(mesh: Any) -> list[dict[str, Any]]:
    """The boundary loop's vertices around its foremost one: label of the edge leaving
    each, x and the height z (m)."""
    loop, labels = boundary_loop(BoundaryChain(mesh))
    xy = mesh.ngmesh.Coordinates()[loop]
    tip = int(np.argmax(xy[:, 0]))
    return [{"label": labels[i % len(loop)], "x_m": float(xy[i % len(loop), 0]),
             "z_m": float(xy[i % len(loop), 1])} for i in range(tip - AROUND, tip + AROUND + 1)]


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("archive", type=Path)
    parser.add_argument("--until", type=float, default=None,
                        help="end time of the resumed run (s; default: its own t_end)")
    parser.add_argument("--out", type=Path, default=Path("benchmarks/results/landing_probe"))
    args = parser.parse_args()
    if not args.archive.is_file():
        parser.error(f"archive '{args.archive}' is not a file")
    with tempfile.TemporaryDirectory() as scratch:
        folder = Path(scratch) / "run"
        unpack(args.archive, folder)
        until = args.until or load_config(folder / "config.toml").time.t_end
        record = {"archive": str(args.archive), "until_s": until} | probe(folder, until)
    args.out.mkdir(parents=True, exist_ok=True)
    (args.out / "landing_probe.json").write_text(json.dumps(record, indent=1) + "\n")
    print(f"{record['status']} at t = {record['t_final']:.6g} s: {record['message']}")
    print(f"{len(record['cut_steps'])} steps cut by a landing; remeshes {record['remeshes']}, "
          f"failed {record['remesh_failures']}")
    for vertex in record["front_at_failed_remesh"]:
        print(f"  {vertex['label']:8s} x = {vertex['x_m']:.6f} m, z = {vertex['z_m']:.3e} m")
    for cut in record["cut_steps"]:
        if cut["allowed_s"] < TINY:
            print(f"  proposed {cut['proposed_s']:.3g} s, allowed {cut['allowed_s']:.3g} s: "
                  f"node {cut['node']} {cut['height_m']:.3g} m above the bed, "
                  f"w = ({cut['w_m_s'][0]:.4g}, {cut['w_m_s'][1]:.4g}) m/s")


if __name__ == "__main__":
    main()
