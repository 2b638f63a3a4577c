"""Benchmark: what an erodible layer costs against a rigid bed, and the default collapse
against an earlier version of granflow, each run as users run it, side by side.

Run: python benchmarks/speed.py --targets [--baseline-src PATH] [--repeat N]
         [--pairs trapezoid cylinder slope22] [--src PATH --tag before]
         [--out benchmarks/results/speed_targets]

Every run is ``granflow run SCENARIO --quiet`` in a new process (figures and animation
included), one after the other and alternating within each pair, so that both members of a
pair see the same load on this shared machine; the medians over REPEAT rounds of each
process's processor time (user + system: what the load of other processes on the machine
changes least) and wall time, and their ratios, are reported with each run's loop time
(summary.json), steps and iterations:

* trapezoid: ``trapezoid-erodible`` against ``trapezoid-rigid``;
* cylinder: ``cylinder-erodible`` against ``cylinder-rigid``;
* slope22: the slope study's 22-degree row of the glass beads' mu(I) (``erosion_slopes.py``,
  variant ``glass-beads``: the rectangle over 5 mm, the layer 1.3 times its rigid twin's
  front at 3 s, meshed 0.1 m ahead of the flow, to rest or to 3 s) against its rigid twin;
* baseline (with ``--baseline-src``, the ``src`` folder of a checkout of an earlier
  commit): ``trapezoid-rigid`` run by that code (``PYTHONPATH``) against this one.

The targets (``TARGETS``): the erodible trapezoid at most 2.5 and the erodible cylinder at
most 2 times their rigid twins' processor time, the 22-degree erodible row in at most 300 s
of processor time. ``--src PATH --tag NAME`` runs the pairs with an earlier checkout's code
and files them under NAME (e.g. ``before``): the table then shows each erodible run's
triangles, steps and iterations before and after.

Writes OUT/speed_targets.json and OUT/speed_targets.md and prints the tables.
"""

from __future__ import annotations

import argparse
import json
import os
import resource
import statistics
import subprocess
import sys
import time
from pathlib import Path

from common.results import read_results, report, write_json, write_markdown
from erosion_slopes import overrides as slope_overrides

# the glass beads' rigid rectangle at 22 degrees: its front at t = 3 s, still moving
# (``granflow run rectangle-rigid`` with ``slope_overrides("glass-beads", "rectangle", 0, 22)``)
RIGID_22_FRONT_M = 2.8946
PAIRS = {
    "trapezoid": (("trapezoid-rigid", []), ("trapezoid-erodible", [])),
    "cylinder": (("cylinder-rigid", []), ("cylinder-erodible", [])),
    "slope22": (("rectangle-rigid", slope_overrides("glass-beads", "rectangle", 0.0, 22.0,
                                                     None)),
                ("rectangle-rigid", slope_overrides("glass-beads", "rectangle", 0.005, 22.0,
                                                     RIGID_22_FRONT_M))),
}
# pair: (what is measured, at most): the processor-time ratio erodible / rigid, or the
# erodible run's processor time (s)
TARGETS = {"trapezoid": ("ratio", 2.5), "cylinder": ("ratio", 2.0),
           "slope22": ("processor time (s)", 300.0)}
KEYS = ["status", "wall_time_s", "steps", "nonlinear_iterations", "n_triangles",
        "remeshes", "stop_time_s", "runout_m"]


def run(scenario: str, sets: list[str], out: Path, src: Path | None = None) -> dict:
    """One ``granflow run`` in a new process; its whole wall time and summary figures."""
    env = dict(os.environ)
    if src is not None:
        env["PYTHONPATH"] = str(src)
    command = [sys.executable, "-m", "granflow", "run", scenario, "--out", str(out),
               "--force", "--quiet", *(arg for o in sets for arg in ("--set", o))]
    before = resource.getrusage(resource.RUSAGE_CHILDREN)
    start = time.perf_counter()
    subprocess.run(command, check=True, stdout=subprocess.DEVNULL, env=env)
    wall = time.perf_counter() - start
    after = resource.getrusage(resource.RUSAGE_CHILDREN)
    cpu = (after.ru_utime - before.ru_utime) + (after.ru_stime - before.ru_stime)
    summary = json.loads((out / "summary.json").read_text())
    return {"process_wall_time_s": wall, "process_cpu_time_s": cpu} | {
        k: summary.get(k) for k in KEYS}


def compare(name: str, first: tuple[str, list[str], Path | None],
            second: tuple[str, list[str], Path | None], repeat: int, out: Path) -> dict:
    """Both members of a pair, alternately, REPEAT times; medians and their ratio."""
    runs: dict[str, list[dict]] = {"first": [], "second": []}
    for k in range(repeat):
        for label, (scenario, sets, src) in (("first", first), ("second", second)):
            result = run(scenario, sets, out / name / f"{label}{k}", src)
            runs[label].append(result)
            report(f"{name} {label} {k}", result)
    median = {label: statistics.median(r["process_wall_time_s"] for r in rows)
              for label, rows in runs.items()}
    cpu = {label: statistics.median(r["process_cpu_time_s"] for r in rows)
           for label, rows in runs.items()}
    loop = {label: statistics.median(r["wall_time_s"] for r in rows)
            for label, rows in runs.items()}
    return {"first": {"scenario": first[0], "overrides": first[1],
                      "src": str(first[2]) if first[2] else None},
            "second": {"scenario": second[0], "overrides": second[1],
                       "src": str(second[2]) if second[2] else None},
            "runs": runs, "process_wall_time_median_s": median,
            "process_cpu_time_median_s": cpu,
            "cpu_ratio_second_to_first": cpu["second"] / cpu["first"],
            "loop_wall_time_median_s": loop,
            "ratio_second_to_first": median["second"] / median["first"],
            "loop_ratio_second_to_first": loop["second"] / loop["first"]}


def target_lines(results: dict) -> list[str]:
    """Each pair's measure against its target (``TARGETS``)."""
    lines = ["| pair | measure | measured | target (at most) | met |", "|---|---|---|---|---|"]
    for name, (measure, limit) in TARGETS.items():
        if name not in results:
            continue
        r = results[name]
        value = (r["cpu_ratio_second_to_first"] if measure == "ratio"
                 else r["process_cpu_time_median_s"]["second"])
        lines.append(f"| {name} | {measure} | {value:.2f} | {limit:g} | "
                     f"{'yes' if value <= limit else 'no'} |")
    if "slope22" in results:    # its ratio too: the third side-by-side ratio
        lines.append(f"| slope22 | ratio | {results['slope22']['cpu_ratio_second_to_first']:.2f}"
                     " | - | - |")
    return lines


def before_after_lines(results: dict, tag: str) -> list[str]:
    """The erodible run of each pair with the code filed under ``tag`` and this one."""
    lines = [f"| pair | triangles, {tag} / now | steps | iterations | remeshes "
             "| processor time (s) |", "|---|---|---|---|---|---|"]
    for name in PAIRS:
        if name not in results or f"{tag}/{name}" not in results:
            continue
        old, new = results[f"{tag}/{name}"], results[name]
        rows = [r["runs"]["second"][0] for r in (old, new)]
        cells = [f"{rows[0].get(k)} / {rows[1].get(k)}" for k in
                 ("n_triangles", "steps", "nonlinear_iterations", "remeshes")]
        cpu = [r["process_cpu_time_median_s"]["second"] for r in (old, new)]
        lines.append(f"| {name} | {' | '.join(cells)} | {cpu[0]:.0f} / {cpu[1]:.0f} |")
    return lines


def main(argv: list[str]) -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--pairs", nargs="*", default=list(PAIRS), choices=list(PAIRS),
                        help="the scenario pairs (none: only the baseline)")
    parser.add_argument("--baseline-src", type=Path,
                        help="src folder of an earlier granflow checkout: time its default "
                             "collapse against this one's")
    parser.add_argument("--repeat", type=int, default=1)
    parser.add_argument("--src", type=Path,
                        help="src folder of an earlier checkout: run the pairs with its code")
    parser.add_argument("--tag", default="",
                        help="file the pairs under TAG/PAIR (with --src, e.g. before)")
    parser.add_argument("--out", type=Path, default=Path("benchmarks/results/speed_targets"))
    args = parser.parse_args(argv)
    results_file = args.out / "speed_targets.json"
    results = read_results(results_file)
    src = args.src.resolve() if args.src is not None else None
    prefix = f"{args.tag}/" if args.tag else ""
    cases = {prefix + name: ((*PAIRS[name][0], src), (*PAIRS[name][1], src))
             for name in args.pairs}
    if args.baseline_src is not None:
        cases["baseline"] = (("trapezoid-rigid", [], args.baseline_src.resolve()),
                             ("trapezoid-rigid", [], None))
    for name, (first, second) in cases.items():
        results[name] = compare(name, first, second, args.repeat, args.out / "runs")
        write_json(results_file, results)
    lines = ["| pair | first | second | processor time (s), first / second | second / first "
             "| wall time (s), first / second | second / first | iterations, first / second |",
             "|---|---|---|---|---|---|---|---|"]
    for name, r in results.items():
        p, c = r["process_wall_time_median_s"], r["process_cpu_time_median_s"]
        its = [r["runs"][k][0]["nonlinear_iterations"] for k in ("first", "second")]
        lines.append(f"| {name} | {r['first']['scenario']} | {r['second']['scenario']} | "
                     f"{c['first']:.1f} / {c['second']:.1f} | {r['cpu_ratio_second_to_first']:.2f} "
                     f"| {p['first']:.1f} / {p['second']:.1f} | {r['ratio_second_to_first']:.2f} "
                     f"| {its[0]} / {its[1]} |")
    tags = sorted({k.split("/")[0] for k in results if "/" in k})
    lines += ["", *target_lines(results)]
    for tag in tags:
        lines += ["", *before_after_lines(results, tag)]
    write_markdown(args.out / "speed_targets.md", lines, show=True)


if __name__ == "__main__":
    main(sys.argv[1:])
