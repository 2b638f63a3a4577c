"""Benchmark: erosion on slopes. Runout, flow duration and the erodible/rigid runout ratio
against slope, for several model ingredients, beside what the experiments report.

Run: python benchmarks/erosion_slopes.py [--variants drucker-prager mu-i ...]
         [--shapes rectangle trapezoid] [--slopes 0 10 16 19 22]
         [--thickness 0.0025 0.005 0.01] [--beds rigid erodible] [--cells 2]
         [--out benchmarks/results/erosion_slopes] [--t-end 3] [--collect]

Each variant is a set of overrides applied to both beds; the ratio is taken between its
erodible and rigid runs at the same slope. The rigid bed of each variant and slope runs
first: the layer then reaches 1.3 times its runout (the layer must not end under the flow).
Runs go to OUT/runs/VARIANT/SHAPE-HEmm-SLOPE (HE = 0 is the rigid bed); a finished run is
kept and one with a checkpoint (every 100 steps) continued, so rerunning the command
continues the study; a finished row already in OUT/erosion_slopes.json with the same
overrides (or a longer bed, ``common/carry.same_run``) is kept without its run folder (a
fresh clone has none). A run interrupted (SIGINT, SIGTERM) is recorded as it stands (its
front in time, ``interrupted``) and ends the invocation; its folder is packed into
OUT/carried/NAME.tar.gz, which a fresh clone's invocation unpacks and continues (a run
outliving its machine travels in the repository; the archive goes once the row is
finished). A failed row's folder is packed too: the same command resumes it as it failed.
``--t-end T`` carries the study past its 3 s: a row that reached 3 s still moving is
continued from its checkpoint to T (``granflow resume --set time.t_end=T``; a row at rest
is kept); each row records the end time it ran to (``t_end``) and, once carried, its
earlier figures by end time (``earlier``). A row carried further is kept as it is by an
invocation with an earlier end (the default's): never run again or shortened. OUT/
erosion_slopes.json holds the summaries' figures, OUT/erosion_slopes.md the table, OUT/
erosion_slopes.png the ratio against slope, OUT/erosion_slopes_fronts.md each layer row's
front against its rigid twin's in time, the fronts' speeds at the end and where the
displaced layer material went (``common/erosion.py``). The flow duration is the time the
flowing area falls below 1 % (``common/runs.flow_duration``). Two invocations may run
different rows into the same OUT at once: each row is written into the record as it is on
disk then.

Experimental reference (what could be checked here; the papers' tables were not reachable):
on glass beads (repose angle about 23.5 deg, avalanche angle about 25.5 deg), an erodible
layer of the same beads leaves the runout unchanged below a critical slope and lengthens it
above, by up to about 40 % near the repose angle, growing with the layer's thickness
(Mangeney et al. 2010, J. Geophys. Res. 115, F03040, abstract: critical slope about half the
repose angle; Farin et al. 2014, J. Geophys. Res. Earth Surf. 119, 504-532; the critical
slope is quoted as about 16 deg by Fernandez-Nieto et al. 2016, J. Fluid Mech. 798, which
also report that a constant friction coefficient gives the opposite trend and mu(I) the
observed one). The experiments' column is 20 cm long and 14 cm high (the `rectangle`).
"""

from __future__ import annotations

import argparse
import tomllib
from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
from common.carry import (  # noqa: E402
    BED_LENGTH,
    STUDY_END,
    carried,
    pack,
    same_run,
    settled,
    unpack,
    with_earlier,
)
from common.erosion import (  # noqa: E402
    CLOCK,
    destination_table,
    front_history,
    front_speed_end,
    fronts_table,
    layer_destination,
)
from common.erosion_ratio import (  # noqa: E402
    CELLS,
    at_1mm,
    front,
    key,
    ratio,
    rigid_key,
    runout,
)
from common.erosion_variants import (  # noqa: E402
    LENGTH,
    REACH,
    RIGID_TWIN,
    VARIANTS,
)
from common.results import read_results, report, write_json, write_markdown  # noqa: E402
from common.runs import collected, flow_duration, run_or_continue  # noqa: E402

from granflow.io.plots import save_figure  # noqa: E402

SCENARIO = {"rectangle": "rectangle-rigid", "trapezoid": "trapezoid-rigid"}
HEIGHT = {"rectangle": 0.14, "trapezoid": 0.25}     # above the layer
ERODIBLE = ["numerics.mesh_velocity=elastic", "surface_tension.enabled=true",
            "mesh.layer_ahead=0.1",   # benchmarks/layer_ahead.py
            "numerics.anderson_depth=3",   # as trapezoid-erodible
            "surface_tension.length=mesh_size"]   # the study's rows: the tension of their time
T_END = STUDY_END   # s: the study's end; --t-end carries rows further (``common/carry.py``)
COMMON = ["boundary.normal_load=reaction", f"time.t_end={T_END}", "output.checkpoint_every=100",
          "mesh.adaptive=false"]   # every row ran on the uniform mesh
KEYS = ["status", "t_final", "steps", "wall_time_s", "n_triangles", "remeshes",
        "stop_time_s", "front_stop_time_s", "runout_m", "column_front_m",
        "layer_displaced_area_m2", "layer_mobilised_area_max_m2", "erosion_depth_max_m",
        "layer_area_drift_max", "runout_1mm_m"]


def overrides(variant: str, shape: str, he: float, slope: float,
              rigid_runout: float | None, cells: int = CELLS) -> list[str]:
    """The run's overrides: the variant's, the slope, and for a layer its thickness (the
    column's height above it kept) and its length."""
    own = VARIANTS[variant]
    if he == 0:                         # a rigid bed has no layer material
        own = [o for o in own if not o.startswith("layer.")]
    out = [*COMMON, *own, f"geometry.slope_deg={slope!r}"]
    if he > 0:
        reach = REACH.get(variant, 1.3)
        length = LENGTH.get(variant) or (
            max(1.0, reach * rigid_runout) if rigid_runout else 1.0 + 0.05 * slope)
        out += [*ERODIBLE, f"mesh.layer_cells={cells}", f"geometry.erodible_thickness={he!r}",
                f"geometry.height={HEIGHT[shape] + he!r}", f"{BED_LENGTH}{length!r}"]
    return out


def run(variant: str, shape: str, he: float, slope: float, rigid: float | None,
        out: Path, cells: int = CELLS, done: dict | None = None,
        t_end: float = T_END) -> dict:
    """One run: kept when finished (``done``, its row in the JSON, with the same overrides;
    else its folder) at rest or at ``t_end`` or later, continued from its checkpoint (to
    ``t_end`` if it reached an earlier end still moving), else run afresh."""
    found = overrides(variant, shape, he, slope, rigid, cells)
    same = bool(done) and same_run(done.get("overrides", found), found)
    if same and settled(done, t_end):
        return done
    used = done["overrides"] if same and done else found   # an interrupted run as it began
    summary = carried(run_or_continue(SCENARIO[shape], used, out), out, t_end)
    return with_earlier(row_of(summary, out) | {"overrides": used}, done if same else None)



def row_of(summary: dict, out: Path) -> dict:
    """The summary's figures, the flow's duration (below 1 % flowing), the front on a fixed
    clock and its speed at the end, and where the displaced layer material went
    (``common/erosion.py``)."""
    config = tomllib.loads((out / "config.toml").read_text())
    grain = config.get("layer", {}).get("grain_diameter")    # "none": the column's
    grain = grain if isinstance(grain, float) else config["material"]["grain_diameter"]
    t_end = float(config["time"]["t_end"])
    clock = CLOCK + tuple(float(t) for t in range(int(T_END) + 1, int(t_end) + 1))
    return {k: summary.get(k) for k in KEYS} | {
        "t_end": t_end, "duration_s": flow_duration(out),
        "front_history": front_history(out, clock),
        "front_speed_end_m_s": front_speed_end(out)} | layer_destination(
        out, grain, config["geometry"]["width"], summary.get("column_front_m"))


def table(results: dict[str, dict]) -> str:
    head = ["variant", "shape", "slope (deg)", "layer (mm)", "cells", "runout (m)",
            "ratio to rigid",
            "flow duration (s)", "stop (s)", "displaced layer (m^2)", "erosion depth (mm)",
            "wall time (min)"]
    lines = ["| " + " | ".join(head) + " |", "|" + "---|" * len(head)]
    for r in sorted(results.values(), key=lambda r: (r["variant"], r["shape"], r["slope"],
                                                      r["he"], r.get("cells", CELLS))):
        x = runout(r)
        value, bound = ratio(results, r)
        shown = "-" if value is None else f"{bound} {value:.3f}".strip()

        def num(v: float | None, fmt: str, scale: float = 1.0) -> str:
            return "-" if v is None else format(scale * v, fmt)

        lines.append("| " + " | ".join([
            r["variant"], r["shape"], f"{r['slope']:g}", f"{1e3 * r['he']:g}",
            str(r.get("cells", CELLS)) if r["he"] > 0 else "-",
            num(x, ".3f") if x else f"≥ {front(r):.3f}, moving at {r['t_final']:.2f} s"
            if front(r) else f"{r['status']} at {r['t_final']:.2f} s", shown,
            num(r.get("duration_s"), ".3f"), num(r.get("stop_time_s"), ".3f"),
            num(r.get("layer_displaced_area_m2"), ".2e"),
            num(r.get("erosion_depth_max_m"), ".1f", 1e3),
            num(r.get("wall_time_s"), ".1f", 1 / 60)]) + " |")
    return "\n".join(lines) + "\n"


def ratio_table(results: dict[str, dict]) -> str:
    """One line per variant, column, layer and resolution, one column per slope: the
    erodible runout (m), its ratio to the rigid bed's and the flow duration (s); a run whose
    front had not settled gives its front at the end, marked still moving, and the ratio
    marked as ``ratio`` says. A layer row whose variant has rigid twins with the layer rows'
    surface tension (VARIANT-tension) has a second line with the ratios against those;
    where the twins' records read their front 1 mm above the bed (``runout_1mm_m``, the
    layer rows' measure), a line with those ratios follows each."""
    slopes = sorted({r["slope"] for r in results.values()})
    lines = ["| variant | column | layer (mm) | cells | "
             + " | ".join(f"{s:g}°" for s in slopes) + " |", "|" + "---|" * (4 + len(slopes))]
    groups: dict[tuple, dict[float, str]] = {}
    twins = [(r, r["variant"]) for r in results.values() if r["he"] > 0]
    twins += [(r, f"{r['variant']}-tension") for r, _ in twins
              if rigid_key(f"{r['variant']}-tension", r["shape"], r["slope"]) in results]
    measured = [(r, twin, False) for r, twin in twins] + [
        (r, twin, True) for r, twin in twins
        if at_1mm(results.get(rigid_key(twin, r["shape"], r["slope"]), {}))]
    for r, twin, thick in measured:
        x = runout(r)
        value, bound = ratio(results, r | {"variant": twin}, thick)
        shown = "" if value is None else {
            "": f" ({value:.2f})", "≤": f" (≤ {value:.2f}, rigid moving at t_end)",
            "≥": f" (≥ {value:.2f})", "≈": f" (≈ {value:.2f}, rigid moving too)"}[bound]
        if x is None:
            cell = (f"≥ {front(r):.3f}, moving at {r['t_final']:.1f} s{shown}" if front(r)
                    else f"{r['status']} at {r['t_final']:.2f} s")
        else:
            duration = r.get("duration_s")
            cell = f"{x:.3f}{shown}" + (f", {duration:.2f} s" if duration else "")
        rigid = ("" if twin == r["variant"] else twin) + (", at 1 mm" if thick else "")
        label = r["variant"] + (f" (rigid: {rigid.lstrip(', ')})" if rigid else "")
        group = (label, r["shape"], 1e3 * r["he"], r.get("cells", CELLS))
        groups.setdefault(group, {})[r["slope"]] = cell
    for (variant, shape, he, cells), row in sorted(groups.items()):
        lines.append(f"| {variant} | {shape} | {he:g} | {cells} | "
                     + " | ".join(row.get(s, "-") for s in slopes) + " |")
    return "\n".join(lines) + "\n"


def panel(variant: str, shape: str, he: float) -> int:
    """Which panel of the figure draws a row: 0 the constant-friction ingredients on the
    rectangle over 5 mm, 1 Drucker-Prager's thicknesses and columns, 2 the glass beads'
    mu(I), the hysteretic friction and the nonlocal law (-1: Drucker-Prager's 5 mm
    rectangle is on 0 and 1)."""
    if variant in ("glass-beads", "nonlocal") or variant.startswith("hysteretic"):
        return 2
    if variant == "drucker-prager":
        return -1 if (shape, he) == ("rectangle", 0.005) else 1
    return 0


BOUND_MARKERS = {"≤": ("v", "upper bound: rigid front still moving at its end"),
                 "≥": ("^", "lower bound: erodible front still moving at its end"),
                 "≈": ("o", "both fronts still moving at their end: ratio of the fronts")}


def figure(results: dict[str, dict], path: Path) -> None:
    """Erodible/rigid runout ratio against slope over the experiments' trend (no change
    below the critical slope, up to +40 % near repose): left, each constant-friction
    ingredient on the rectangle over 5 mm; middle, the layer's thickness and the column's
    shape; right, the glass beads' mu(I), the hysteretic friction and the nonlocal law (a
    variant at one slope, the parameters varied, as a lone marker). Open markers are bounds
    (``ratio``):
    down, the rigid front was still moving at t_end; up, the erodible one; a circle, both."""
    fig, axes = plt.subplots(1, 3, figsize=(16, 4.6), sharey=True)
    groups: dict[tuple, list[tuple[float, float, str]]] = {}
    for r in results.values():
        value, bound = ratio(results, r)
        if value is not None:
            group = (r["variant"], r["shape"], r["he"], r.get("cells", CELLS))
            groups.setdefault(group, []).append((r["slope"], value, bound))
    for (variant, shape, he, cells), points in sorted(groups.items()):
        where = panel(variant, shape, he)
        style = ("o-" if cells == 1 else "s--") if len(points) > 1 else "D"
        points.sort()
        label = f"{variant}, {shape}, {1e3 * he:g} mm, {cells} cell{'s' * (cells > 1)}"
        slopes, ratios, _ = zip(*points, strict=True)
        marked = {kind: [(s, q) for s, q, bound in points if bound == kind]
                  for kind in BOUND_MARKERS}
        for i, ax in enumerate(axes):
            if where == i or (where == -1 and i < 2):
                line, = ax.plot(slopes, ratios, style, ms=3 if len(points) > 1 else 5,
                                label=label)
                for kind, found in marked.items():
                    if found:
                        ax.plot(*zip(*found, strict=True), BOUND_MARKERS[kind][0], ms=7,
                                mfc="none", color=line.get_color())
    for ax, title in zip(axes, ("constant friction (rectangle, 5 mm layer)",
                                "layer thickness and column (Drucker-Prager)",
                                "glass beads' mu(I), hysteretic friction"), strict=True):
        ax.axhline(1.0, color="0.5", lw=0.8)
        ax.fill_between([16, 23.5], [1.0, 1.0], [1.0, 1.4], color="0.85",
                        label="experiments: up to +40 % above ~16 deg")
        for marker, meaning in BOUND_MARKERS.values():
            ax.plot([], [], marker, ms=7, mfc="none", color="0.3", label=meaning)
        ax.set(xlabel="slope (deg)", title=title)
        ax.legend(fontsize=6)
    axes[0].set_ylabel("runout erodible / rigid")
    save_figure(fig, path)


def where(results: dict[str, dict]) -> str:
    """The erodible rows' fronts against their rigid twins' in time, then where their
    displaced layer material went (``common/erosion.py``)."""
    rows = sorted(((n, r) for n, r in results.items() if r["he"] > 0 and "front_history" in r),
                  key=lambda item: (item[1]["variant"], item[1]["slope"], item[1]["he"]))
    pairs = [(n, r, results.get(rigid_key(r["variant"], r["shape"], r["slope"]), {}))
             for n, r in rows]
    later = sorted({float(t) for _, r, _ in pairs for t in r["front_history"]} - set(CLOCK))
    return ("## The front over the layer minus the rigid twin's (mm)\n\n"
            + fronts_table(pairs, CLOCK + tuple(later))
            + "\n## Where the displaced layer material went, at the end\n\n"
            + destination_table(rows))


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--variants", nargs="+", default=list(VARIANTS), choices=VARIANTS)
    parser.add_argument("--shapes", nargs="+", default=["rectangle"], choices=SCENARIO)
    parser.add_argument("--slopes", nargs="+", type=float, default=[0, 10, 16, 19, 22])
    parser.add_argument("--thickness", nargs="+", type=float, default=[0.005])
    parser.add_argument("--beds", nargs="+", default=["rigid", "erodible"],
                        choices=["rigid", "erodible"])
    parser.add_argument("--out", type=Path, default=Path("benchmarks/results/erosion_slopes"))
    parser.add_argument("--cells", type=int, default=CELLS, help="cells across the layer")
    parser.add_argument("--t-end", type=float, default=T_END,
                        help="carry rows still moving at 3 s on to this end time (s)")
    parser.add_argument("--collect", action="store_true")
    args = parser.parse_args()
    if not T_END <= args.t_end <= 60:
        parser.error(f"--t-end must be between the study's {T_END:g} s and 60 s, "
                     f"not {args.t_end:g}")
    store = args.out / "erosion_slopes.json"
    results = read_results(store)
    for variant in args.variants:
        for shape in args.shapes:
            for slope in args.slopes:
                beds = ([0.0] if "rigid" in args.beds else []) + (
                    args.thickness if "erodible" in args.beds else [])
                for he in beds:
                    if he == 0 and variant in RIGID_TWIN:     # its rigid bed is the twin's
                        continue
                    name = key(variant, shape, he, slope, args.cells)
                    folder = args.out / "runs" / name
                    archive = args.out / "carried" / f"{name}.tar.gz"
                    results = read_results(store)   # with rows another invocation ran
                    if args.collect:
                        summary = collected(folder)
                        if summary is None:
                            continue
                        kept = results.get(name) or {}      # its overrides stay its own
                        row = with_earlier(row_of(summary, folder), kept) | {
                            k: v for k, v in kept.items() if k == "overrides"}
                    else:
                        if unpack(archive, folder):
                            print(f"{name}: continued from {archive}")
                        rigid = results.get(rigid_key(variant, shape, slope), {}).get("runout_m")
                        row = run(variant, shape, he, slope, rigid, folder, args.cells,
                                  results.get(name), args.t_end)
                    results[name] = row | {"variant": variant, "shape": shape,
                                           "slope": slope, "he": he, "cells": args.cells}
                    report(name, results[name])
                    results = read_results(store) | {name: results[name]}
                    write_json(store, results)
                    write_markdown(args.out / "erosion_slopes.md", table(results))
                    write_markdown(args.out / "erosion_slopes_ratios.md", ratio_table(results))
                    write_markdown(args.out / "erosion_slopes_fronts.md", where(results))
                    status = results[name].get("status")
                    if status in ("interrupted", "failed"):   # a failure is resumed as it failed
                        pack(folder, archive)
                    else:
                        archive.unlink(missing_ok=True)     # finished: no longer carried
                    if status == "interrupted":   # SIGINT or SIGTERM
                        print(f"{name} interrupted: the study stops here; the same command "
                              f"continues it from the run's checkpoint (packed into {archive})")
                        figure(results, args.out / "erosion_slopes.png")
                        return
    figure(results, args.out / "erosion_slopes.png")
    print(table(results))


if __name__ == "__main__":
    main()
