"""The cost-growth table of ``three_d_fieldsplit_cost.py --table``: processor seconds per
solve by solver, state and size, the exponent a of k N^a (least squares in log-log over
the sizes, and the slope between the two largest sizes), the resident memory each solve
added, and the size N where a fieldsplit variant is as cheap as the cheaper direct solve,
on one process and on P ranks under the stated assumptions (``EFFICIENCY``,
``PER_RANK``)."""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np

from common.fits import power_fit

STATES = ("rest", "flowing", "front")
NAMES = {"umfpack": "UMFPACK", "pardiso": "PARDISO", "selfp-gamg-flexible": "selfp",
         "lsc-gamg-flexible": "LSC"}
DIRECT = ("umfpack", "pardiso")
FIELDSPLIT = ("selfp-gamg-flexible", "lsc-gamg-flexible")
RANKS = (1, 2, 16, 64, 256)
EFFICIENCY = 0.5     # the fieldsplit solve's parallel efficiency assumed on P > 1 ranks
PER_RANK = 10_000    # the fewest unknowns per rank at which that efficiency is assumed
# the published figure the assumption stays below: parallel unstructured multigrid on 3D
# elasticity up to 960 processors (Adams and Demmel, "Parallel multigrid solver for 3D
# unstructured finite element problems", ACM/IEEE SC99); GAMG is its author's later
# smoothed-aggregation multigrid in PETSc
CITED_EFFICIENCY = {"value": 0.6, "processors": 960,
                    "source": "Adams and Demmel, ACM/IEEE SC99"}


def records(folder: Path) -> dict[str, list[dict]]:
    """The records by state, sorted by the number of unknowns."""
    found: dict[str, list[dict]] = {state: [] for state in STATES}
    for path in folder.glob("cost_*_h*.json"):
        record = json.loads(path.read_text())
        found[record["state"]].append(record)
    return {s: sorted(r, key=lambda x: x["unknowns"]) for s, r in found.items()}


def crossover(direct: tuple[float, float], iterative: tuple[float, float],
              ranks: int = 1) -> float | None:
    """N where the fieldsplit time k_i N^a_i / (P e) equals the direct k_d N^a_d (the
    direct solve gathered on one rank: P does not divide it), and at least ``PER_RANK``
    unknowns a rank; None where the lines do not cross upward."""
    (kd, ad), (ki, ai) = direct, iterative
    if ad <= ai:
        return None
    speed_up = 1.0 if ranks == 1 else ranks * EFFICIENCY
    n = (ki / speed_up / kd) ** (1.0 / (ad - ai))
    return float(n if ranks == 1 else max(n, ranks * PER_RANK))


def slope(n: np.ndarray, y: np.ndarray) -> float:
    """The log-log slope between the two largest sizes."""
    return float(np.log(y[-1] / y[-2]) / np.log(n[-1] / n[-2]))


def report(folder: Path) -> tuple[str, dict]:
    """The Markdown tables and their data."""
    data: dict = {"efficiency": EFFICIENCY, "per_rank": PER_RANK,
                  "cited_efficiency": CITED_EFFICIENCY, "states": {}}
    found = {s: r for s, r in records(folder).items() if len(r) >= 2}
    sizes = sorted({r["unknowns"] for rows in found.values() for r in rows})
    head = " | ".join(f"{n:,}" for n in sizes)
    lines = ["Processor seconds per solve (FGMRes steps), the exponent a of the fit k N^a "
             "over the sizes and the slope between the two largest:", "",
             f"| state | solver | {head} | a (fit) | a (last two) |",
             "|---|---|" + "---|" * (len(sizes) + 2)]
    memory = ["", "Resident memory the direct solve's factor added, MB (first round), and the "
              "exponent fitted from the second size on:", "",
              f"| state | solver | {head} | a (fit) |",
              "|---|---|" + "---|" * (len(sizes) + 1)]
    for state, rows in found.items():
        n = np.array([r["unknowns"] for r in rows], dtype=float)
        fits = {}
        entry: dict = {"unknowns": [r["unknowns"] for r in rows],
                       "free_unknowns": [r["free_unknowns"] for r in rows],
                       "peak_rss_mb": [r["peak_rss_mb"] for r in rows], "solvers": {}}
        for solver, name in NAMES.items():
            counted = [r["counted"][solver] for r in rows]
            cpu = np.array([c["cpu_s"] for c in counted])
            added = np.array([r["rounds"][solver][0]["added_mb"] for r in rows])
            fits[solver] = power_fit(n, cpu)
            # the smallest size's few MB are the allocator's noise: fitted from 5,414 on
            mem_fit = power_fit(n[1:], np.maximum(added[1:], 1e-3))[1] if len(n) > 2 else None
            entry["solvers"][solver] = {
                "cpu_s": cpu.tolist(), "steps": [c["steps"] for c in counted],
                "converged": [c.get("converged", True) for c in counted],
                "k": fits[solver][0], "exponent": fits[solver][1],
                "exponent_last_two": slope(n, cpu), "added_mb": added.tolist(),
                "memory_exponent": mem_fit, "at_1e6_s": fits[solver][0] * 1e6 ** fits[solver][1],
                "memory_at_1e6_mb": (float(np.exp(np.polyval(np.polyfit(
                    np.log(n[1:]), np.log(np.maximum(added[1:], 1e-3)), 1), np.log(1e6))))
                    if len(n) > 2 and solver in DIRECT else None),
                "relative_difference": [c["relative_difference"] for c in counted]}
            cells = [f"{c['cpu_s']:.3g}" + (f" ({c['steps']})" if c["steps"] else "")
                     + ("" if c.get("converged", True) else " fails") for c in counted]
            lines.append(f"| {state} | {name} | " + " | ".join(cells)
                         + f" | {fits[solver][1]:.2f} | {slope(n, cpu):.2f} |")
            if solver in DIRECT:     # the fieldsplit's few MB vanish in the freed factor's
                memory.append(f"| {state} | {name} | " + " | ".join(f"{a:.0f}" for a in added)
                              + (f" | {mem_fit:.2f} |" if mem_fit is not None else " | - |"))
        cheaper = min(DIRECT, key=lambda s: fits[s][0] * n[-1] ** fits[s][1])
        entry["direct"] = cheaper
        entry["crossover"] = {solver: {str(p): crossover(fits[cheaper], fits[solver], p)
                                       for p in RANKS} for solver in FIELDSPLIT}
        data["states"][state] = entry
    cross = ["", "Unknowns N at which the fieldsplit solve is as cheap as the cheaper direct "
             f"solve, from the fits: on P ranks the fieldsplit time divided by P x "
             f"{EFFICIENCY}, at least {PER_RANK:,} unknowns a rank, the direct solve (gathered "
             "on one rank) not faster:", "",
             "| state | variant | direct | " + " | ".join(f"P = {p}" for p in RANKS) + " |",
             "|---|---|---|" + "---|" * len(RANKS)]
    for state, entry in data["states"].items():
        for solver in FIELDSPLIT:
            cells = [("never" if v is None else f"{v:.1e}")
                     for v in entry["crossover"][solver].values()]
            cross.append(f"| {state} | {NAMES[solver]} | {NAMES[entry['direct']]} | "
                         + " | ".join(cells) + " |")
    checks = check(folder, data)
    return "\n".join(lines + memory + cross + checks), data


def check(folder: Path, data: dict) -> list[str]:
    """The fits against the sizes measured with fewer solvers (check_*.json, not fitted):
    the measured time per solve over the fit's, recorded in ``data["checks"]``."""
    found = sorted((json.loads(p.read_text()) for p in folder.glob("check_*_h*.json")),
                   key=lambda r: (r["unknowns"], STATES.index(r["state"])))
    if not found:
        return []
    lines = ["", "The fits against a larger size measured apart (not fitted): processor "
             "seconds per solve (steps), measured / the fit's:", "",
             "| state | solver | unknowns | measured | fit | ratio |", "|---|---|---|---|---|---|"]
    data["checks"] = []
    for record in found:
        for solver, counted in record["counted"].items():
            fit = data["states"][record["state"]]["solvers"][solver]
            expected = fit["k"] * record["unknowns"] ** fit["exponent"]
            data["checks"].append({"state": record["state"], "solver": solver,
                                   "unknowns": record["unknowns"], "cpu_s": counted["cpu_s"],
                                   "steps": counted["steps"], "fit_s": expected,
                                   "converged": counted.get("converged", True),
                                   "relative_difference": counted["relative_difference"]})
            steps = f" ({counted['steps']})" if counted["steps"] else ""
            lines.append(f"| {record['state']} | {NAMES[solver]} | {record['unknowns']:,} | "
                         f"{counted['cpu_s']:.3g}{steps} | {expected:.3g} | "
                         f"{counted['cpu_s'] / expected:.2f} |")
    return lines
