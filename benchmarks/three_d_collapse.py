"""Benchmark: the 3D rectangle collapse in a channel, run by ``granflow run`` as a user runs
it: its processor time to rest and its profile, on one process or under ``mpiexec``, and the
column between frictionless walls against the 2D plane-strain run.

Run: python benchmarks/three_d_collapse.py rest [--size 0.04] [--ranks 1]
     python benchmarks/three_d_collapse.py plane-strain [--size 0.03] [--t-end 0.2]
         [--out benchmarks/results/three_d_collapse]

``rest``: the rectangle-rigid scenario (l0 = 20 cm, h0 = 14 cm, Drucker-Prager 25.5 deg,
the bed 25.5 deg, the back and side walls 10.2 deg) with ``geometry.dimension = 3`` in half
a 10 cm channel at mesh.size, run to rest. On one process the run is profiled (cProfile,
the 20 functions of largest own processor time); with ``--ranks N`` it is ``mpiexec -n N granflow
run`` and the processor time is that of all ranks (the waited-for children). Writes the
summary's figures, processor seconds, peak memory and the profile.

``plane-strain``: the same rectangle in 2D and in 3D between two frictionless planes one
mesh.size apart (``boundary.channel_width = none``), both to t_end with outputs at t_end/2
and t_end: the runouts and the distances between the centre-line surfaces (the mean and
the largest of the symmetric point-to-polyline distances, ``io/profiles.py``).
"""

from __future__ import annotations

import argparse
import cProfile
import json
import pstats
import resource
import subprocess
import sys
import time
from pathlib import Path
from typing import Any

from granflow.app.api import Run, run
from granflow.geometry.polylines import point_to_polyline
from granflow.io.profiles import curves, surface_distances

CHANNEL = ["geometry.dimension=3", "boundary.channel_width=0.1"]


def _cpu(who: int) -> tuple[float, float]:
    """Processor seconds (user + system) and peak memory (MB) of ``who``."""
    r = resource.getrusage(who)
    return r.ru_utime + r.ru_stime, r.ru_maxrss / 1024.0


def rest(size: float, ranks: int, out: Path, two_d: bool = False) -> dict[str, Any]:
    sets = [*(CHANNEL[1:] if two_d else CHANNEL), f"mesh.size={size!r}"]
    folder = out / (f"run2d_h{size:g}" if two_d else f"run_h{size:g}_n{ranks}")
    if ranks == 1:
        profiler = cProfile.Profile(time.process_time)   # processor, not wall, seconds
        cpu0, _ = _cpu(resource.RUSAGE_SELF)
        profiler.enable()
        result = run("rectangle-rigid", sets, out=folder, force=True, progress=False)
        profiler.disable()
        cpu1, peak = _cpu(resource.RUSAGE_SELF)
        stats = pstats.Stats(profiler).sort_stats("tottime")
        top = [{"function": f"{Path(f).name}:{line}({name})", "calls": nc, "own_s": tt,
                "cumulative_s": ct}
               for (f, line, name), (_, nc, tt, ct, _) in list(stats.stats.items())]
        top = sorted(top, key=lambda row: -row["own_s"])[:20]
    else:
        granflow = Path(sys.executable).parent / "granflow"
        cpu0, _ = _cpu(resource.RUSAGE_CHILDREN)
        args = [str(Path(sys.executable).parent / "mpiexec"), "-n", str(ranks),
                str(granflow), "run", "rectangle-rigid", "--out", str(folder), "--force",
                "--quiet", *(a for s in sets for a in ("--set", s))]
        subprocess.run(args, check=True)
        cpu1, peak = _cpu(resource.RUSAGE_CHILDREN)
        result, top = Run(folder), []
    s = result.summary
    figures = {key: getattr(s, key, None) for key in (
        "status", "message", "steps", "rejected_steps", "nonlinear_iterations", "n_dofs",
        "runout_m", "stop_time_s", "volume_relative_error")}
    raw = json.loads((folder / "summary.json").read_text())
    figures |= {"dimension": 2 if two_d else 3}
    figures |= {key: raw.get(key) for key in ("runout_wall_m", "runout_centre_m",
                                              "wall_height_m", "remeshes",
                                              "min_tetrahedron_quality")}
    return {"size": size, "ranks": ranks, "cpu_s": cpu1 - cpu0, "peak_mb": peak,
            **figures, "profile": top}


def behind_front(plane: Run, slab: Run, t: float, size: float) -> float:
    """The largest distance (m) from a point of either centre-line surface lying more than
    one mesh.size behind the nearer front to the other surface (the front's foot left out:
    docs/three_d.md)."""
    a, b = (curves(r.root, "free_surface", [t])[t] for r in (plane, slab))
    end = min(a[:, 0].max(), b[:, 0].max()) - size
    return float(max(point_to_polyline(a[a[:, 0] <= end], b).max(),
                     point_to_polyline(b[b[:, 0] <= end], a).max()))


def plane_strain(size: float, t_end: float, out: Path, reuse: bool) -> dict[str, Any]:
    times = [t_end / 2, t_end]
    sets = [f"mesh.size={size!r}", f"time.t_end={t_end!r}", f"time.output_times={times}",
            "time.stop_at_rest=false"]
    folders = (out / f"plane_h{size:g}", out / f"slab_h{size:g}")
    if reuse and all((f / "summary.json").exists() for f in folders):
        plane, slab = (Run(f) for f in folders)
    else:
        plane = run("rectangle-rigid", sets, out=folders[0], force=True, progress=False)
        slab = run("rectangle-rigid", [*sets, "geometry.dimension=3",
                                       "boundary.channel_width=none"],
                   out=folders[1], force=True, progress=False)
    gaps = surface_distances(plane.root, slab.root, times=times)
    return {"size": size, "t_end": t_end, "runout_2d_m": plane.summary.runout_m,
            "runout_3d_m": slab.summary.runout_m,
            "runout_relative": slab.summary.runout_m / plane.summary.runout_m - 1.0,
            "surface_distance_mean_m": {f"{t:g}": gaps[t][0] for t in gaps},
            "surface_distance_max_m": {f"{t:g}": gaps[t][1] for t in gaps},
            "surface_distance_behind_front_max_m": {
                f"{t:g}": behind_front(plane, slab, t, size) for t in times}}


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("case", choices=("rest", "plane-strain"))
    parser.add_argument("--size", type=float, default=None)
    parser.add_argument("--ranks", type=int, default=1)
    parser.add_argument("--t-end", type=float, default=0.2)
    parser.add_argument("--two-d", action="store_true",
                        help="rest: the 2D run with the depth-averaged side walls instead")
    parser.add_argument("--reuse", action="store_true",
                        help="plane-strain: measure the runs already in --out/runs")
    parser.add_argument("--out", type=Path,
                        default=Path("benchmarks/results/three_d_collapse"))
    args = parser.parse_args(argv)
    args.out.mkdir(parents=True, exist_ok=True)
    runs = args.out / "runs"
    if args.case == "rest":
        size = args.size or 0.04
        data = rest(size, args.ranks, runs, args.two_d)
        name = (f"rest2d_h{size:g}.json" if args.two_d
                else f"rest_h{size:g}_n{args.ranks}.json")
        print(f"{data['status']}: stop {data['stop_time_s']} s, runout {data['runout_m']:.4f}"
              f" m, {data['steps']} steps, {data['cpu_s']:.0f} s CPU, "
              f"{data['peak_mb']:.0f} MB")
    else:
        size = args.size or 0.03
        data = plane_strain(size, args.t_end, runs, args.reuse)
        name = f"plane_strain_h{size:g}.json"
        print(f"runout 2D {data['runout_2d_m']:.4f} m, 3D {data['runout_3d_m']:.4f} m "
              f"({100 * data['runout_relative']:+.2f} %), surfaces at most "
              f"{data['surface_distance_max_m']} m apart")
    (args.out / name).write_text(json.dumps(data, indent=1) + "\n", encoding="utf-8")
    return 0


if __name__ == "__main__":
    sys.exit(main())
