"""Benchmark: what an erodible layer costs against a rigid bed as users wait for it, each run
a whole ``granflow run`` process, side by side, on a quiet machine and beside a busy one.

Run: python benchmarks/speed.py --targets [--pairs trapezoid cylinder slope22]
         [--repeat 3] [--conditions quiet busy] [--baseline-src PATH]
         [--baseline-scenario trapezoid-rigid]
         [--src PATH --tag NAME] [--out benchmarks/results/speed_targets]

Every run is ``granflow run SCENARIO --quiet`` in a new process (start-up, figures and
animation included), timed from outside: its wall time from start to exit, and the
operating system's account of the finished child (``os.wait4``): processor time (user +
system), peak memory, page faults and context switches. The members of a pair alternate
(rigid, erodible, rigid, ...) so that both see the same machine; each figure is the median
over REPEAT rounds, and a ratio is the median of the rounds' ratios. The load average
(1 min) before each run is kept beside it.

Conditions: ``quiet`` runs on the machine as it is; ``busy`` starts one process that spins
on a core (a second busy process, as a user's laptop has) before the round and stops it
after. Wall-time ratios are meaningful only when the quiet rounds ran on a quiet machine:
the table says how loaded it was, and the targets are judged on the quiet wall times.

* trapezoid: ``trapezoid-erodible`` against ``trapezoid-rigid``;
* cylinder: ``cylinder-erodible`` against ``cylinder-rigid``;
* slope22: the slope study's 22-degree row of the glass beads' mu(I) (``erosion_slopes.py``,
  variant ``glass-beads``: the rectangle over 5 mm, the layer 1.3 times its rigid twin's
  front at 3 s, meshed 0.1 m ahead of the flow, to rest or to 3 s) against its rigid twin,
  with granflow's defaults for the mesh and the tension (the study's rows pinned the
  uniform mesh of their time);
* baseline (with ``--baseline-src``, the ``src`` folder of a checkout of an earlier
  commit): ``trapezoid-rigid`` (or ``--baseline-scenario``) run by that code
  (``PYTHONPATH``) against this one.

The targets (``TARGETS``, wall time on a quiet machine): each erodible run at most 2.5 times
its rigid twin, the 22-degree erodible row in at most 300 s. ``--src PATH --tag NAME`` runs
the pairs with an earlier checkout's code and files them under NAME.

In each pair the rigid run comes first and the erodible second (for the baseline: the
earlier code, then this one). Writes OUT/speed_targets.json and OUT/speed_targets.md and
prints the tables.
"""

from __future__ import annotations

import argparse
import statistics
import subprocess
import sys
import time
from pathlib import Path

from common.process import timed_run
from common.results import read_results, report, write_json, write_markdown
from erosion_slopes import overrides as slope_overrides

# the glass beads' rigid rectangle at 22 degrees: its front at t = 3 s, still moving
# (``granflow run rectangle-rigid`` with ``slope_overrides("glass-beads", "rectangle", 0, 22)``)
RIGID_22_FRONT_M = 2.8946
PINNED = ("mesh.adaptive=", "surface_tension.length=")   # the study's rows' own mesh, tension


def _slope22(he: float, rigid_front: float | None) -> list[str]:
    return [o for o in slope_overrides("glass-beads", "rectangle", he, 22.0, rigid_front)
            if not o.startswith(PINNED)]


PAIRS = {
    "trapezoid": (("trapezoid-rigid", []), ("trapezoid-erodible", [])),
    "cylinder": (("cylinder-rigid", []), ("cylinder-erodible", [])),
    "slope22": (("rectangle-rigid", _slope22(0.0, None)),
                ("rectangle-rigid", _slope22(0.005, RIGID_22_FRONT_M))),
}
# pair: (what is measured, at most): the wall-time ratio erodible / rigid, or the erodible
# run's wall time (s), on a quiet machine
TARGETS = {"trapezoid": ("ratio", 2.5), "cylinder": ("ratio", 2.5),
           "slope22": ("wall time (s)", 300.0)}
QUIET_LOAD = 0.5    # load average (1 min) above which the machine was not quiet
BUSY = "while True:\n    pass\n"
KEYS = ["status", "wall_time_s", "steps", "rejected_steps", "nonlinear_iterations",
        "n_triangles", "remeshes", "stop_time_s", "runout_m"]


def run(scenario: str, sets: list[str], out: Path, src: Path | None = None) -> dict:
    """One ``granflow run`` in a new process: its times, the load before it, its summary's
    KEYS."""
    result = timed_run(scenario, sets, out, src=src)
    summary = result.pop("summary")
    return result | {k: summary.get(k) for k in KEYS}


class Busy:
    """One process spinning on a core while the block runs (the ``busy`` condition)."""

    def __init__(self, on: bool) -> None:
        self.on, self.process = on, None

    def __enter__(self) -> Busy:
        if self.on:
            self.process = subprocess.Popen([sys.executable, "-c", BUSY])
            time.sleep(1.0)     # let it start spinning
        return self

    def __exit__(self, *exc: object) -> None:
        if self.process is not None:
            self.process.kill()
            self.process.wait()


def median(rows: list[dict], key: str) -> float:
    return statistics.median(r[key] for r in rows)


def compare(name: str, first: tuple[str, list[str], Path | None],
            second: tuple[str, list[str], Path | None], repeat: int,
            conditions: list[str], out: Path) -> dict:
    """Both members of a pair, alternately, REPEAT rounds in each condition."""
    runs: dict[str, dict[str, list[dict]]] = {c: {"first": [], "second": []}
                                              for c in conditions}
    for k in range(repeat):
        for condition in conditions:
            with Busy(condition == "busy"):
                for label, (scenario, sets, src) in (("first", first), ("second", second)):
                    result = run(scenario, sets, out / name / f"{condition}-{label}{k}", src)
                    runs[condition][label].append(result)
                    report(f"{name} {condition} {label} {k}", result)
    stats = {}
    for condition, rows in runs.items():
        ratios = [b["process_wall_time_s"] / a["process_wall_time_s"]
                  for a, b in zip(rows["first"], rows["second"], strict=True)]
        cpu_ratios = [b["process_cpu_time_s"] / a["process_cpu_time_s"]
                      for a, b in zip(rows["first"], rows["second"], strict=True)]
        stats[condition] = {
            "wall_s": {lab: median(r, "process_wall_time_s") for lab, r in rows.items()},
            "cpu_s": {lab: median(r, "process_cpu_time_s") for lab, r in rows.items()},
            "wall_ratio": statistics.median(ratios), "cpu_ratio": statistics.median(cpu_ratios),
            "load_before": median(rows["first"] + rows["second"], "load_before")}
    return {"first": {"scenario": first[0], "overrides": first[1],
                      "src": str(first[2]) if first[2] else None},
            "second": {"scenario": second[0], "overrides": second[1],
                       "src": str(second[2]) if second[2] else None},
            "runs": runs, "stats": stats}


def pair_lines(results: dict) -> list[str]:
    lines = ["| pair | condition | load (1 min) | wall time (s), first / second | ratio "
             "| processor time (s), first / second | ratio | iterations | remeshes |",
             "|---|---|---|---|---|---|---|---|---|"]
    for name, r in results.items():
        for condition, s in r["stats"].items():
            rows = r["runs"][condition]
            its = " / ".join(str(rows[k][0]["nonlinear_iterations"]) for k in rows)
            meshes = " / ".join(str(rows[k][0]["remeshes"]) for k in rows)
            w, c = s["wall_s"], s["cpu_s"]
            lines.append(f"| {name} | {condition} | {s['load_before']:.1f} | "
                         f"{w['first']:.1f} / {w['second']:.1f} | {s['wall_ratio']:.2f} | "
                         f"{c['first']:.1f} / {c['second']:.1f} | {s['cpu_ratio']:.2f} | "
                         f"{its} | {meshes} |")
    return lines


def target_lines(results: dict) -> list[str]:
    """Each pair's measure against its target, on the quiet wall times."""
    lines = ["| pair | measure | wall time (quiet) | processor time | target (at most) | met |",
             "|---|---|---|---|---|---|"]
    for name, (measure, limit) in TARGETS.items():
        if name not in results or "quiet" not in results[name]["stats"]:
            continue
        s = results[name]["stats"]["quiet"]
        wall, cpu = ((s["wall_ratio"], s["cpu_ratio"]) if measure == "ratio"
                     else (s["wall_s"]["second"], s["cpu_s"]["second"]))
        quiet = s["load_before"] <= QUIET_LOAD + 1.0   # our own run counts for one
        verdict = ("yes" if wall <= limit else "no") if quiet else (
            f"not judged: load {s['load_before']:.1f}, rerun on a quiet machine")
        lines.append(f"| {name} | {measure} | {wall:.2f} | {cpu:.2f} | {limit:g} | {verdict} |")
    return lines


def load_lines(results: dict) -> list[str]:
    """What a second busy process does to each run: busy over quiet, and why."""
    lines = ["| pair | member | wall busy / quiet | processor busy / quiet | involuntary "
             "switches, quiet / busy | minor faults | peak memory (MB) |",
             "|---|---|---|---|---|---|---|"]
    for name, r in results.items():
        if not {"quiet", "busy"} <= set(r["runs"]):
            continue
        for label, member in (("first", "rigid"), ("second", "erodible")):
            q, b = r["runs"]["quiet"][label], r["runs"]["busy"][label]
            lines.append(
                f"| {name} | {member} | "
                f"{median(b, 'process_wall_time_s') / median(q, 'process_wall_time_s'):.2f} | "
                f"{median(b, 'process_cpu_time_s') / median(q, 'process_cpu_time_s'):.2f} | "
                f"{median(q, 'involuntary_switches'):.0f} / "
                f"{median(b, 'involuntary_switches'):.0f} | {median(q, 'minor_faults'):.0f} | "
                f"{median(q, 'peak_memory_mb'):.0f} |")
    return lines


def main(argv: list[str]) -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--pairs", nargs="*", default=list(PAIRS), choices=list(PAIRS),
                        help="the scenario pairs (none: only the baseline)")
    parser.add_argument("--repeat", type=int, default=3)
    parser.add_argument("--conditions", nargs="+", default=["quiet", "busy"],
                        choices=["quiet", "busy"])
    parser.add_argument("--baseline-src", type=Path,
                        help="src folder of an earlier granflow checkout: time its default "
                             "collapse against this one's")
    parser.add_argument("--baseline-scenario", default="trapezoid-rigid",
                        help="the scenario the baseline times with both codes")
    parser.add_argument("--src", type=Path,
                        help="src folder of an earlier checkout: run the pairs with its code")
    parser.add_argument("--tag", default="",
                        help="file the pairs under TAG/PAIR (with --src, e.g. before)")
    parser.add_argument("--out", type=Path, default=Path("benchmarks/results/speed_targets"))
    args = parser.parse_args(argv)
    results_file = args.out / "speed_targets.json"
    results = {k: v for k, v in read_results(results_file).items() if "stats" in v}
    src = args.src.resolve() if args.src is not None else None
    prefix = f"{args.tag}/" if args.tag else ""
    cases = {prefix + name: ((*PAIRS[name][0], src), (*PAIRS[name][1], src))
             for name in args.pairs}
    if args.baseline_src is not None:
        cases["baseline"] = ((args.baseline_scenario, [], args.baseline_src.resolve()),
                             (args.baseline_scenario, [], None))
    for name, (first, second) in cases.items():
        results[name] = compare(name, first, second, args.repeat, args.conditions,
                                args.out / "runs")
        write_json(results_file, results)
    lines = [*pair_lines(results), "", *target_lines(results), "", *load_lines(results)]
    write_markdown(args.out / "speed_targets.md", lines, show=True)


if __name__ == "__main__":
    main(sys.argv[1:])
