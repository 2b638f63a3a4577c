"""Two rheologies on the same collapse: Drucker-Prager (2.13) against mu(I).

    python examples/compare_rheologies.py [--quick] [--out runs/example-rheologies]
                                          [--figure PATH]

Runs the trapezoid over the rigid bed with each law, reads both runs' free surfaces back as
tidy DataFrames (t, kind, x, z), puts them on a common grid in x and prints the largest
height difference at each output time; draws both last surfaces into OUT/rheologies.png
(or PATH).
"""

from __future__ import annotations

import argparse
from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402
import pandas as pd  # noqa: E402

import granflow  # noqa: E402

LAWS = {"drucker-prager": {}, "mu-i": {"material.rheology": "mu-i"}}
QUICK = {"mesh.size": 0.05, "time.t_end": 0.06, "time.output_times": [0.03, 0.06]}


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--quick", action="store_true", help="coarse and short (for tests)")
    parser.add_argument("--out", type=Path, default=Path("runs/example-rheologies"))
    parser.add_argument("--figure", type=Path, help="where to draw the comparison "
                        "(default OUT/rheologies.png)")
    args = parser.parse_args()

    surfaces, ends = [], {}
    for law, overrides in LAWS.items():
        run = granflow.run("trapezoid-rigid", overrides={**overrides, **(QUICK if args.quick
                                                                          else {})},
                           out=args.out / law, force=True)
        s = run.summary
        ended = (f"at rest from t = {s.stop_time_s:.3f} s" if s.at_rest
                 else f"still moving at t = {s.t_final:.3f} s")
        print(f"{law}: {s.status}, {ended}, runout {s.runout_m:.4f} m")
        table = run.surfaces
        free = table[table["kind"] == "free_surface"]
        surfaces.append(free.assign(law=law))
        ends[law] = (ended, run.profile("free_surface"))       # the last state
    both = pd.concat(surfaces, ignore_index=True)

    grid = np.linspace(0.0, both["x"].max(), 400)
    for t, at_t in both.groupby("t"):                # the output times both runs reached
        heights = {law: np.interp(grid, rows["x"], rows["z"], right=0.0)
                   for law, rows in at_t.groupby("law")}
        if len(heights) == 2:
            gap = np.abs(heights["drucker-prager"] - heights["mu-i"]).max()
            print(f"t = {t:.3f} s: largest height difference {1000 * gap:.2f} mm")

    fig, ax = plt.subplots(figsize=(8, 3))
    for law, (ended, last) in ends.items():
        ax.plot(last["x"], last["z"], label=f"{law}, {ended}")
    ax.set(xlabel="x (m)", ylabel="z (m)", aspect="equal", title="Free surface, last state")
    ax.legend(fontsize=8)
    figure = args.figure or args.out / "rheologies.png"
    fig.savefig(figure, dpi=120, bbox_inches="tight")
    print(f"figure: {figure}")


if __name__ == "__main__":
    main()
