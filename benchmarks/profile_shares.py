"""Benchmark: where the time of one ``granflow run`` goes, by category, from py-spy samples.

Run: python benchmarks/profile_shares.py [SCENARIO] [--set key=value ...] [--src PATH]
         [--rate 50] [--out benchmarks/results/profile_shares/NAME.json]

Samples the whole process (``py-spy record --format raw``, Python frames) and sorts each
stack into the first category of ``CATEGORIES`` whose pattern it contains (inclusive: a
sample inside the factorisation called from the nonlinear iteration counts as
factorisation). ``--src`` runs an earlier checkout's code (its ``src`` folder, through
``PYTHONPATH``), so that two versions are profiled the same way. Prints the shares and writes
them, with the sample count, as JSON. Needs ``py-spy`` (``pip install py-spy``).
"""

from __future__ import annotations

import argparse
import json
import os
import re
import subprocess
import sys
import tempfile
from collections import Counter
from pathlib import Path

from common.results import write_json, write_markdown

CATEGORIES = [   # (name, patterns of a frame "Class.method (path:line)"), first match wins
    ("factorisation (sparse LU)", [r"update \(.*fem/linalg\.py", r"Inverse"]),
    ("back-substitution", [r"solve \(.*fem/linalg\.py"]),
    ("assembly (matrix and right-hand side of (3.2))", [r"[aA]ssemble\w* \("]),
    ("output (VTU, profiles, frames, figures, animation)", [r"granflow/io/", r"matplotlib"]),
    ("mesh velocity (3.6) and the mesh move", [r"mesh_motion\.py", r"column_mover\.py"]),
    ("mesh-size field (adaptive mesh)", [r"size_field\.py", r"column_sizes\.py"]),
    ("remeshing and transfer", [r"remesh\.py", r"transfer\.py", r"column_remesher\.py"]),
    ("surface tension and deposition", [r"surface_tension\.py", r"deposition\.py"]),
    ("erodible layer tracking", [r"layer_material\.py", r"column_layer\.py"]),
    ("nonlinear iteration (norms, vectors, mixing, dual)",
     [r"nonlinear\.py", r"anderson\.py", r"primal_dual\.py"]),
    ("step acceptance, error estimate and diagnostics",
     [r"simulation/", r"fem/flow\.py", r"column_measures\.py"]),
    ("start-up (imports, mesh, forms)", [r"_find_and_load", r"^build_"]),
]
COMPILED = [(name, [re.compile(p) for p in patterns]) for name, patterns in CATEGORIES]


def category(stack: str) -> str:
    """The first category with a pattern matching one of the stack's frames."""
    frames = stack.split(";")
    for name, patterns in COMPILED:
        if any(p.search(f) for p in patterns for f in frames):
            return name
    return "other"


def shares(raw: str) -> tuple[dict[str, float], int]:
    """Category -> share of the samples, and the number of samples."""
    counts: Counter[str] = Counter()
    for line in raw.splitlines():
        stack, _, n = line.rpartition(" ")
        if stack and n.isdigit():
            counts[category(stack)] += int(n)
    total = sum(counts.values())
    order = [c for c, _ in CATEGORIES] + ["other"]
    return {c: counts[c] / total for c in order if total}, total


def main(argv: list[str]) -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("scenario", nargs="?", default="trapezoid-rigid")
    parser.add_argument("--set", dest="overrides", action="append", default=[])
    parser.add_argument("--src", type=Path, help="an earlier checkout's src folder")
    parser.add_argument("--rate", type=int, default=50)
    parser.add_argument("--raw", type=Path, help="also keep py-spy's raw stacks there")
    parser.add_argument("--out", type=Path,
                        default=Path("benchmarks/results/profile_shares/profile.json"))
    args = parser.parse_args(argv)
    env = dict(os.environ)
    if args.src is not None:
        env["PYTHONPATH"] = str(args.src.resolve())
    with tempfile.TemporaryDirectory() as tmp:
        raw = Path(tmp) / "stacks.txt"
        command = ["py-spy", "record", "--format", "raw", "--rate", str(args.rate),
                   "--output", str(raw), "--", sys.executable, "-m", "granflow", "run",
                   args.scenario, "--quiet", "--force", "--out", str(Path(tmp) / "run"),
                   *(a for o in args.overrides for a in ("--set", o))]
        subprocess.run(command, check=True, env=env, stdout=subprocess.DEVNULL)
        found, samples = shares(raw.read_text())
        if args.raw is not None:
            write_markdown(args.raw, raw.read_text())
        summary = json.loads((Path(tmp) / "run" / "summary.json").read_text())
    for name, share in found.items():
        print(f"{100 * share:5.1f} %  {name}")
    print(f"{samples} samples at {args.rate} Hz; {summary.get('nonlinear_iterations')} "
          f"iterations, {summary.get('steps')} steps")
    write_json(args.out, {
        "scenario": args.scenario, "overrides": args.overrides,
        "src": str(args.src) if args.src else None, "rate_hz": args.rate, "samples": samples,
        "steps": summary.get("steps"), "iterations": summary.get("nonlinear_iterations"),
        "shares": found})


if __name__ == "__main__":
    main(sys.argv[1:])
