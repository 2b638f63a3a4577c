"""A granular column collapse with its figures: the paper's rectangle over a rigid bed.

    python examples/collapse.py [--quick] [--out runs/example-collapse] [--figure PATH]

Runs the 20 x 14 cm rectangle to rest (about a minute; --quick: a coarse mesh and the first
0.1 s, a few seconds), prints the headline numbers from ``run.summary`` and draws the free
surfaces at the output times and at rest into OUT/free_surfaces.png (or PATH); the run's
own figures are in OUT/plots.
"""

from __future__ import annotations

import argparse
from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

import granflow  # noqa: E402

QUICK = {"mesh.size": 0.04, "time.t_end": 0.1, "time.output_times": [0.05, 0.1]}


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--quick", action="store_true", help="coarse and short (for tests)")
    parser.add_argument("--out", type=Path, default=Path("runs/example-collapse"))
    parser.add_argument("--figure", type=Path, help="where to draw the free surfaces "
                        "(default OUT/free_surfaces.png)")
    args = parser.parse_args()

    run = granflow.run("rectangle-rigid", overrides=QUICK if args.quick else None,
                       out=args.out, force=True)
    s = run.summary
    ended = (f"at rest from t = {s.stop_time_s:.3f} s" if s.at_rest
             else f"still moving at t = {s.t_final:.3f} s")
    print(f"{s.scenario}: {s.status}, {ended}, after {s.steps} steps "
          f"({s.wall_time_s:.1f} s of wall time, sparse LU {s.linear_solver})")
    print(f"runout {s.runout_m:.4f} m, height at the wall {s.extra['wall_height_m']:.4f} m, "
          f"area drift {s.volume_relative_error:.1e}")
    ax = run.plot.free_surfaces()
    figure = args.figure or run.root / "free_surfaces.png"
    ax.figure.savefig(figure, dpi=120, bbox_inches="tight")
    plt.close(ax.figure)
    print(f"figure: {figure}")


if __name__ == "__main__":
    main()
