"""A column over a layer of its own material: how much of the bed it entrains.

    python examples/erodible_layer.py [--quick] [--out runs/example-layer] [--figure PATH]

Runs the trapezoid over its 5 mm layer twice, once with the layer of the column's own
material and once with a looser, weaker layer (lower density and friction angle: the
``[layer]`` keys), then compares what each flow did to the bed from the runs' tables: the
eroded area against time (``run.diagnostics``), the erosion depth along the bed
(``run.erosion``) and where the displaced layer material came from (``run.profile``).
Draws both erosion depths into OUT/erosion_depths.png (or PATH).
"""

from __future__ import annotations

import argparse
from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

import granflow  # noqa: E402

LAYERS = {"same material": {}, "looser layer": {"layer.friction_angle_deg": 22.0,
                                                "layer.density": 1450.0}}
QUICK = {"mesh.size": 0.05, "geometry.erodible_thickness": 0.01, "geometry.bed_length": 0.5,
         "time.t_end": 0.05, "time.output_times": [0.05], "surface_tension.enabled": False}


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--quick", action="store_true", help="coarse and short (for tests)")
    parser.add_argument("--out", type=Path, default=Path("runs/example-layer"))
    parser.add_argument("--figure", type=Path, help="where to draw the erosion depths "
                        "(default OUT/erosion_depths.png)")
    args = parser.parse_args()

    fig, ax = plt.subplots(figsize=(8, 3))
    for name, layer in LAYERS.items():
        overrides = {**layer, **(QUICK if args.quick else {})}
        run = granflow.run("trapezoid-erodible", overrides=overrides,
                           out=args.out / name.replace(" ", "-"), force=True)
        history = run.diagnostics
        extra = run.summary.extra
        s = run.summary
        ended = (f"at rest from t = {s.stop_time_s:.3f} s" if s.at_rest
                 else f"still moving at t = {s.t_final:.3f} s")
        print(f"{name}: {s.status}, {ended}, front "
              f"{run.summary.runout_m:.3f} m, column material to {extra['column_front_m']:.3f}"
              f" m; layer displaced {1e4 * extra['layer_displaced_area_m2']:.2f} cm^2 per "
              f"metre (largest in motion at once {1e4 * history['layer_mobilised_area'].max():.2f}"
              f"), down to {1e3 * extra['erosion_depth_max_m']:.1f} mm")
        markers = run.profile("layer_markers")
        grain = run.config.layer.grain_diameter or run.config.material.grain_diameter
        moved = markers[markers["travel"] > grain]      # displaced: by one grain diameter
        if len(moved):
            print(f"  displaced layer material started between x0 = {moved['x0'].min():.3f} "
                  f"and {moved['x0'].max():.3f} m and now lies up to x = "
                  f"{moved['x'].max():.3f} m")
        erosion = run.erosion
        last = erosion[erosion["t"] == erosion["t"].max()]
        ax.step(last["x0"], 1e3 * last["depth"], where="mid", label=name)
    ax.set(xlabel="initial x (m)", ylabel="erosion depth (mm)",
           title="How deep the flow displaced the layer, by original position")
    ax.invert_yaxis()
    ax.legend()
    figure = args.figure or args.out / "erosion_depths.png"
    fig.savefig(figure, dpi=120, bbox_inches="tight")
    print(f"figure: {figure}")


if __name__ == "__main__":
    main()
