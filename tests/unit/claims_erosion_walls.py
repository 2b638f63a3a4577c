"""The erosion page's numbers from the side-walls study's rows carried to rest, the
thickness at 19 degrees and the level gain's checks (benchmarks/erosion_slopes.py,
``benchmarks/results/erosion_slopes_walls``), as claims for tests/unit/test_docs_numbers.py:
(page, text with ``{}`` where the number stands, results file, function of the data,
format, scale)."""

from __future__ import annotations

import json
import re
from collections.abc import Callable
from pathlib import Path
from typing import Any

STUDY = "erosion_slopes_walls/erosion_slopes.json"
DATA = json.loads((Path(__file__).resolve().parents[2] / "benchmarks" / "results"
                   / STUDY).read_text(encoding="utf-8"))
BEADS = "glass-beads-no-slip-small-eta-walls"
DP = "drucker-prager-no-slip-small-eta-walls"
Number = tuple[Callable[[Any], float], str, float]


def row(variant: str, name: str, key: str) -> Callable[[Any], float]:
    """A row's figure, as it stands now (carried rows at their last state)."""
    return lambda d: d[f"{variant}/rectangle-{name}"][key]


def ratio(layer: str, rigid: str) -> Callable[[Any], float]:
    """A row's runout over another's ("variant/name" each)."""
    return lambda d: (d[f"{layer.split('/')[0]}/rectangle-{layer.split('/')[1]}"]["runout_m"]
                      / d[f"{rigid.split('/')[0]}/rectangle-{rigid.split('/')[1]}"]["runout_m"])


def bed_length(layer: str) -> Callable[[Any], float]:
    """The length of a layer row's layer (m), from its overrides."""
    def length(d: Any) -> float:
        found = d[f"{layer.split('/')[0]}/rectangle-{layer.split('/')[1]}"]["overrides"]
        return next(float(o.split("=")[1]) for o in found
                    if o.startswith("geometry.bed_length="))
    return length


def front(name: str, t: str) -> Callable[[Any], float]:
    """A row's front at ``t`` ("variant/name")."""
    variant, case = name.split("/")
    return lambda d: d[f"{variant}/rectangle-{case}"]["front_history"][t]


def lead(layer: str, rigid: str, t: str | None) -> Callable[[Any], float]:
    """A row's front minus another's at ``t`` (at rest: None), in m."""
    def gain(d: Any) -> float:
        a, b = (d[f"{v.split('/')[0]}/rectangle-{v.split('/')[1]}"] for v in (layer, rigid))
        if t is None:
            return a["runout_m"] - b["runout_m"]
        return a["front_history"][t] - b["front_history"][t]
    return gain


def shown(number: Number) -> str:
    fn, spec, scale = number
    text = format(fn(DATA) * scale, spec)
    return re.sub(r"e([+-])0*(\d)", lambda m: f"e{'-' if m[1] == '-' else ''}{m[2]}", text)


def each(text: str, *numbers: Number, page: str = "docs/erosion.md") -> list[tuple]:
    """One claim per number of ``text`` (its ``{}`` in order): that number a slot, the
    others written as the record gives them."""
    parts = text.split("{}")
    assert len(parts) == len(numbers) + 1, text
    claims = []
    for i, number in enumerate(numbers):
        filled = [shown(n) if j != i else "{}" for j, n in enumerate(numbers)]
        line = parts[0] + "".join(f + p for f, p in zip(filled, parts[1:], strict=True))
        claims.append((page, line, STUDY, *number))
    return claims


B, D = BEADS, DP


def third_step_rigid(d: Any) -> float:
    """The no-slip rigid row's step from the finer mesh to the third (its front at 0.5 s,
    where the finer mesh's level front is within a millimetre of its runout), in m."""
    return (front(f"{B}-finer-tension/0mm-0", "0.5")(d)
            - row(f"{B}-fine-tension", "0mm-0", "runout_m")(d))
CLOCK4 = ("0.1", "0.2", "0.3", "0.5")
GAINS = [("5mm-0", "0mm-0"), ("10mm-0", "0mm-0"), ("5mm-10", "0mm-10")]   # level and 10 deg
mm = 1e3
CLAIMS: list[tuple] = [
    # every row carried on
    *each("| 16° | {} m, at rest at {} s | {} m, at rest at {} s | {} |",
          (row(B, "0mm-16", "runout_m"), ".4f", 1), (row(B, "0mm-16", "stop_time_s"), ".3f", 1),
          (row(B, "5mm-16", "runout_m"), ".4f", 1), (row(B, "5mm-16", "stop_time_s"), ".3f", 1),
          (ratio(f"{B}/5mm-16", f"{B}/0mm-16"), ".3f", 1)),
    *each("| 19° | {} m, at rest at {} s | {} m, at rest at {} s | {} |",
          (row(B, "0mm-19", "runout_m"), ".4f", 1), (row(B, "0mm-19", "stop_time_s"), ".3f", 1),
          (row(B, "5mm-19", "runout_m"), ".4f", 1), (row(B, "5mm-19", "stop_time_s"), ".3f", 1),
          (ratio(f"{B}/5mm-19", f"{B}/0mm-19"), ".3f", 1)),
    *each("| 22° | front {} m at {} s, moving at {} mm/s | front {} m at {} s, moving at {} mm/s"
          " | ≈ {} |",
          (row(B, "0mm-22", "runout_m"), ".4f", 1), (row(B, "0mm-22", "t_final"), ".0f", 1),
          (row(B, "0mm-22", "front_speed_end_m_s"), ".0f", mm),
          (row(B, "5mm-22", "runout_m"), ".4f", 1), (row(B, "5mm-22", "t_final"), ".0f", 1),
          (row(B, "5mm-22", "front_speed_end_m_s"), ".0f", mm),
          (ratio(f"{B}/5mm-22", f"{B}/0mm-22"), ".2f", 1)),
    *each("the rigid fronts crept on by {} and {} mm.",
          (lambda d: abs(d[f"{B}/rectangle-0mm-16"]["runout_m"]
                         - d[f"{B}/rectangle-0mm-16"]["front_history"]["3"]), ".1f", mm),
          (lambda d: d[f"{B}/rectangle-0mm-19"]["runout_m"]
           - d[f"{B}/rectangle-0mm-19"]["front_history"]["3"], ".0f", mm)),
    *each("from +{} mm at 3 s to +{} mm at 6 s,",
          (lead(f"{B}/5mm-22", f"{B}/0mm-22", "3"), ".0f", mm),
          (lead(f"{B}/5mm-22", f"{B}/0mm-22", "6"), ".0f", mm)),
    *each("({} % of the displaced layer ahead of the column's, {} cm² displaced)",
          (row(B, "5mm-22", "displaced_ahead_of_column_share"), ".0f", 100),
          (row(B, "5mm-22", "layer_displaced_area_m2"), ".1f", 1e4)),
    *each("(≈ 1.28 at 3 s, ≈ {} at 6 s)", (ratio(f"{B}/5mm-22", f"{B}/0mm-22"), ".2f", 1)),
    # the thickness at 19 degrees
    *each("**Over 10 mm: {} m, at rest at {} s, ratio {}** (5 mm: {})",
          (row(B, "10mm-19", "runout_m"), ".4f", 1), (row(B, "10mm-19", "stop_time_s"), ".3f", 1),
          (ratio(f"{B}/10mm-19", f"{B}/0mm-19"), ".3f", 1),
          (ratio(f"{B}/5mm-19", f"{B}/0mm-19"), ".3f", 1)),
    *each("Its lead: +{}, +{}, {}, +{}, +{} and +{} mm at 0.1, 0.3, 0.75, 1, 1.5 and 2 s",
          *((lead(f"{B}/10mm-19", f"{B}/0mm-19", t), ".0f", mm)
            for t in ("0.1", "0.3", "0.75", "1", "1.5", "2"))),
    *each("(5 mm: +{}, +{}, {}, +{}, +{}, +{}).",
          *((lead(f"{B}/5mm-19", f"{B}/0mm-19", t), ".0f", mm)
            for t in ("0.1", "0.3", "0.75", "1", "1.5", "2"))),
    *each("**Over 2.5 mm: front {} m at {} s, still creeping ({} mm/s): ratio ≥ {}**",
          (row(B, "2.5mm-19", "runout_m"), ".4f", 1), (row(B, "2.5mm-19", "t_final"), ".0f", 1),
          (row(B, "2.5mm-19", "front_speed_end_m_s"), ".0f", mm),
          (ratio(f"{B}/2.5mm-19", f"{B}/0mm-19"), ".3f", 1)),
    *each("Its lead: +{}, +{}, +{}, +{}, +{} and +{} mm at 0.1, 0.3, 0.75, 1, 1.5 and"
          " 2 s: the same",
          *((lead(f"{B}/2.5mm-19", f"{B}/0mm-19", t), ".0f", mm)
            for t in ("0.1", "0.3", "0.75", "1", "1.5", "2"))),
    *each("≥ {}, {} and {}, steps of +{} and +{}",
          (ratio(f"{B}/2.5mm-19", f"{B}/0mm-19"), ".3f", 1),
          (ratio(f"{B}/5mm-19", f"{B}/0mm-19"), ".3f", 1),
          (ratio(f"{B}/10mm-19", f"{B}/0mm-19"), ".3f", 1),
          (lambda d: ratio(f"{B}/5mm-19", f"{B}/0mm-19")(d)
           - ratio(f"{B}/2.5mm-19", f"{B}/0mm-19")(d), ".3f", 1),
          (lambda d: ratio(f"{B}/10mm-19", f"{B}/0mm-19")(d)
           - ratio(f"{B}/5mm-19", f"{B}/0mm-19")(d), ".3f", 1)),
    *each("2.5 mm: ≥ {} at 19° (creeping at 3 s)",
          (ratio(f"{B}/2.5mm-19", f"{B}/0mm-19"), ".2f", 1), page="docs/verification.md"),
    *each("(2.5 to 5 to 10 mm: +{}, +{})",
          (lambda d: ratio(f"{B}/5mm-19", f"{B}/0mm-19")(d)
           - ratio(f"{B}/2.5mm-19", f"{B}/0mm-19")(d), ".3f", 1),
          (lambda d: ratio(f"{B}/10mm-19", f"{B}/0mm-19")(d)
           - ratio(f"{B}/5mm-19", f"{B}/0mm-19")(d), ".3f", 1), page="docs/verification.md"),
    # what the level gain is
    *each("| Drucker–Prager, rigid, 14 cm | {} m, at rest at {} s | - |",
          (row(D, "0mm-0", "runout_m"), ".4f", 1), (row(D, "0mm-0", "stop_time_s"), ".3f", 1)),
    *each("| Drucker–Prager over 5 mm | {} m, at rest at {} s | {} (+{} mm) |",
          (row(D, "5mm-0", "runout_m"), ".4f", 1), (row(D, "5mm-0", "stop_time_s"), ".3f", 1),
          (ratio(f"{D}/5mm-0", f"{D}/0mm-0"), ".3f", 1),
          (lead(f"{D}/5mm-0", f"{D}/0mm-0", None), ".1f", mm)),
    *each("| Drucker–Prager, rigid, 14.5 cm | {} m | +{} mm |",
          (row(f"{D}-taller", "0mm-0", "runout_m"), ".4f", 1),
          (lead(f"{D}-taller/0mm-0", f"{D}/0mm-0", None), ".1f", mm)),
    *each("| beads, rigid, 14 cm | {} m | - |", (row(B, "0mm-0", "runout_m"), ".4f", 1)),
    *each("| beads over 5 mm | {} m | {} (+{} mm) |",
          (row(B, "5mm-0", "runout_m"), ".4f", 1), (ratio(f"{B}/5mm-0", f"{B}/0mm-0"), ".3f", 1),
          (lead(f"{B}/5mm-0", f"{B}/0mm-0", None), ".1f", mm)),
    *each("| beads over 10 mm | {} m, at rest at {} s | {} (+{} mm) |",
          (row(B, "10mm-0", "runout_m"), ".4f", 1), (row(B, "10mm-0", "stop_time_s"), ".3f", 1),
          (ratio(f"{B}/10mm-0", f"{B}/0mm-0"), ".3f", 1),
          (lead(f"{B}/10mm-0", f"{B}/0mm-0", None), ".1f", mm)),
    *each("| beads, rigid, 14.5 cm | {} m | +{} mm |",
          (row(f"{B}-taller", "0mm-0", "runout_m"), ".4f", 1),
          (lead(f"{B}-taller/0mm-0", f"{B}/0mm-0", None), ".1f", mm)),
    *each("| beads, rigid, 15 cm | {} m | +{} mm |",
          (row(f"{B}-15cm", "0mm-0", "runout_m"), ".4f", 1),
          (lead(f"{B}-15cm/0mm-0", f"{B}/0mm-0", None), ".1f", mm)),
    *each("gains +{} mm over 5 mm (predicted 0.96–1.01",
          (lead(f"{D}/5mm-0", f"{D}/0mm-0", None), ".1f", mm)),
    *each("A rigid column 5 mm taller runs +{} mm further with Drucker–Prager ({} of its layer"
          " row's gain) and +{} mm with the beads ({}).",
          (lead(f"{D}-taller/0mm-0", f"{D}/0mm-0", None), ".1f", mm),
          (lambda d: lead(f"{D}-taller/0mm-0", f"{D}/0mm-0", None)(d)
           / lead(f"{D}/5mm-0", f"{D}/0mm-0", None)(d), ".2f", 1),
          (lead(f"{B}-taller/0mm-0", f"{B}/0mm-0", None), ".1f", mm),
          (lambda d: lead(f"{B}-taller/0mm-0", f"{B}/0mm-0", None)(d)
           / lead(f"{B}/5mm-0", f"{B}/0mm-0", None)(d), ".2f", 1)),
    *each("the layer rows run {} (Drucker–Prager), {} and {} (the beads over 5 and 10 mm)",
          (ratio(f"{D}/5mm-0", f"{D}-taller/0mm-0"), ".3f", 1),
          (ratio(f"{B}/5mm-0", f"{B}-taller/0mm-0"), ".3f", 1),
          (ratio(f"{B}/10mm-0", f"{B}-15cm/0mm-0"), ".3f", 1)),
    *each("(predicted 1.05–1.13 over 10 mm: refuted, {})",
          (ratio(f"{B}/10mm-0", f"{B}/0mm-0"), ".3f", 1)),
    *each("+{} mm for 5 mm more column, +{} mm for 10 mm; at 10° +{} mm for 5 mm (the layer row"
          " over 5 mm against it: {}).",
          (lead(f"{B}-taller/0mm-0", f"{B}/0mm-0", None), ".1f", mm),
          (lead(f"{B}-15cm/0mm-0", f"{B}/0mm-0", None), ".1f", mm),
          (lead(f"{B}-taller/0mm-10", f"{B}/0mm-10", None), ".1f", mm),
          (ratio(f"{B}/5mm-10", f"{B}-taller/0mm-10"), ".3f", 1)),
    *each("The fronts at 0.3 s are {}, {} and {} m for 14, 14.5 and 15 cm.",
          *((lambda d, v=v: d[f"{v}/rectangle-0mm-0"]["front_history"]["0.3"], ".3f", 1)
            for v in (B, f"{B}-taller", f"{B}-15cm"))),
    # the verification page's summary rows
    *each("5 mm: 1.05 at 0°, {} at 10°, {} at 16°, {} at 19°, every row at rest; ≈ {} at 22°",
          *((ratio(f"{B}/5mm-{a}", f"{B}/0mm-{a}"), ".2f", 1) for a in (10, 16, 19, 22)),
          page="docs/verification.md"),
    *each("10 mm: {} at 0°, {} at 19° (at rest)",
          *((ratio(f"{B}/10mm-{a}", f"{B}/0mm-{a}"), ".2f", 1) for a in (0, 19)),
          page="docs/verification.md"),
    *each("| - | Drucker–Prager {}; against the taller twins {} (Drucker–Prager), {} and {} (beads"
          " over 5 and 10 mm); the rigid runout +{} / +{} mm for 5 / 10 mm more column;",
          (ratio(f"{D}/5mm-0", f"{D}/0mm-0"), ".3f", 1),
          (ratio(f"{D}/5mm-0", f"{D}-taller/0mm-0"), ".3f", 1),
          (ratio(f"{B}/5mm-0", f"{B}-taller/0mm-0"), ".3f", 1),
          (ratio(f"{B}/10mm-0", f"{B}-15cm/0mm-0"), ".3f", 1),
          (lead(f"{B}-taller/0mm-0", f"{B}/0mm-0", None), ".1f", mm),
          (lead(f"{B}-15cm/0mm-0", f"{B}/0mm-0", None), ".1f", mm), page="docs/verification.md"),
    *each("It comes to rest {} s before its rigid twin.",
          (lambda d: d[f"{B}/rectangle-0mm-19"]["stop_time_s"]
           - d[f"{B}/rectangle-10mm-19"]["stop_time_s"], ".0f", 1)),
    *each("The candidate gains on the level bed (+{} mm over 5 mm, ratio {}) and at 10° (+{} mm,"
          " {}), where",
          (lead(f"{B}/5mm-0", f"{B}/0mm-0", None), ".0f", mm),
          (ratio(f"{B}/5mm-0", f"{B}/0mm-0"), ".3f", 1),
          (lead(f"{B}/5mm-10", f"{B}/0mm-10", None), ".0f", mm),
          (ratio(f"{B}/5mm-10", f"{B}/0mm-10"), ".3f", 1)),
    *each("(mesh.size 0.014 m, {} triangles in the 14 cm run)",
          (row(B, "0mm-0", "n_triangles"), ".0f", 1)),
    *each("So the level and 10° gains, +{} to +{} mm, are",
          (lead(f"{B}/10mm-0", f"{B}/0mm-0", None), ".0f", mm),
          (lead(f"{B}/5mm-10", f"{B}/0mm-10", None), ".0f", mm)),
    # the level rows on a mesh twice as fine
    *each("The 14 cm rigid column runs {} m on the finer mesh ({} triangles), {} mm ({} %) beyond"
          " the study's {} m",
          (row(f"{B}-fine", "0mm-0", "runout_m"), ".4f", 1),
          (row(f"{B}-fine", "0mm-0", "n_triangles"), ",d", 1),
          (lead(f"{B}-fine/0mm-0", f"{B}/0mm-0", None), ".1f", mm),
          (lambda d: ratio(f"{B}-fine/0mm-0", f"{B}/0mm-0")(d) - 1, ".1f", 100),
          (row(B, "0mm-0", "runout_m"), ".4f", 1)),
    *each("5 mm more column adds +{} mm there against +{} mm on the study's mesh",
          (lead(f"{B}-taller-fine/0mm-0", f"{B}-fine/0mm-0", None), ".1f", mm),
          (lead(f"{B}-taller/0mm-0", f"{B}/0mm-0", None), ".1f", mm)),
    *each("| beads, rigid, 14 cm | {} m, at rest at {} s | - |",
          (row(f"{B}-fine", "0mm-0", "runout_m"), ".4f", 1),
          (row(f"{B}-fine", "0mm-0", "stop_time_s"), ".3f", 1)),
    *each("| beads over 5 mm | {} m, at rest at {} s | {} (+{} mm) |",
          (row(f"{B}-fine", "5mm-0", "runout_m"), ".4f", 1),
          (row(f"{B}-fine", "5mm-0", "stop_time_s"), ".3f", 1),
          (ratio(f"{B}-fine/5mm-0", f"{B}-fine/0mm-0"), ".3f", 1),
          (lead(f"{B}-fine/5mm-0", f"{B}-fine/0mm-0", None), ".1f", mm)),
    *each("| beads, rigid, 14.5 cm | {} m | +{} mm |\n\n- **The study's mesh",
          (row(f"{B}-taller-fine", "0mm-0", "runout_m"), ".4f", 1),
          (lead(f"{B}-taller-fine/0mm-0", f"{B}-fine/0mm-0", None), ".1f", mm)),
    *each("The row over 5 mm runs {} m, as far as its rigid twin: ratio {} (predicted",
          (row(f"{B}-fine", "5mm-0", "runout_m"), ".4f", 1),
          (ratio(f"{B}-fine/5mm-0", f"{B}-fine/0mm-0"), ".3f", 1)),
    *each("(+{}, +{}, {} and {} mm at 0.1, 0.2, 0.3 and 0.5 s; the study's mesh:"
          " +{}, +{}, +{}, +{})",
          *((lead(f"{B}-fine/5mm-0", f"{B}-fine/0mm-0", t), ".0f", mm) for t in CLOCK4),
          *((lead(f"{B}/5mm-0", f"{B}/0mm-0", t), ".0f", mm) for t in CLOCK4)),
    *each("The fronts stay within {} mm of each other throughout",
          (lambda d: max(abs(lead(f"{B}-fine/5mm-0", f"{B}-fine/0mm-0", t)(d))
                         for t in ("0.1", "0.2", "0.3", "0.5", "0.75", "1")), ".0f", mm)),
    *each("The taller rigid column still runs +{} mm further",
          (lead(f"{B}-taller-fine/0mm-0", f"{B}-fine/0mm-0", None), ".1f", mm)),
    *each("coarse response to the height is scatter of about {} mm.",
          (lambda d: lead(f"{B}-taller-fine/0mm-0", f"{B}-fine/0mm-0", None)(d)
           - lead(f"{B}-taller/0mm-0", f"{B}/0mm-0", None)(d), ".0f", mm)),
    *each("finer mesh: the 14 cm rigid column +{} %, the row over 5 mm {} of it",
          (lambda d: ratio(f"{B}-fine/0mm-0", f"{B}/0mm-0")(d) - 1, ".1f", 100),
          (ratio(f"{B}-fine/5mm-0", f"{B}-fine/0mm-0"), ".3f", 1), page="docs/verification.md"),
    *each("a level or 10° gain of {}–{} %",
          (lambda d: min(ratio(f"{B}/{h}", f"{B}/{r}")(d) - 1 for h, r in GAINS), ".1f", 100),
          (lambda d: max(ratio(f"{B}/{h}", f"{B}/{r}")(d) - 1 for h, r in GAINS), ".1f", 100)),
    # the slopes on the finer mesh
    *each("| 10° | {} m, at rest at {} s | {} m, at rest at {} s | {} | {} |",
          (row(f"{B}-fine", "0mm-10", "runout_m"), ".4f", 1),
          (row(f"{B}-fine", "0mm-10", "stop_time_s"), ".3f", 1),
          (row(f"{B}-fine", "5mm-10", "runout_m"), ".4f", 1),
          (row(f"{B}-fine", "5mm-10", "stop_time_s"), ".3f", 1),
          (ratio(f"{B}-fine/5mm-10", f"{B}-fine/0mm-10"), ".3f", 1),
          (ratio(f"{B}/5mm-10", f"{B}/0mm-10"), ".3f", 1)),
    *each("Ratio {} (predicted 0.98–1.03): no change",
          (ratio(f"{B}-fine/5mm-10", f"{B}-fine/0mm-10"), ".3f", 1)),
    *each("The rigid twin runs {} % further than on the study's mesh",
          (lambda d: ratio(f"{B}-fine/0mm-10", f"{B}/0mm-10")(d) - 1, ".1f", 100)),
    *each("at rest {} s later.",
          (lambda d: row(f"{B}-fine", "0mm-10", "stop_time_s")(d)
           - row(B, "0mm-10", "stop_time_s")(d), ".3f", 1)),
    *each("It leads by +{} and +{} mm at 0.1 and 0.2 s, falls behind by {} and {} mm at 0.3"
          " and 0.5 s and ends +{} mm (the study's mesh: +{}, {}, {}, +{} mm, then +{} mm at"
          " rest)",
          *((lead(f"{B}-fine/5mm-10", f"{B}-fine/0mm-10", t), ".0f", mm) for t in CLOCK4[:2]),
          *((lead(f"{B}-fine/0mm-10", f"{B}-fine/5mm-10", t), ".0f", mm) for t in CLOCK4[2:]),
          (lead(f"{B}-fine/5mm-10", f"{B}-fine/0mm-10", None), ".1f", mm),
          *((lead(f"{B}/5mm-10", f"{B}/0mm-10", t), ".0f", mm) for t in CLOCK4),
          (lead(f"{B}/5mm-10", f"{B}/0mm-10", None), ".0f", mm)),
    *each("The layer is {} m long at 10° and {} m at 19° there, the study's\nmesh's {} m",
          (bed_length(f"{B}-fine/5mm-10"), "g", 1), (bed_length(f"{B}-fine/5mm-19"), ".2f", 1),
          (bed_length(f"{B}/5mm-10"), "g", 1)),
    *each("at 10° over 5 mm {} (the study's mesh {}), the rigid runout +{} %",
          (ratio(f"{B}-fine/5mm-10", f"{B}-fine/0mm-10"), ".3f", 1),
          (ratio(f"{B}/5mm-10", f"{B}/0mm-10"), ".3f", 1),
          (lambda d: ratio(f"{B}-fine/0mm-10", f"{B}/0mm-10")(d) - 1, ".1f", 100),
          page="docs/verification.md"),
    # the 19-degree row on the finer mesh, and the twins' front treatment
    *each("| 19° | failed at {} s | {} m, at rest at {} s | - | {} |",
          (row(f"{B}-fine", "0mm-19", "t_final"), ".3f", 1),
          (row(f"{B}-fine", "5mm-19", "runout_m"), ".4f", 1),
          (row(f"{B}-fine", "5mm-19", "stop_time_s"), ".3f", 1),
          (ratio(f"{B}/5mm-19", f"{B}/0mm-19"), ".3f", 1)),
    *each("the runouts\n  move by {}, {} and {} mm at 0, 10 and 19° when the cells are halved;"
          " the rigid\n  rows by +{} and +{} mm at 0 and 10°.",
          *((lead(f"{B}-fine/5mm-{a}", f"{B}/5mm-{a}", None), "+.1f", mm) for a in (0, 10, 19)),
          *((lead(f"{B}-fine/0mm-{a}", f"{B}/0mm-{a}", None), ".1f", mm) for a in (0, 10))),
    *each("({} and {} m at 0.3 and 0.5 s, against {} and {} m; the study's mesh's rigid\n"
          "  twin: {} and {} m)",
          *((front(f"{B}-fine/0mm-19", t), ".3f", 1) for t in ("0.3", "0.5")),
          *((front(f"{B}-fine/5mm-19", t), ".3f", 1) for t in ("0.3", "0.5")),
          *((front(f"{B}/0mm-19", t), ".3f", 1) for t in ("0.3", "0.5"))),
    *each("{} remeshes in {} steps", (row(f"{B}-fine", "0mm-19", "remeshes"), ",d", 1),
          (row(f"{B}-fine", "0mm-19", "steps"), ",d", 1)),
    *each("The 19° rigid twin failed at {} s.", (row(f"{B}-fine", "0mm-19", "t_final"), ".3f", 1)),
    *each("The tension shortens the rigid rows by {} to\n  {} mm",
          (lambda d: min(-lead(f"{B}-tension/0mm-{a}", f"{B}/0mm-{a}", None)(d)
                         for a in (0, 10, 16)), ".0f", mm),
          (lambda d: max(-lead(f"{B}-tension/0mm-{a}", f"{B}/0mm-{a}", None)(d)
                         for a in (0, 10, 16)), ".0f", mm)),
    *each("| level, study's mesh | {} m | {} m | {} mm |",
          (row(B, "0mm-0", "runout_m"), ".4f", 1), (row(f"{B}-tension", "0mm-0", "runout_m"),
                                                   ".4f", 1),
          (lead(f"{B}-tension/0mm-0", f"{B}/0mm-0", None), ".1f", mm)),
    *each("| 10°, study's mesh | {} m | {} m | {} mm |",
          (row(B, "0mm-10", "runout_m"), ".4f", 1),
          (row(f"{B}-tension", "0mm-10", "runout_m"), ".4f", 1),
          (lead(f"{B}-tension/0mm-10", f"{B}/0mm-10", None), ".1f", mm)),
    *each("| 16°, study's mesh | {} m | {} m | {} mm |",
          (row(B, "0mm-16", "runout_m"), ".4f", 1),
          (row(f"{B}-tension", "0mm-16", "runout_m"), ".4f", 1),
          (lead(f"{B}-tension/0mm-16", f"{B}/0mm-16", None), ".1f", mm)),
    *each("| level, finer mesh | {} m | {} m | {} mm |",
          (row(f"{B}-fine", "0mm-0", "runout_m"), ".4f", 1),
          (row(f"{B}-fine-tension", "0mm-0", "runout_m"), ".4f", 1),
          (lead(f"{B}-fine-tension/0mm-0", f"{B}-fine/0mm-0", None), ".1f", mm)),
    *each("| 10°, finer mesh | {} m | failed at {} s | - |",
          (row(f"{B}-fine", "0mm-10", "runout_m"), ".4f", 1),
          (row(f"{B}-fine-tension", "0mm-10", "t_final"), ".3f", 1)),
    *each("| 0° | {} ({}) | {} ({}) |",
          (ratio(f"{B}/5mm-0", f"{B}-tension/0mm-0"), ".3f", 1),
          (ratio(f"{B}/5mm-0", f"{B}/0mm-0"), ".3f", 1),
          (ratio(f"{B}-fine/5mm-0", f"{B}-fine-tension/0mm-0"), ".3f", 1),
          (ratio(f"{B}-fine/5mm-0", f"{B}-fine/0mm-0"), ".3f", 1)),
    *each("| 10° | {} ({}) | - ({}) |",
          (ratio(f"{B}/5mm-10", f"{B}-tension/0mm-10"), ".3f", 1),
          (ratio(f"{B}/5mm-10", f"{B}/0mm-10"), ".3f", 1),
          (ratio(f"{B}-fine/5mm-10", f"{B}-fine/0mm-10"), ".3f", 1)),
    *each("| 16° | {} ({}) | - |",
          (ratio(f"{B}/5mm-16", f"{B}-tension/0mm-16"), ".3f", 1),
          (ratio(f"{B}/5mm-16", f"{B}/0mm-16"), ".3f", 1)),
    *each("the rigid runout +{} mm ({} to {} m), the layer row +{} mm.",
          (lead(f"{B}-fine-tension/0mm-0", f"{B}-tension/0mm-0", None), ".1f", mm),
          (row(f"{B}-tension", "0mm-0", "runout_m"), ".4f", 1),
          (row(f"{B}-fine-tension", "0mm-0", "runout_m"), ".4f", 1),
          (lead(f"{B}-fine/5mm-0", f"{B}/5mm-0", None), ".1f", mm)),
    *each("with the tension (10° at\n  {} s) or without it (19° at {} s)",
          (row(f"{B}-fine-tension", "0mm-10", "t_final"), ".3f", 1),
          (row(f"{B}-fine", "0mm-19", "t_final"), ".3f", 1)),
    *each("the layer row at 19° moves\n  by {} mm when the cells are halved ({} m)",
          (lead(f"{B}-fine/5mm-19", f"{B}/5mm-19", None), ".1f", mm),
          (row(f"{B}-fine", "5mm-19", "runout_m"), ".4f", 1)),
    *each("at 19° the layer row {} m ({} mm on the study's mesh), its rigid twins failed ({} s;"
          " with the tension, 10°: {} s, and 19° on the study's mesh: {} s); against rigid"
          " twins with the layer rows' tension {}"
          " and {} on the level bed (study's and finer mesh), {} at 10°, {} at 16°",
          (row(f"{B}-fine", "5mm-19", "runout_m"), ".4f", 1),
          (lead(f"{B}-fine/5mm-19", f"{B}/5mm-19", None), "+.1f", mm),
          (row(f"{B}-fine", "0mm-19", "t_final"), ".3f", 1),
          (row(f"{B}-fine-tension", "0mm-10", "t_final"), ".3f", 1),
          (row(f"{B}-tension", "0mm-19", "t_final"), ".3f", 1),
          (ratio(f"{B}/5mm-0", f"{B}-tension/0mm-0"), ".3f", 1),
          (ratio(f"{B}-fine/5mm-0", f"{B}-fine-tension/0mm-0"), ".3f", 1),
          (ratio(f"{B}/5mm-10", f"{B}-tension/0mm-10"), ".3f", 1),
          (ratio(f"{B}/5mm-16", f"{B}-tension/0mm-16"), ".3f", 1),
          page="docs/verification.md"),
    *each("| 19°, study's mesh | {} m | failed at {} s | - |",
          (row(B, "0mm-19", "runout_m"), ".4f", 1),
          (row(f"{B}-tension", "0mm-19", "t_final"), ".3f", 1)),
    *each("and at 19° with\n  the tension on the study's mesh too ({} s).",
          (row(f"{B}-tension", "0mm-19", "t_final"), ".3f", 1)),
    *each("rigid {} m, over 5 mm {} m, the\n  fronts' ratio {}.",
          (front(f"{B}-finer-tension/0mm-0", "0.5"), ".4f", 1),
          (front(f"{B}-finer/5mm-0", "0.5"), ".4f", 1),
          (lambda d: front(f"{B}-finer/5mm-0", "0.5")(d)
           / front(f"{B}-finer-tension/0mm-0", "0.5")(d), ".3f", 1)),
    *each("Each halving of the cells adds +{} and then +{} mm to the rigid\n  row",
          (lead(f"{B}-fine-tension/0mm-0", f"{B}-tension/0mm-0", None), ".1f", mm),
          (third_step_rigid, ".1f", mm)),
    *each("The layer row moves by +{} and +{} mm.\n  With no slip",
          (lead(f"{B}-fine/5mm-0", f"{B}/5mm-0", None), ".1f", mm),
          (lambda d: front(f"{B}-finer/5mm-0", "0.5")(d)
           - row(f"{B}-fine", "5mm-0", "runout_m")(d), ".1f", mm)),
    *each("(on the finer one it failed\n  at {} s)",
          (row(f"{B}-fine-tension", "0mm-19", "t_final"), ".3f", 1)),
    *each("interrupted at {} and {} s and\n  carried",
          (row(f"{B}-finer-tension", "0mm-0", "t_final"), ".2f", 1),
          (row(f"{B}-finer", "5mm-0", "t_final"), ".2f", 1)),
    *each("rigid runout has no mesh limit (+{} and +{} mm at each halving of the cells",
          (lead(f"{B}-fine-tension/0mm-0", f"{B}-tension/0mm-0", None), ".1f", mm),
          (third_step_rigid, ".1f", mm),
          page="docs/verification.md"),
]
