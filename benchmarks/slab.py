"""Benchmark: the slab test. A slab of the column's material, 1 cm thick, launched at 1 m/s
down a periodic incline (a) on the rigid bed, (b) on a layer of the same material at rest
on that bed; the distance the slab travels until it stops (or, where it does not, where it
is at t_end and its speed then), and the ratio (b)/(a), for each law and each switch of one
model ingredient (docs/erosion.md, "The slab: the mechanism isolated").

Run: python benchmarks/slab.py [--variants drucker-prager glass-beads/no-slip ...]
         [--slopes 0 10 16 19 22] [--thickness 0.005] [--speed 1.0]
         [--out benchmarks/results/slab] [--collect]
     python benchmarks/slab.py --fluidity

--fluidity: the nonlocal fluidity's condition on the Coulomb bed, g = 0 against zero flux,
for a slab alone on the bed at 22 deg, 2 mm (thinner than the model's h_stop, 2.68 mm) and
5 mm thick, 0.31 mm cells, to 10 s without the stop at rest: its distance, its speed at the
end, the fluidity then, the nonlinear iterations (OUT/slab_fluidity.json).

A variant is a law, or a law and switches joined by "/" ("nonlocal/no-slip+small-eta"):
its overrides are the law's then each switch's (the layer's packing, switch d:
"critical-layer", "loose-layer", "dense-layer", the slab at phi_c; their prediction is
OUT/packing-prediction.md). Runs go to OUT/runs/VARIANT/HEmm-SLOPE
(HE = 0: on the bed; ignored by git); OUT/slab.json keeps every run's figures, and a run
already there with the same overrides is not run again (rerunning continues the table);
OUT/slab-HEmm.md is the table: per variant and slope, (a), (b) and their ratio; OUT/slab-HEmm.png
the ratio against slope. Each run records its processor time.
"""

from __future__ import annotations

import argparse
import resource
import shutil
from pathlib import Path

import matplotlib
import numpy as np

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
from common.erosion_variants import GLASS_BEADS  # noqa: E402
from common.results import read_results, report, write_json, write_markdown  # noqa: E402

import granflow  # noqa: E402
from granflow.config import load_config  # noqa: E402
from granflow.io.diagnostics import read_diagnostics  # noqa: E402
from granflow.io.plots import save_figure  # noqa: E402
from granflow.io.run_dir import RunDir  # noqa: E402

LAWS = {
    # the paper's constants: friction 25.5 deg inside and on the bed, eta = 1 Pa s
    "drucker-prager": [],
    # Jop, Forterre & Pouliquen's glass beads (as benchmarks/erosion_slopes.py)
    "glass-beads": GLASS_BEADS,
    # the same beads starting at their avalanche angle: the slab launched flowing (s = 1),
    # the layer at rest (s = 0, ``layer.initial_mobilisation``)
    "hysteretic": [*GLASS_BEADS, "material.friction=hysteretic",
                   "material.start_friction_angle_deg=25.5",
                   "material.initial_mobilisation=1.0", "layer.initial_mobilisation=0.0"],
    # Henann & Kamrin's glass beads: mu_s = tan 20.9, b = 0.9377, A = 0.48, d = 0.53 mm
    "nonlocal": ["material.rheology=nonlocal", "material.friction_angle_deg=20.9",
                 "material.grain_diameter=0.00053"],
}
PACKED_SLAB = ["material.packing=critical-state", "material.density=1500.0",
               "layer.packing=critical-state"]
SWITCHES = {
    "no-slip": ["boundary.bed=no-slip"],          # (a) the bed: rough, does not slide
    "material-bed": ["boundary.bed=material"],   # (a) the bed: the material's own law
    "small-eta": ["material.viscosity=0.01"],    # (b) eta / 100
    # (c) the band resolved: cells of 0.31 mm, 0.6 grain, across slab and a 5 mm layer
    # (mesh.layer_cells at most 16; the base: 2.5 mm)
    "fine-band": ["mesh.size=0.0003125", "mesh.layer_cells=16"],
    "side-walls": ["boundary.channel_width=0.1"],   # (e) the experiments' 10 cm channel
    "zero-fluidity": ["boundary.bed_fluidity=zero"],   # nonlocal: g = 0 on the Coulomb bed
    # (d) the layer's packing (critical-state defaults: phi_c 0.60, a 0, K 4): the slab at
    # phi_c (1500 kg/m^3 over grains of 2500), the layer at phi_c, loose (0.58) or dense (0.62)
    "critical-layer": [*PACKED_SLAB, "layer.density=1500.0"],
    "loose-layer": [*PACKED_SLAB, "layer.density=1450.0"],
    "dense-layer": [*PACKED_SLAB, "layer.density=1550.0"],
}
TABLE = [f"{law}{suffix}" for law in LAWS for suffix in (
    "", "/no-slip", "/material-bed", "/small-eta", "/fine-band", "/side-walls",
    "/no-slip+small-eta")] + ["nonlocal/zero-fluidity"] + [
    # run after the table, where its answer pointed (not in the prediction)
    f"{law}/material-bed+small-eta" for law in LAWS if law != "drucker-prager"] + [
    # (d) run after the table, its prediction in packing-prediction.md
    f"{law}/{bed}+small-eta+{packing}-layer" for bed in ("no-slip", "material-bed")
    for law in LAWS for packing in ("critical", "loose", "dense")]
COMMON = ["output.progress=false", "time.output_times=[]"]
KEYS = ["status", "t_final", "steps", "nonlinear_iterations", "rejected_steps",
        "slab_distance_m", "slab_speed_m_s", "stop_time_s", "layer_distance_m",
        "layer_moved_depth_m", "bed_slip_m_s", "surface_speed_m_s", "n_triangles",
        "wall_time_s", "packing_min", "packing_max", "mass_relative_error_max"]


def overrides(variant: str, he: float, slope: float, speed: float) -> list[str]:
    """The law's and the switches' overrides, the slope, the speed and the layer; a run on
    the bed drops the layer's keys (it has no layer)."""
    law, _, switches = variant.partition("/")
    own = list(LAWS[law])
    for switch in filter(None, switches.split("+")):
        own += SWITCHES[switch]
    if he == 0:
        own = [o for o in own if not o.startswith(("layer.", "mesh.layer_cells"))]
    return [*COMMON, *own, f"geometry.slope_deg={slope!r}", f"initial.slab_speed={speed!r}",
            f"geometry.erodible_thickness={he!r}"]


def key(variant: str, he: float, slope: float) -> str:
    return f"{variant}|{1e3 * he:g}mm|{slope:g}"


def run(variant: str, he: float, slope: float, speed: float, out: Path,
        done: dict | None, results: dict) -> dict:
    """One run, or its row from the record when it (or another variant's run: the layer's
    packing switches share their run on the bed) ran with the same overrides."""
    found = overrides(variant, he, slope, speed)
    if not done or done.get("overrides") != found:
        done = next((dict(row, variant=variant) for row in results.values()
                     if row.get("overrides") == found), done)
    folder = out / "runs" / variant.replace("/", "_") / f"{1e3 * he:g}mm-{slope:g}"
    if done and done.get("overrides") == found and done.get("status") in ("completed",
                                                                         "stopped"):
        if "surface_distance_m" not in done and (folder / "diagnostics.csv").is_file():
            done["surface_distance_m"] = surface_distance(folder)   # a row of before
        return done
    shutil.rmtree(folder, ignore_errors=True)
    before = resource.getrusage(resource.RUSAGE_SELF).ru_utime
    granflow.run(load_config("slab", found), out=folder, force=True)
    cpu = resource.getrusage(resource.RUSAGE_SELF).ru_utime - before
    summary = RunDir.summary(folder)
    return ({k: summary.get(k) for k in KEYS}
            | {"surface_distance_m": surface_distance(folder), "variant": variant, "he": he,
               "slope": slope, "speed": speed, "cpu_s": round(cpu, 2), "overrides": found})


def surface_distance(folder: Path) -> float:
    """How far the free surface's material travelled: its mean speed along the bed
    (``surface_speed``, every step) integrated in time from U0 at t = 0 (the front of a
    collapse is surface material overriding)."""
    table = read_diagnostics(folder)
    t = np.concatenate([[0.0], table["t"].to_numpy()])
    speed = table["surface_speed"].to_numpy()
    return float(np.trapezoid(np.concatenate([[speed[0]], speed]), t))


def ratio(bed: dict, layer: dict, measure: str = "slab_distance_m"
          ) -> tuple[float | None, str]:
    """(b)/(a) of the slab's distances, and what it is: "" both at rest; "≥" the slab on the
    layer still moving at t_end (it only goes further); "≤" the slab on the bed still
    moving; "≈" both moving (their distances at t_end: the speeds say more)."""
    if not bed or not layer or not bed.get(measure):
        return None, ""
    value = layer[measure] / bed[measure]
    stopped = (bed.get("stop_time_s") is not None, layer.get("stop_time_s") is not None)
    return value, {(True, True): "", (True, False): "≥", (False, True): "≤",
                   (False, False): "≈"}[stopped]


def cell(row: dict | None) -> str:
    """A run's distance, and its stop time or its speed at t_end."""
    if row is None:
        return "-"
    if row.get("status") not in ("completed", "stopped"):
        return f"{row.get('status')} at {row.get('t_final', 0):.2f} s"
    x = row["slab_distance_m"]
    if row.get("stop_time_s") is not None:
        return f"{x:.3f} m, {row['stop_time_s']:.2f} s"
    return f"≥ {x:.3f} m, {1e3 * row['slab_speed_m_s']:.1f} mm/s at {row['t_final']:.0f} s"


def table(results: dict, variants: list[str], slopes: list[float], he: float) -> str:
    """Per variant: the ratio (b)/(a) of the slab's distances at each slope (the speeds'
    ratio at t_end where both still move), that of the surface's distances, then (a) and
    (b) themselves."""
    head = "| variant | " + " | ".join(f"{s:g}°" for s in slopes) + " |"
    lines = [head, "|" + "---|" * (1 + len(slopes))]
    for variant in variants:
        ratios, surfaces, runs = [], [], []
        for slope in slopes:
            a, b = results.get(key(variant, 0.0, slope)), results.get(key(variant, he, slope))
            value, mark = ratio(a or {}, b or {})
            shown = "-" if value is None else f"{mark} {value:.2f}".strip()
            if mark == "≈" and a and b and a.get("slab_speed_m_s"):
                shown += f" (speeds {b['slab_speed_m_s'] / a['slab_speed_m_s']:.2f})"
            ratios.append(shown)
            value, mark = ratio(a or {}, b or {}, "surface_distance_m")
            surfaces.append("-" if value is None else f"{mark} {value:.2f}".strip())
            runs.append(f"{cell(a)}<br>{cell(b)}")
        lines.append(f"| **{variant}** | " + " | ".join(ratios) + " |")
        lines.append("| its surface | " + " | ".join(surfaces) + " |")
        lines.append("| (a) / (b) | " + " | ".join(runs) + " |")
    return "\n".join(lines) + "\n"


def figure(results: dict, variants: list[str], slopes: list[float], he: float,
           path: Path) -> None:
    """The ratio against slope, one panel per law."""
    laws = list(dict.fromkeys(v.partition("/")[0] for v in variants))
    fig, axes = plt.subplots(1, len(laws), figsize=(4 * len(laws), 3.6), sharey=True,
                             squeeze=False)
    for ax, law in zip(axes[0], laws, strict=True):
        ax.axhline(1.0, color="0.6", lw=0.8)
        for variant in (v for v in variants if v.partition("/")[0] == law):
            points = [(s, *ratio(results.get(key(variant, 0.0, s)) or {},
                                 results.get(key(variant, he, s)) or {})) for s in slopes]
            points = [(s, r, m) for s, r, m in points if r is not None]
            if not points:
                continue
            line, = ax.plot([p[0] for p in points], [p[1] for p in points], "-",
                            label=variant.partition("/")[2] or "base")
            for s, r, m in points:
                ax.plot(s, r, "o", color=line.get_color(),
                        fillstyle="full" if not m else "none")
        ax.set_title(law)
        ax.set_xlabel("slope (deg)")
    axes[0][0].set_ylabel(f"slab distance: on {1e3 * he:g} mm / on the bed")
    axes[0][-1].legend(fontsize=7)
    save_figure(fig, path)


def fluidity(out: Path, speed: float) -> dict:
    """The fluidity's condition on the Coulomb bed (module docstring)."""
    rows = {}
    for height in (0.002, 0.005):
        for condition in ("zero-flux", "zero"):
            found = [*COMMON, *LAWS["nonlocal"], f"boundary.bed_fluidity={condition}",
                     f"geometry.height={height!r}", "mesh.size=0.0003125",
                     "geometry.slope_deg=22.0", f"initial.slab_speed={speed!r}",
                     "time.t_end=10.0", "time.stop_at_rest=false"]
            name = f"{1e3 * height:g}mm-{condition}"
            folder = out / "runs" / "fluidity" / name
            shutil.rmtree(folder, ignore_errors=True)
            granflow.run(load_config("slab", found), out=folder, force=True)
            summary = RunDir.summary(folder)
            table = read_diagnostics(folder)
            rows[name] = {k: summary.get(k) for k in KEYS} | {
                "fluidity_max_end": float(table["fluidity_max"].iloc[-1]),
                "overrides": found}
            report(name, {k: rows[name][k] for k in (
                "slab_distance_m", "slab_speed_m_s", "fluidity_max_end",
                "nonlinear_iterations")})
    write_json(out / "slab_fluidity.json", rows)
    return rows


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--variants", nargs="+", default=TABLE)
    parser.add_argument("--slopes", nargs="+", type=float, default=[0, 10, 16, 19, 22])
    parser.add_argument("--thickness", type=float, default=0.005)
    parser.add_argument("--speed", type=float, default=1.0)
    parser.add_argument("--out", type=Path, default=Path("benchmarks/results/slab"))
    parser.add_argument("--collect", action="store_true", help="only rewrite the tables")
    parser.add_argument("--fluidity", action="store_true",
                        help="the fluidity's condition on the Coulomb bed (only that)")
    args = parser.parse_args()
    if args.fluidity:
        fluidity(args.out, args.speed)
        return
    path = args.out / "slab.json"
    results = read_results(path)
    if not args.collect:
        for variant in args.variants:
            for slope in args.slopes:
                for he in (0.0, args.thickness):
                    name = key(variant, he, slope)
                    results[name] = run(variant, he, slope, args.speed, args.out,
                                        results.get(name), results)
                    report(name, {k: results[name].get(k) for k in (
                        "status", "slab_distance_m", "stop_time_s", "slab_speed_m_s",
                        "cpu_s")})
                    write_json(path, results)
    write_markdown(args.out / f"slab-{1e3 * args.thickness:g}mm.md",
                   table(results, args.variants, args.slopes, args.thickness), show=True)
    figure(results, args.variants, args.slopes, args.thickness,
           args.out / f"slab-{1e3 * args.thickness:g}mm.png")


if __name__ == "__main__":
    main()
