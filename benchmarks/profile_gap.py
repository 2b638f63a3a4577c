"""Benchmark: where an erodible run's extra time goes, against its rigid twin, by category.

Run: python benchmarks/profile_gap.py RIGID.json ERODIBLE.json --cpu RIGID_S ERODIBLE_S
         [--out benchmarks/results/profile_shares/NAME.md]

RIGID.json and ERODIBLE.json are ``profile_shares.py`` records of the two runs (py-spy's
shares of each process by category); RIGID_S and ERODIBLE_S the runs' processor times
(``speed.py --targets``: the medians of whole ``granflow run`` processes). Each category's
seconds are its share times the processor time; the table gives both runs' seconds, the
erodible run's extra seconds and their share of the whole gap, largest first, and the ratio
the erodible run would reach without each category's extra: what each lever can give.
"""

from __future__ import annotations

import argparse
import json
import sys
from pathlib import Path

from common.results import write_markdown


def gap_lines(rigid: dict, erodible: dict, rigid_s: float, erodible_s: float) -> list[str]:
    """The table: seconds per category, the gap's parts, largest first."""
    names = list(dict.fromkeys([*erodible["shares"], *rigid["shares"]]))
    seconds = {n: (rigid_s * rigid["shares"].get(n, 0.0),
                   erodible_s * erodible["shares"].get(n, 0.0)) for n in names}
    gap = erodible_s - rigid_s
    lines = [f"processor time: rigid {rigid_s:.1f} s, erodible {erodible_s:.1f} s, ratio "
             f"{erodible_s / rigid_s:.2f}, gap {gap:.1f} s; iterations {rigid.get('iterations')}"
             f" / {erodible.get('iterations')}, steps {rigid.get('steps')} / "
             f"{erodible.get('steps')}", "",
             "| category | rigid (s) | erodible (s) | extra (s) | share of the gap | ratio "
             "without this extra |", "|---|---|---|---|---|---|"]
    for name in sorted(names, key=lambda n: seconds[n][0] - seconds[n][1]):
        r, e = seconds[name]
        lines.append(f"| {name} | {r:.1f} | {e:.1f} | {e - r:+.1f} | {(e - r) / gap:.0%} | "
                     f"{(erodible_s - (e - r)) / rigid_s:.2f} |")
    return lines


def main(argv: list[str]) -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("rigid", type=Path)
    parser.add_argument("erodible", type=Path)
    parser.add_argument("--cpu", type=float, nargs=2, required=True,
                        metavar=("RIGID_S", "ERODIBLE_S"))
    parser.add_argument("--out", type=Path)
    args = parser.parse_args(argv)
    lines = gap_lines(json.loads(args.rigid.read_text()), json.loads(args.erodible.read_text()),
                      *args.cpu)
    if args.out is None:
        print("\n".join(lines))
    else:
        write_markdown(args.out, lines, show=True)


if __name__ == "__main__":
    main(sys.argv[1:])
