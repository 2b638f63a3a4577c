"""A parameter study with the Python API and pandas: runout against the column's height.

    python examples/parameter_study.py [--quick] [--out runs/example-study] [--figure PATH]

Collapses rectangles of base 10 cm and heights 5, 10 and 20 cm over the rigid bed, gathers
their summaries into one DataFrame, writes it as CSV, prints the normalised runout
(r_inf - l0) / l0 against the aspect ratio a = h0 / l0 and draws it with the deposits into
OUT/study.png (or PATH). For many runs in parallel, use `granflow sweep` (the same runs on
Dask workers).
"""

from __future__ import annotations

import argparse
from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import pandas as pd  # noqa: E402

import granflow  # noqa: E402

WIDTH = 0.1
HEIGHTS = [0.05, 0.1, 0.2]


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--quick", action="store_true", help="coarse and short (for tests)")
    parser.add_argument("--out", type=Path, default=Path("runs/example-study"))
    parser.add_argument("--figure", type=Path, help="where to draw the study "
                        "(default OUT/study.png)")
    args = parser.parse_args()

    base = granflow.Config.load("rectangle-rigid").set("geometry.width", WIDTH)
    if args.quick:
        base = (base.set("mesh.size", 0.025).set("time.t_end", 0.05)
                .set("time.output_times", [0.05]))
    rows = []
    fig, (deposits, law) = plt.subplots(1, 2, figsize=(10, 3.2), width_ratios=[2, 1],
                                        layout="constrained")
    for height in HEIGHTS:
        run = granflow.run(base.set("geometry.height", height),
                           out=args.out / f"h{height:g}", force=True)
        last = run.profile("free_surface")            # the last state: at rest, or at t_end
        deposits.plot(last["x"], last["z"], label=f"h0 = {100 * height:g} cm")
        s = run.summary
        rows.append({"height_m": height, "aspect_ratio": height / WIDTH, "status": s.status,
                     "runout_m": s.runout_m, "stop_time_s": s.stop_time_s,
                     "steps": s.steps, "wall_time_s": s.wall_time_s})
    table = pd.DataFrame(rows)
    table["normalised_runout"] = (table["runout_m"] - WIDTH) / WIDTH
    table.to_csv(args.out / "study.csv", index=False)
    print(table[["aspect_ratio", "status", "runout_m", "normalised_runout", "steps"]]
          .to_string(index=False, float_format=lambda v: f"{v:.4g}"))
    deposits.set(xlabel="x (m)", ylabel="z (m)", aspect="equal", title="Last state")
    deposits.legend(fontsize=8)
    law.plot(table["aspect_ratio"], table["normalised_runout"], "o-")
    law.set(xlabel="a = h0 / l0", ylabel="(r_inf - l0) / l0", title="Runout", xlim=(0, None),
            ylim=(0, None))
    figure = args.figure or args.out / "study.png"
    fig.savefig(figure, dpi=120, bbox_inches="tight")
    print(f"figure: {figure}")


if __name__ == "__main__":
    main()
