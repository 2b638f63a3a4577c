"""Benchmark: the paper's Tables 1 and 2 in full and the iteration counts of section 4.

Run: python benchmarks/plug_flow_tables.py [--out benchmarks/results/plug_flow]
Writes table1.csv/json/png, table2.csv/json/png and iterations.json into --out, and prints
the figures. Expect roughly 15-30 minutes on one core.
"""

from __future__ import annotations

import argparse
import time
from pathlib import Path

from common.results import write_json

from granflow.verify import run_cell, verify_plug_flow

PAPER_ITERATIONS = {1e-2: 824, 1e-4: 2958, 1e-6: 5086, 1e-8: 5272}


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__)
    parser.add_argument("--out", type=Path, default=Path("benchmarks/results/plug_flow"))
    parser.add_argument("--skip-tables", action="store_true")
    args = parser.parse_args()
    args.out.mkdir(parents=True, exist_ok=True)
    start = time.perf_counter()
    rows = []
    for eps, paper in PAPER_ITERATIONS.items():
        error, iterations, _, wall = run_cell(eps, 3.12e-3, 0.125)
        rows.append({"eps": eps, "iterations": iterations, "paper_iterations": paper,
                     "ratio": iterations / paper, "error": error, "wall_time_s": wall})
        print(f"eps={eps:g}: {iterations} iterations (paper {paper}), error {error:.3g}")
    write_json(args.out / "iterations.json", rows)
    if not args.skip_tables:
        for table in (1, 2):
            path = verify_plug_flow(table, "all", args.out, progress=False)
            print(path.read_text())
    print(f"total wall time {time.perf_counter() - start:.1f} s")


if __name__ == "__main__":
    main()
