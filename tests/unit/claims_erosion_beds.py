"""The erosion page's numbers from the sliding beds' rows (the Coulomb and material beds in
the side-walls study's set-up, the paper's model on two meshes, the rigid twins' fronts 1 mm
above the bed; benchmarks/erosion_slopes.py, ``benchmarks/results/erosion_slopes_walls``),
as claims for tests/unit/test_docs_numbers.py, with the side-walls claims' helpers."""

from __future__ import annotations

import importlib.util
import json
from collections.abc import Callable
from pathlib import Path
from typing import Any

_SPEC = importlib.util.spec_from_file_location(
    "claims_erosion_walls", Path(__file__).with_name("claims_erosion_walls.py"))
assert _SPEC is not None and _SPEC.loader is not None
_WALLS = importlib.util.module_from_spec(_SPEC)
_SPEC.loader.exec_module(_WALLS)
each, row, ratio, lead = _WALLS.each, _WALLS.row, _WALLS.ratio, _WALLS.lead

FIRST = json.loads((Path(__file__).resolve().parents[2] / "benchmarks" / "results"
                    / "erosion_slopes" / "erosion_slopes.json").read_text(encoding="utf-8"))
N, C, M = ("glass-beads-no-slip-small-eta-walls", "glass-beads-coulomb-small-eta-walls",
           "glass-beads-material-small-eta-walls")
P = "drucker-prager"
mm = 1e3
SLOPES = (0, 10, 19)


def thick(layer: str, rigid: str) -> Callable[[Any], float]:
    """A layer row's runout over its rigid twin's front 1 mm above the bed."""
    return lambda d: (row(*layer.split("/"), "runout_m")(d)
                      / row(*rigid.split("/"), "runout_1mm_m")(d))


def tongue(rigid: str) -> Callable[[Any], float]:
    """A rigid row's furthest point beyond its front 1 mm above the bed (m)."""
    return lambda d: (row(*rigid.split("/"), "runout_m")(d)
                      - row(*rigid.split("/"), "runout_1mm_m")(d))


def over(a: str, b: str) -> Callable[[Any], float]:
    """One rigid row's runout over another's, minus one."""
    return lambda d: (row(*a.split("/"), "runout_m")(d) / row(*b.split("/"), "runout_m")(d)
                      - 1)


def spread(slope: int) -> Callable[[Any], float]:
    """The three beds' layer rows over 5 mm: largest minus smallest runout (m)."""
    return lambda d: (max(row(v, f"5mm-{slope}", "runout_m")(d) for v in (N, C, M))
                      - min(row(v, f"5mm-{slope}", "runout_m")(d) for v in (N, C, M)))


def first(slope: int, rigid: bool = False) -> Callable[[Any], float]:
    """The first study's Drucker-Prager ratio at ``slope``: as published, or (``rigid``)
    against the rigid row run again here, its front 1 mm above the bed."""
    def value(d: Any) -> float:
        layer = FIRST[f"{P}/rectangle-5mm-{slope}"]["runout_m"]
        if rigid:
            return layer / d[f"{P}/rectangle-0mm-{slope}"]["runout_1mm_m"]
        return layer / FIRST[f"{P}/rectangle-0mm-{slope}"]["runout_m"]
    return value


def rerun_drift(d: Any) -> float:
    """The largest change of Drucker-Prager's rigid rows run again (m)."""
    return max(abs(d[f"{P}/rectangle-0mm-{a}"]["runout_m"]
                   - FIRST[f"{P}/rectangle-0mm-{a}"]["runout_m"]) for a in (0, 10, 16, 19, 22))


CLAIMS = [
    *(claim for v, label in ((N, "no-slip bed"), (C, "Coulomb bed"), (M, "material bed"))
      for claim in each(f"| {label} | {{}} m | {{}} m | {{}} mm |",
                        (row(v, "0mm-0", "runout_m"), ".4f", 1),
                        (row(f"{v}-fine", "0mm-0", "runout_m"), ".4f", 1),
                        (lead(f"{v}-fine/0mm-0", f"{v}/0mm-0", None), "+.1f", mm))),
    *each("| the paper's model | {} m | {} m | {} mm |",
          (row(P, "0mm-0", "runout_m"), ".4f", 1), (row(f"{P}-fine", "0mm-0", "runout_m"),
                                                   ".4f", 1),
          (lead(f"{P}-fine/0mm-0", f"{P}/0mm-0", None), "+.1f", mm)),
    *each("mesh were interrupted at {} and {} s",
          (row(f"{C}-finer", "0mm-0", "t_final"), ".2f", 1),
          (row(f"{M}-finer", "0mm-0", "t_final"), ".2f", 1)),
    *each("- **The paper's model moves by {} mm**",
          (lead(f"{P}-fine/0mm-0", f"{P}/0mm-0", None), "+.1f", mm)),
    *each("level bed:** {} %\n  (Coulomb) and {} % (material) on the study's mesh, {} % and {} "
          "% on the finer\n  one.",
          (over(f"{C}/0mm-0", f"{P}/0mm-0"), "+.1f", 100),
          (over(f"{M}/0mm-0", f"{P}/0mm-0"), "+.1f", 100),
          (over(f"{C}-fine/0mm-0", f"{P}-fine/0mm-0"), "+.1f", 100),
          (over(f"{M}-fine/0mm-0", f"{P}-fine/0mm-0"), "+.1f", 100)),
    *each("study's mesh ({} % here),\n  is at {} % on the finer mesh.",
          (over(f"{N}/0mm-0", f"{P}/0mm-0"), "+.1f", 100),
          (over(f"{N}-fine/0mm-0", f"{P}-fine/0mm-0"), "+.1f", 100)),
    *each("| over 5 mm, no-slip bed | {} m | {} m | {} m |",
          *((row(N, f"5mm-{a}", "runout_m"), ".4f", 1) for a in SLOPES)),
    *each("| over 5 mm, Coulomb bed | {} m | {} m | {} m, moving at 3 s |",
          *((row(C, f"5mm-{a}", "runout_m"), ".4f", 1) for a in SLOPES)),
    *each("| over 5 mm, material bed | {} m | {} m | {} m, at rest at {} s |",
          *((row(M, f"5mm-{a}", "runout_m"), ".4f", 1) for a in SLOPES),
          (row(M, "5mm-19", "stop_time_s"), ".3f", 1)),
    *each("| rigid, Coulomb bed | {} m | {} m | {} m |",
          *((row(f"{C}-tension", f"0mm-{a}", "runout_m"), ".4f", 1) for a in SLOPES)),
    *each("| rigid, material bed | {} m | {} m | {} m at 6 s, moving at {} mm/s |",
          *((row(f"{M}-tension", f"0mm-{a}", "runout_m"), ".4f", 1) for a in SLOPES),
          (row(f"{M}-tension", "0mm-19", "front_speed_end_m_s"), ".0f", mm)),
    *each("runouts are within {} mm of each other at 0°, {} mm at\n  10° and {} mm at 19°",
          *((spread(a), ".1f", mm) for a in SLOPES)),
    *each("The rigid rows differ by up to {} % (19°: {} m on the no-slip\n  bed, {} m on the "
          "Coulomb bed)",
          (over(f"{C}-tension/0mm-19", f"{N}/0mm-19"), ".0f", 100),
          (row(N, "0mm-19", "runout_m"), ".4f", 1),
          (row(f"{C}-tension", "0mm-19", "runout_m"), ".4f", 1)),
    *each("{} mm (Coulomb) and {} mm (material) on the level bed, {} and\n{} mm at 19°.",
          (tongue(f"{C}-tension/0mm-0"), ".1f", mm), (tongue(f"{M}-tension/0mm-0"), ".1f", mm),
          (tongue(f"{C}-tension/0mm-19"), ".1f", mm),
          (tongue(f"{M}-tension/0mm-19"), ".1f", mm)),
    *each("| Coulomb bed | {} | {} | ≥ {} |",
          *((ratio(f"{C}/5mm-{a}", f"{C}-tension/0mm-{a}"), ".3f", 1) for a in SLOPES)),
    *each("| material bed | {} | {} | ≤ {} |",
          *((ratio(f"{M}/5mm-{a}", f"{M}-tension/0mm-{a}"), ".3f", 1) for a in SLOPES)),
    *(claim for v, mark in ((C, "≥"), (M, "≤"))
      for claim in each(f"| its rigid twin at 1 mm | {{}} | {{}} | {mark} {{}} |",
                        *((thick(f"{v}/5mm-{a}", f"{v}-tension/0mm-{a}"), ".3f", 1)
                          for a in SLOPES))),
    *each("| material bed, finer mesh | {} | {} | ≤ {} |\n| its rigid twin at 1 mm | {} | {} | "
          "≤ {} |",
          *((ratio(f"{M}-fine/5mm-{a}", f"{M}-fine-tension/0mm-{a}"), ".3f", 1) for a in SLOPES),
          *((thick(f"{M}-fine/5mm-{a}", f"{M}-fine-tension/0mm-{a}"), ".3f", 1)
            for a in SLOPES)),
    *each("The layer row at 19° moves by {} mm\n  ({} m, at rest at {} s).",
          (lead(f"{M}-fine/5mm-19", f"{M}/5mm-19", None), "+.1f", mm),
          (row(f"{M}-fine", "5mm-19", "runout_m"), ".4f", 1),
          (row(f"{M}-fine", "5mm-19", "stop_time_s"), ".3f", 1)),
    *each("alike too ({} to {}).",
          (thick(f"{C}/5mm-0", f"{C}-tension/0mm-0"), ".2f", 1),
          (thick(f"{C}/5mm-19", f"{C}-tension/0mm-19"), ".2f", 1)),
    *each("10° ({} and {}; {} and {} with the fronts alike) and above it at 19°\n  (≤ {}, the "
          "rigid twin still creeping at 6 s; ≤ {} with the fronts alike)",
          (ratio(f"{M}/5mm-0", f"{M}-tension/0mm-0"), ".3f", 1),
          (ratio(f"{M}/5mm-10", f"{M}-tension/0mm-10"), ".3f", 1),
          (thick(f"{M}/5mm-0", f"{M}-tension/0mm-0"), ".3f", 1),
          (thick(f"{M}/5mm-10", f"{M}-tension/0mm-10"), ".3f", 1),
          (ratio(f"{M}/5mm-19", f"{M}-tension/0mm-19"), ".3f", 1),
          (thick(f"{M}/5mm-19", f"{M}-tension/0mm-19"), ".3f", 1)),
    *each("refuted by {} and {} on the study's",
          (lambda d: 0.97 - ratio(f"{M}/5mm-0", f"{M}-tension/0mm-0")(d), ".3f", 1),
          (lambda d: 0.98 - ratio(f"{M}/5mm-10", f"{M}-tension/0mm-10")(d), ".3f", 1)),
    *each("ratios move by {}, {} and {} at 0, 10 and 19° (predicted below 0.03)",
          *((lambda d, a=a: (ratio(f"{M}-fine/5mm-{a}", f"{M}-fine-tension/0mm-{a}")(d)
                             - ratio(f"{M}/5mm-{a}", f"{M}-tension/0mm-{a}")(d)), "+.3f", 1)
            for a in SLOPES)),
    *each("on the material bed: {} m at 6 s, moving at\n  {} mm/s; on the finer mesh {} m at "
          "6 s, at {} mm/s",
          (row(f"{M}-tension", "0mm-19", "runout_m"), ".4f", 1),
          (row(f"{M}-tension", "0mm-19", "front_speed_end_m_s"), ".0f", mm),
          (row(f"{M}-fine-tension", "0mm-19", "runout_m"), ".4f", 1),
          (row(f"{M}-fine-tension", "0mm-19", "front_speed_end_m_s"), ".0f", mm)),
    *each("over 5 mm {} m, at rest at {} s; the rigid twin {} m, at rest at\n  {} s: {} ({} with "
          "the fronts alike), inside the rule's band by {}.",
          (row(M, "5mm-16", "runout_m"), ".4f", 1), (row(M, "5mm-16", "stop_time_s"), ".3f", 1),
          (row(f"{M}-tension", "0mm-16", "runout_m"), ".4f", 1),
          (row(f"{M}-tension", "0mm-16", "stop_time_s"), ".3f", 1),
          (ratio(f"{M}/5mm-16", f"{M}-tension/0mm-16"), ".3f", 1),
          (thick(f"{M}/5mm-16", f"{M}-tension/0mm-16"), ".3f", 1),
          (lambda d: 1.05 - ratio(f"{M}/5mm-16", f"{M}-tension/0mm-16")(d), ".3f", 1)),
    *each("grows with the slope above 10°: {}, {}, {} and\n  ≤ {}.",
          *((ratio(f"{M}/5mm-{a}", f"{M}-tension/0mm-{a}"), ".3f", 1) for a in (0, 10, 16, 19))),
    *each("interrupted at {} s and carried; its rigid twin's\n  front is at {} m at 6 s, still "
          "moving at {} mm/s.",
          (row(M, "5mm-22", "t_final"), ".2f", 1),
          (row(f"{M}-tension", "0mm-22", "runout_m"), ".4f", 1),
          (row(f"{M}-tension", "0mm-22", "front_speed_end_m_s"), ".0f", mm)),
    *each("within {} mm of\n  the first runs)", (rerun_drift, ".1f", mm)),
    *each("give the first study's layer rows {}, {}, {}, {} and {}\n  at 0, 10, 16, 19 and 22°",
          *((first(a, rigid=True), ".3f", 1) for a in (0, 10, 16, 19, 22))),
    *each("({}, {}, {}, {} and\n  {} as published)",
          *((first(a), ".3f", 1) for a in (0, 10, 16, 19, 22))),
    *each("level test against the paper's model ({} %, as the Coulomb bed's {} %)",
          (over(f"{M}/0mm-0", f"{P}/0mm-0"), "+.0f", 100),
          (over(f"{C}/0mm-0", f"{P}/0mm-0"), "+.0f", 100)),
    *each("level rigid runouts move {} and {} mm when the cells are halved (no-slip: {} mm), "
          "{} and {} % beyond the paper's model; over 5 mm, the three beds' layer rows within "
          "{} mm of each other",
          *((lead(f"{v}-fine/0mm-0", f"{v}/0mm-0", None), "+.1f", mm) for v in (C, M, N)),
          (over(f"{C}/0mm-0", f"{P}/0mm-0"), "+.1f", 100),
          (over(f"{M}/0mm-0", f"{P}/0mm-0"), "+.1f", 100),
          (lambda d: max(spread(a)(d) for a in SLOPES), ".1f", mm), page="docs/verification.md"),
    *each("ratios Coulomb {}, {}, ≥ {} and material {}, {}, ≤ {} at 0, 10, 19° ({}, {}, ≤ {} "
          "with the rigid fronts 1 mm above the bed",
          *((ratio(f"{v}/5mm-{a}", f"{v}-tension/0mm-{a}"), ".3f", 1)
            for v in (C, M) for a in SLOPES),
          *((thick(f"{M}/5mm-{a}", f"{M}-tension/0mm-{a}"), ".3f", 1) for a in SLOPES),
          page="docs/verification.md"),
    *each("trend on both meshes (finer: {}, {}, ≤ {});",
          *((ratio(f"{M}-fine/5mm-{a}", f"{M}-fine-tension/0mm-{a}"), ".3f", 1) for a in SLOPES),
          page="docs/verification.md"),
    *each("= 0.01: differs by {}–{} % |",
          (over(f"{M}/0mm-0", f"{P}/0mm-0"), ".0f", 100),
          (over(f"{C}/0mm-0", f"{P}/0mm-0"), ".0f", 100), page="docs/verification.md"),
    *each("The layer rows over the three beds agree within {} %",
          (lambda d: max(spread(a)(d) / row(M, f"5mm-{a}", "runout_m")(d) for a in SLOPES),
           ".1f", 100)),
]
