"""Benchmark: the 3D rectangle collapse in a channel, run by ``granflow run`` as a user runs
it: its processor time to rest and its profile, on one process or under ``mpiexec``, and the
column between frictionless walls against the 2D plane-strain run.

Run: python benchmarks/three_d_collapse.py rest [--size 0.04] [--ranks 1]
         [--linear-solver fieldsplit] [--stop-at 0.1]
     python benchmarks/three_d_collapse.py plane-strain [--size 0.03] [--t-end 0.2]
         [--scenario rectangle-rigid|trapezoid-rigid] [--rheology drucker-prager|mu-i]
     python benchmarks/three_d_collapse.py channel [--size 0.04] [--slope 0] [--reuse]
         [--out benchmarks/results/three_d_collapse]

``rest``: the rectangle-rigid scenario (l0 = 20 cm, h0 = 14 cm, Drucker-Prager 25.5 deg,
the bed 25.5 deg, the back and side walls 10.2 deg) with ``geometry.dimension = 3`` in half
a 10 cm channel at mesh.size, run to rest. On one process the run is profiled (cProfile,
the 20 functions of largest own processor time); with ``--ranks N`` it is ``mpiexec -n N granflow
run`` and the processor time is that of all ranks (the waited-for children). Writes the
summary's figures, processor seconds, peak memory and the profile. ``--linear-solver``
sets ``numerics.linear_solver`` and ``--stop-at`` ``time.t_end`` (a run stopped short of
rest); both join the record's name.

``plane-strain``: the same rectangle in 2D and in 3D between two frictionless planes one
mesh.size apart (``boundary.channel_width = none``), both to t_end with outputs at t_end/2
and t_end: the runouts and the distances between the centre-line surfaces (the mean and
the largest of the symmetric point-to-polyline distances, ``io/profiles.py``). With
``--scenario trapezoid-rigid`` or ``--rheology mu-i`` the other column or law, at two
mesh sizes a convergence check of the gap to plane strain.

``channel``: the 3D run to rest in half the 10 cm channel (the side walls' Coulomb friction
10.2 deg, the glass beads' on glass) against the 2D run with the side walls' depth-averaged
friction (``boundary.channel_width = 0.1``), both at mesh.size: runouts (the 3D centre line
and wall), stop times, when the front settles, and at each output time both wrote and at
the end the 2D free surface against the 3D centre-line and wall surfaces (distances, all
and behind the front's last mesh.size; the mean height difference 3D - 2D; the share of
the common stretch where the 2D surface lies between the two 3D ones). With ``--slope``
the bed is inclined, with the erosion study's settings of its rigid reference
(``benchmarks/erosion_slopes.py``: the friction loaded by the reaction, to 3 s). Both runs
write VTU every few steps, for ``benchmarks/three_d_creep.py``. A 3D run stopped before
rest (interrupted) is compared by its fronts with the 2D front at the same time.
"""

from __future__ import annotations

import argparse
import cProfile
import json
import os
import pstats
import resource
import subprocess
import sys
import time
from pathlib import Path
from typing import Any

import numpy as np

from granflow.app.api import Run, run
from granflow.geometry.polylines import point_to_polyline, surface_distance
from granflow.io.profiles import curves, final_profile, profile_at, surface_distances

CHANNEL = ["geometry.dimension=3", "boundary.channel_width=0.1"]


def _cpu(who: int) -> tuple[float, float]:
    """Processor seconds (user + system) and peak memory (MB) of ``who``."""
    r = resource.getrusage(who)
    return r.ru_utime + r.ru_stime, r.ru_maxrss / 1024.0


def rest_name(size: float, ranks: int, solver: str | None, stop: float | None) -> str:
    """``h0.04_n1``, with ``_<solver>`` and ``_t<stop>`` when they are set."""
    return (f"h{size:g}_n{ranks}" + (f"_{solver}" if solver else "")
            + (f"_t{stop:g}" if stop else ""))


def rest(size: float, ranks: int, out: Path, two_d: bool = False, solver: str | None = None,
         stop: float | None = None) -> dict[str, Any]:
    sets = [*(CHANNEL[1:] if two_d else CHANNEL), f"mesh.size={size!r}",
            *([f"numerics.linear_solver={solver}"] if solver else []),
            *([f"time.t_end={stop!r}"] if stop else [])]
    folder = out / (f"run2d_h{size:g}" if two_d else f"run_{rest_name(size, ranks, solver, stop)}")
    load, wall = os.getloadavg(), time.perf_counter()
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
    wall = time.perf_counter() - wall
    load = [round(a, 2) for a in (*load, *os.getloadavg())]   # 1, 5, 15 min: before, after
    s = result.summary
    figures = {key: getattr(s, key, None) for key in (
        "status", "message", "steps", "rejected_steps", "nonlinear_iterations", "n_dofs",
        "runout_m", "stop_time_s", "volume_relative_error")}
    raw = json.loads((folder / "summary.json").read_text())
    figures |= {"dimension": 2 if two_d else 3}
    figures |= {key: raw.get(key) for key in ("runout_wall_m", "runout_centre_m",
                                              "wall_height_m", "remeshes",
                                              "min_tetrahedron_quality")}
    if solver:
        figures |= {"linear_solver": raw.get("linear_solver"), "t_end": stop,
                    **{key: raw.get(key) for key in ("krylov_iterations", "krylov_solves",
                                                     "krylov_largest")}}
    return {"size": size, "ranks": ranks, "cpu_s": cpu1 - cpu0, "wall_s": wall,
            "load_average": load, "peak_mb": peak, **figures, "profile": top}


def behind_front(plane: Run, slab: Run, t: float, size: float) -> float:
    """The largest distance (m) from a point of either centre-line surface lying more than
    one mesh.size behind the nearer front to the other surface (the front's foot left out:
    docs/three_d.md)."""
    a, b = (curves(r.root, "free_surface", [t])[t] for r in (plane, slab))
    end = min(a[:, 0].max(), b[:, 0].max()) - size
    return float(max(point_to_polyline(a[a[:, 0] <= end], b).max(),
                     point_to_polyline(b[b[:, 0] <= end], a).max()))


def plane_strain_name(size: float, scenario: str, rheology: str) -> str:
    """``h0.02``, with ``_trapezoid`` and ``_mu-i`` for the other column and law."""
    return (f"h{size:g}" + ("_trapezoid" if scenario == "trapezoid-rigid" else "")
            + ("" if rheology == "drucker-prager" else f"_{rheology}"))


def plane_strain(size: float, t_end: float, out: Path, reuse: bool,
                 scenario: str = "rectangle-rigid", rheology: str = "drucker-prager"
                 ) -> dict[str, Any]:
    times = [t_end / 2, t_end]
    sets = [f"mesh.size={size!r}", f"time.t_end={t_end!r}", f"time.output_times={times}",
            "time.stop_at_rest=false", f"material.rheology={rheology}"]
    name = plane_strain_name(size, scenario, rheology)
    folders = (out / f"plane_{name}", out / f"slab_{name}")
    cpu = None
    if reuse and all((f / "summary.json").exists() for f in folders):
        plane, slab = (Run(f) for f in folders)
    else:
        cpu0, _ = _cpu(resource.RUSAGE_SELF)
        plane = run(scenario, sets, out=folders[0], force=True, progress=False)
        cpu1, _ = _cpu(resource.RUSAGE_SELF)
        slab = run(scenario, [*sets, "geometry.dimension=3", "boundary.channel_width=none"],
                   out=folders[1], force=True, progress=False)
        cpu = {"2d": cpu1 - cpu0, "3d": _cpu(resource.RUSAGE_SELF)[0] - cpu1}
    gaps = surface_distances(plane.root, slab.root, times=times)
    return {"size": size, "t_end": t_end, "scenario": scenario, "rheology": rheology,
            "cpu_s": cpu, "runout_2d_m": plane.summary.runout_m,
            "runout_3d_m": slab.summary.runout_m,
            "runout_relative": slab.summary.runout_m / plane.summary.runout_m - 1.0,
            "surface_distance_mean_m": {f"{t:g}": gaps[t][0] for t in gaps},
            "surface_distance_max_m": {f"{t:g}": gaps[t][1] for t in gaps},
            "surface_distance_behind_front_max_m": {
                f"{t:g}": behind_front(plane, slab, t, size) for t in times}}


EROSION_STUDY = ["boundary.normal_load=reaction", "time.t_end=3.0"]   # its rigid rows
SNAPSHOTS = ["output.vtk_every=5"]     # for benchmarks/three_d_creep.py


def channel(size: float, slope: float, out: Path, reuse: bool) -> dict[str, Any]:
    """The 3D channel against the 2D depth-averaged side walls (module docstring)."""
    name = f"h{size:g}" + (f"_slope{slope:g}" if slope else "")
    sets = [*CHANNEL[1:], f"mesh.size={size!r}", *SNAPSHOTS]
    if slope:
        sets += [*EROSION_STUDY, f"geometry.slope_deg={slope!r}"]
    cases = {"3d": (out / f"channel3d_{name}", [*sets, CHANNEL[0]]),
             # the study's 2D rows ran on the uniform mesh (a 3D column always does)
             "2d": (out / f"channel2d_{name}", sets + (["mesh.adaptive=false"] if slope
                                                     else []))}
    runs, cpu = {}, {}
    for key, (folder, overrides) in cases.items():
        if reuse and (folder / "summary.json").exists():
            runs[key], cpu[key] = Run(folder), None
            continue
        cpu0, _ = _cpu(resource.RUSAGE_SELF)
        runs[key] = run("rectangle-rigid", overrides, out=folder, force=True, progress=False)
        cpu[key] = _cpu(resource.RUSAGE_SELF)[0] - cpu0
    three, two = runs["3d"], runs["2d"]
    raw = {k: json.loads((r.root / "summary.json").read_text()) for k, r in runs.items()}
    figures = {k: {key: raw[k].get(key) for key in (
        "status", "stop_time_s", "front_settle_time_s", "runout_m", "runout_centre_m",
        "runout_wall_m", "steps", "nonlinear_iterations", "remeshes", "t_final")}
        | {"cpu_s": cpu[k]} for k in runs}
    times = [t for t in three.output_times if t > 0 and all(
        profile_at(r.root, "free_surface", t) for r in (three, two))]
    surfaces = {f"{t:.3f}": compare_surfaces(three.root, two.root, t, size) for t in times}
    surfaces["final"] = compare_surfaces(three.root, two.root, None, size)
    x2 = raw["2d"]["runout_m"]
    diag = two.diagnostics       # the 2D front when the 3D run ended (it may not be at rest)
    end = float(np.interp(raw["3d"]["t_final"], diag["t"], diag["front_x"]))
    return {"size": size, "slope_deg": slope, "runs": figures,
            "front_2d_at_3d_end_m": end,
            "front_centre_relative_at_3d_end": raw["3d"]["runout_centre_m"] / end - 1.0,
            "front_wall_relative_at_3d_end": raw["3d"]["runout_wall_m"] / end - 1.0,
            "runout_centre_relative": raw["3d"]["runout_centre_m"] / x2 - 1.0,
            "runout_wall_relative": raw["3d"]["runout_wall_m"] / x2 - 1.0,
            "surfaces": surfaces}


def compare_surfaces(three: Path, two: Path, t: float | None, size: float) -> dict[str, Any]:
    """The 2D surface against the 3D centre-line and wall surfaces at output time ``t``
    (None: the final state's): for each, the mean and largest symmetric distances, the
    largest behind the nearer front's last ``size``, and the mean height difference 3D - 2D
    over the common stretch; and the share of that stretch (sampled every mm) where the 2D
    surface lies between the 3D ones (0.5 mm slack)."""
    def read(root: Path, kind: str) -> np.ndarray:
        data = final_profile(root, kind) if t is None else profile_at(root, kind, t)
        assert data, f"{root} has no {kind} profile at {t}"
        xz = np.column_stack([data["x"], data["z"]])
        return xz[np.isfinite(xz).all(axis=1)]

    plane = read(two, "free_surface")
    sides = {"centre": read(three, "free_surface"), "wall": read(three, "free_surface_wall")}
    end = min(plane[:, 0].max(), *(c[:, 0].max() for c in sides.values()))
    grid = np.arange(0.0, end, 1e-3)
    height = {k: _height(c, grid) for k, c in {"2d": plane, **sides}.items()}
    out: dict[str, Any] = {}
    for key, curve in sides.items():
        mean, largest = surface_distance(curve, plane)
        cut = min(curve[:, 0].max(), plane[:, 0].max()) - size
        behind = max(point_to_polyline(curve[curve[:, 0] <= cut], plane).max(),
                     point_to_polyline(plane[plane[:, 0] <= cut], curve).max())
        out[key] = {"distance_mean_m": mean, "distance_max_m": largest,
                    "distance_behind_front_max_m": float(behind),
                    "height_difference_mean_m": float(np.mean(height[key] - height["2d"])),
                    "front_x_m": float(curve[:, 0].max())}
    low = np.minimum(height["centre"], height["wall"]) - 5e-4
    high = np.maximum(height["centre"], height["wall"]) + 5e-4
    out["front_x_2d_m"] = float(plane[:, 0].max())
    out["between_share"] = float(np.mean((height["2d"] >= low) & (height["2d"] <= high)))
    return out


def _height(curve: np.ndarray, x: np.ndarray) -> np.ndarray:
    """The surface's highest z above each x (a surface that folds over counts its top)."""
    z = np.full(len(x), -np.inf)
    for (x0, z0), (x1, z1) in zip(curve[:-1], curve[1:], strict=True):
        lo, hi = min(x0, x1), max(x0, x1)
        inside = (x >= lo) & (x <= hi)
        if not inside.any():
            continue
        s = (x[inside] - x0) / (x1 - x0) if x1 != x0 else np.ones(inside.sum())
        z[inside] = np.maximum(z[inside], z0 + s * (z1 - z0) if x1 != x0 else max(z0, z1))
    return z


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("case", choices=("rest", "plane-strain", "channel"))
    parser.add_argument("--size", type=float, default=None)
    parser.add_argument("--ranks", type=int, default=1)
    parser.add_argument("--t-end", type=float, default=0.2)
    parser.add_argument("--slope", type=float, default=0.0,
                        help="channel: the bed's slope (deg), with the erosion study's settings")
    parser.add_argument("--two-d", action="store_true",
                        help="rest: the 2D run with the depth-averaged side walls instead")
    parser.add_argument("--reuse", action="store_true",
                        help="plane-strain, channel: measure the runs already in --out/runs")
    parser.add_argument("--scenario", default="rectangle-rigid",
                        choices=("rectangle-rigid", "trapezoid-rigid"),
                        help="plane-strain: the column")
    parser.add_argument("--rheology", default="drucker-prager",
                        choices=("drucker-prager", "mu-i"), help="plane-strain: the law")
    parser.add_argument("--linear-solver", default=None,
                        choices=("auto", "umfpack", "pardiso", "fieldsplit"),
                        help="rest: numerics.linear_solver (unset: the default)")
    parser.add_argument("--stop-at", type=float, default=None,
                        help="rest: time.t_end (unset: the scenario's, the run to rest)")
    parser.add_argument("--out", type=Path,
                        default=Path("benchmarks/results/three_d_collapse"))
    args = parser.parse_args(argv)
    args.out.mkdir(parents=True, exist_ok=True)
    runs = args.out / "runs"
    if args.case == "rest":
        size = args.size or 0.04
        data = rest(size, args.ranks, runs, args.two_d, args.linear_solver, args.stop_at)
        name = (f"rest2d_h{size:g}.json" if args.two_d else
                f"rest_{rest_name(size, args.ranks, args.linear_solver, args.stop_at)}.json")
        print(f"{data['status']}: stop {data['stop_time_s']} s, runout {data['runout_m']:.4f}"
              f" m, {data['steps']} steps, {data['cpu_s']:.0f} s CPU, "
              f"{data['peak_mb']:.0f} MB")
    elif args.case == "channel":
        size = args.size or 0.04
        data = channel(size, args.slope, runs, args.reuse)
        name = f"channel_h{size:g}" + (f"_slope{args.slope:g}" if args.slope else "") + ".json"
        r3, r2 = data["runs"]["3d"], data["runs"]["2d"]
        print(f"3D: stop {r3['stop_time_s']} s, runout {r3['runout_centre_m']:.4f} m (centre),"
              f" {r3['runout_wall_m']:.4f} m (wall); 2D: stop {r2['stop_time_s']} s, runout "
              f"{r2['runout_m']:.4f} m")
        for t, gap in data["surfaces"].items():
            print(f"  {t}: 2D to centre at most {1e3 * gap['centre']['distance_max_m']:.1f} "
                  f"mm, to wall {1e3 * gap['wall']['distance_max_m']:.1f} mm, between "
                  f"{100 * gap['between_share']:.0f} %")
    else:
        size = args.size or 0.03
        data = plane_strain(size, args.t_end, runs, args.reuse, args.scenario, args.rheology)
        name = f"plane_strain_{plane_strain_name(size, args.scenario, args.rheology)}.json"
        print(f"runout 2D {data['runout_2d_m']:.4f} m, 3D {data['runout_3d_m']:.4f} m "
              f"({100 * data['runout_relative']:+.2f} %), surfaces at most "
              f"{data['surface_distance_max_m']} m apart")
    (args.out / name).write_text(json.dumps(data, indent=1) + "\n", encoding="utf-8")
    return 0


if __name__ == "__main__":
    sys.exit(main())
