"""The comparison of a convergence study's levels (`granflow converge`), read from their
run directories only: summary.json, diagnostics.csv and the free surfaces in profiles/.

Between consecutive levels: the change of stop time, runout, flow duration and, over an
erodible layer, of the displaced and mobilised layer, and the distance between the free
surfaces at each common output time; the observed order of each quantity from each
consecutive triple; the verdict on the finest two levels. For a tightened numerical
parameter (``PARAMETER_MODES`` of ``converge.py``) every level is also judged against the
tightest, and the loosest level that stays within the tolerances (with every tighter one)
is named: the value a scenario's default can take.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import numpy as np

from granflow.app.sweep import FINISHED, SweepRun
from granflow.diagnostics.front import flow_duration
from granflow.geometry.polylines import surface_distance
from granflow.io import profiles
from granflow.io.diagnostics import read_diagnostics
from granflow.io.run_dir import RunDir

DEFAULT_TOLERANCES = {"surface_mean": 1e-3, "surface_max": 3e-3, "stop_time_rel": 0.02,
                      "runout": 5e-3,             # the accuracy targets of the collapses,
                      "displaced_rel": 0.01, "mobilised_rel": 0.05}   # and of a layer's
OPTIONAL_TOLERANCES = {"runout_rel": 5e-3, "duration_rel": 0.01}   # asked for by name
TOLERANCE_MEANING = {
    "surface_mean": "m, mean free-surface distance at every common output time",
    "surface_max": "m, largest free-surface distance at every common output time",
    "stop_time_rel": "stop times, relative to the finer level's",
    "runout": "m, runouts",
    "runout_rel": "runouts, relative to the finer level's",
    "duration_rel": "flow durations (until less than 1 % of the domain flows), relative",
    "displaced_rel": "displaced layer material (erodible layer), relative",
    "mobilised_rel": "largest mobilised layer material (erodible layer), relative"}
RELATIVE = {"runout_rel": "runout_m", "duration_rel": "duration_s",
            "displaced_rel": "displaced", "mobilised_rel": "mobilised"}


@dataclass
class Level:
    """What the comparison needs from one level's run directory."""

    level: int
    run: str
    status: str | None
    message: str
    stop_time_s: float | None
    runout_m: float | None
    steps: int | None
    wall_time_s: float | None
    surfaces: dict[float, np.ndarray] = field(default_factory=dict, repr=False)
    duration_s: float | None = None
    displaced: float | None = None   # layer material displaced (m^2/m, or m^3 in r-z)
    mobilised: float | None = None   # largest layer material in motion at once

    @property
    def finished(self) -> bool:
        return self.status in FINISHED


def read_level(folder: Path, level: int) -> Level:
    """A level from its run directory: summary.json, diagnostics.csv and
    profiles/free_surface_t*.csv."""
    s = RunDir.summary(folder)
    duration = None
    try:
        diag = read_diagnostics(folder)
        if len(diag):
            duration = flow_duration(diag["t"].to_numpy(), diag["flowing_fraction"].to_numpy())
    except (OSError, ValueError, KeyError):
        pass
    surfaces = {}
    for found in profiles.list_profiles(folder, "free_surface"):
        if not found.final and found.t is not None:
            data = found.read()
            surfaces[found.t] = np.column_stack([data["x"], data["z"]]) if data else (
                np.empty((0, 2)))
    layer = {name: next((v for k, v in s.items() if k.startswith(prefix)), None)
             for name, prefix in (("displaced", "layer_displaced_"),
                                  ("mobilised", "layer_mobilised_"))}
    return Level(level, folder.name, s.get("status"), s.get("message", "") or "",
                 s.get("stop_time_s"), s.get("runout_m"), s.get("steps"), s.get("wall_time_s"),
                 surfaces, duration, **layer)


# ------------------------------------------------------------------ the comparison


def _diff(fine: float | None, coarse: float | None) -> float | None:
    return None if fine is None or coarse is None else fine - coarse


def difference(coarse: Level, fine: Level) -> dict[str, Any]:
    """Changes from one level to the next: stop time, runout, and the (mean, max) distance
    between the free surfaces at each output time both have."""
    times = sorted(set(coarse.surfaces) & set(fine.surfaces))
    return {"levels": [coarse.level, fine.level],
            "stop_time_s": _diff(fine.stop_time_s, coarse.stop_time_s),
            "runout_m": _diff(fine.runout_m, coarse.runout_m),
            "duration_s": _diff(fine.duration_s, coarse.duration_s),
            "displaced": _diff(fine.displaced, coarse.displaced),
            "mobilised": _diff(fine.mobilised, coarse.mobilised),
            "surfaces": {t: dict(zip(("mean_m", "max_m"), surface_distance(
                coarse.surfaces[t], fine.surfaces[t]), strict=True)) for t in times}}


def observed_order(first: float | None, second: float | None,
                   signed: bool = True) -> tuple[float, str]:
    """p = log2(|first| / |second|) of two successive differences, with a note when it
    cannot be fitted (NaN): a missing value, a zero difference, or (``signed``) a sign that
    alternates, i.e. not yet monotone convergence."""
    if first is None or second is None or not (math.isfinite(first) and math.isfinite(second)):
        return math.nan, "a value is missing"
    if first == 0 or second == 0:
        return math.nan, "a difference is 0"
    if signed and (first > 0) != (second > 0):
        return math.nan, "the sign alternates (not in the asymptotic range)"
    return math.log2(abs(first) / abs(second)), ""


def orders(differences: list[dict[str, Any]]) -> list[dict[str, Any]]:
    """Observed order of each quantity from each consecutive triple of levels."""
    out = []
    for a, b in zip(differences, differences[1:], strict=False):
        triple = [*a["levels"], b["levels"][1]]
        rows = [("stop_time_s", *observed_order(a["stop_time_s"], b["stop_time_s"])),
                ("runout_m", *observed_order(a["runout_m"], b["runout_m"]))]
        for t in sorted(set(a["surfaces"]) & set(b["surfaces"])):
            for stat in ("mean", "max"):
                rows.append((f"surface_{stat}_t{t:.3f}", *observed_order(
                    a["surfaces"][t][f"{stat}_m"], b["surfaces"][t][f"{stat}_m"], False)))
        out += [{"levels": triple, "quantity": q, "p": p, "note": note} for q, p, note in rows]
    return out


def verdict(coarse: Level, fine: Level, diff: dict[str, Any],
            tolerances: dict[str, float]) -> dict[str, Any]:
    """Whether the finest two levels agree within ``tolerances``: one check per criterion
    (``ok`` None when it does not apply, with the reason) and ``converged``."""
    checks = []

    def check(name: str, value: float | None, tol: float, ok: bool | None, note: str = ""):
        checks.append({"criterion": name, "value": value, "tolerance": tol, "ok": ok,
                       "note": note})

    for lv in (coarse, fine):
        if not lv.finished:
            check(f"level {lv.level} status", None, math.nan, False,
                  f"{lv.status or 'no summary'}: {lv.message}".rstrip(": "))
    tol = tolerances["stop_time_rel"]
    if coarse.stop_time_s is None and fine.stop_time_s is None:
        check("stop_time_rel", None, tol, None, "the mass came to rest at neither level")
    elif coarse.stop_time_s is None or fine.stop_time_s is None:
        check("stop_time_rel", None, tol, False, "the mass came to rest at one level only")
    else:
        rel = abs(diff["stop_time_s"]) / abs(fine.stop_time_s) if fine.stop_time_s else math.inf
        check("stop_time_rel", rel, tol, rel <= tol)
    if diff["runout_m"] is None:
        check("runout", None, tolerances["runout"], False, "a runout is missing")
    else:
        value = abs(diff["runout_m"])
        check("runout", value, tolerances["runout"], value <= tolerances["runout"])
    for name, key in RELATIVE.items():
        reference, change = getattr(fine, key), diff[key]
        if name not in tolerances or reference is None and getattr(coarse, key) is None:
            continue                                # (no layer, or a tolerance not asked)
        if change is None or not reference:
            check(name, None, tolerances[name], False, f"{key} is missing at one level")
            continue
        rel = abs(change) / abs(reference)
        check(name, rel, tolerances[name], rel <= tolerances[name])
    if not diff["surfaces"]:
        check("surface", None, math.nan, None, "no common output time: surfaces not compared")
    for t, d in diff["surfaces"].items():
        for stat in ("mean", "max"):
            value, tol = d[f"{stat}_m"], tolerances[f"surface_{stat}"]
            check(f"surface_{stat} at t = {t:.3f} s", value, tol, value <= tol)
    return {"levels": [coarse.level, fine.level], "tolerances": tolerances,
            "converged": all(c["ok"] is not False for c in checks), "checks": checks}


# ------------------------------------------------------------------ the report


@dataclass
class Report:
    """The study's outcome, as written to converge.csv / converge.json / converge.png."""

    source: str
    mode: str
    overrides: tuple[str, ...]
    levels: list[Level]
    varied: list[dict[str, Any]]
    differences: list[dict[str, Any]]
    orders: list[dict[str, Any]]
    verdict: dict[str, Any]
    against_reference: list[dict[str, Any]] = field(default_factory=list)

    @property
    def label(self) -> str:
        return Path(self.source).stem

    @property
    def converged(self) -> bool:
        return bool(self.verdict["converged"])

    @property
    def loosest(self) -> int | None:
        """The loosest level within the tolerances of the reference, with every tighter
        one (None: not judged against a reference, or none is)."""
        if not self.against_reference:
            return None
        best = None
        for judged in reversed(self.against_reference):
            if not judged["converged"]:
                break
            best = judged["levels"][0]
        return best


def compare_levels(source: str, mode: str, overrides: tuple[str, ...], tolerances: dict[str, float],
            out: Path, runs: list[SweepRun], against_reference: bool = False) -> Report:
    """Compare the levels from their run directories in ``out`` (no simulation state);
    with ``against_reference``, also each level with the last (tightest) one."""
    levels = [read_level(out / run.name, k) for k, run in enumerate(runs)]
    diffs = [difference(a, b) for a, b in zip(levels, levels[1:], strict=False)]
    judged = [verdict(lv, levels[-1], difference(lv, levels[-1]), tolerances)
              for lv in levels[:-1]] if against_reference else []
    return Report(source, mode, overrides, levels,
                  [{k: v for k, v in run.varied.items() if k != "level"} for run in runs],
                  diffs, orders(diffs), verdict(levels[-2], levels[-1], diffs[-1], tolerances),
                  judged)


def _worst(diff: dict[str, Any] | None, stat: str) -> float | None:
    values = [d[f"{stat}_m"] for d in diff["surfaces"].values()] if diff else []
    return max(values) if values else None


CSV_COLUMNS = ["level", "run", "status", "stop_time_s", "runout_m", "steps", "wall_time_s",
               "stop_time_diff_s", "runout_diff_m", "surface_mean_max_m", "surface_max_max_m"]


def write_report(out: Path, report: Report) -> list[Path]:
    """converge.csv (one row per level; the differences are to the level before, the
    surface columns the worst over common output times), converge.json and converge.png."""
    from granflow.io.plots import plot_level_differences

    folder = RunDir(out)
    rows = []
    for lv, varied in zip(report.levels, report.varied, strict=True):
        d = report.differences[lv.level - 1] if lv.level > 0 else None
        values = [lv.level, lv.run, lv.status, lv.stop_time_s, lv.runout_m, lv.steps,
                  lv.wall_time_s, d and d["stop_time_s"], d and d["runout_m"],
                  _worst(d, "mean"), _worst(d, "max"), *varied.values()]
        rows.append(["" if v is None else v for v in values])
    keys = list(report.varied[0])
    written = [folder.write_csv("converge.csv", [*CSV_COLUMNS, *keys], rows)]
    written.append(folder.write_json("converge.json", {
        "source": report.source, "mode": report.mode,
        "overrides": list(report.overrides),
        "levels": [{"level": lv.level, "run": lv.run, "status": lv.status,
                    "message": lv.message, "overrides": varied, "stop_time_s": lv.stop_time_s,
                    "runout_m": lv.runout_m, "steps": lv.steps, "wall_time_s": lv.wall_time_s,
                    "output_times": sorted(lv.surfaces)}
                   for lv, varied in zip(report.levels, report.varied, strict=True)],
        "differences": [d | {"surfaces": {f"{t:.3f}": v for t, v in d["surfaces"].items()}}
                        for d in report.differences],
        "orders": report.orders, "verdict": report.verdict,
        "against_reference": report.against_reference, "loosest_level": report.loosest}))
    stop = [lv.stop_time_s for lv in report.levels]
    series = {
        "stop time (relative)": [abs(d["stop_time_s"]) / abs(s) if d["stop_time_s"] is not None
                                 and s else None for d, s in zip(report.differences, stop[1:],
                                                                 strict=True)],
        "runout (m)": [None if d["runout_m"] is None else abs(d["runout_m"])
                       for d in report.differences],
        "surface mean, worst time (m)": [_worst(d, "mean") for d in report.differences],
        "surface max, worst time (m)": [_worst(d, "max") for d in report.differences]}
    tol = report.verdict["tolerances"]
    limits = dict(zip(series, (tol["stop_time_rel"], tol["runout"], tol["surface_mean"],
                               tol["surface_max"]), strict=True))
    written.append(out / "converge.png")
    plot_level_differences(written[-1], series, limits,
                           f"{report.label}: convergence in {report.mode}")
    return written


def _fmt(value: Any, spec: str) -> str:
    return "-" if value is None else format(value, spec) if isinstance(value, int | float) \
        else str(value)


def format_table(report: Report) -> str:
    """The study as a short text table: levels, changes, orders and the verdict."""
    lines = [f"{'level':>5} {'status':<10} {'steps':>6} {'wall_s':>7} {'stop_s':>8} "
             f"{'runout_m':>9} {'d_stop_s':>9} {'d_runout_m':>10} {'surf_mean':>9} "
             f"{'surf_max':>9}"]
    for lv in report.levels:
        d = report.differences[lv.level - 1] if lv.level > 0 else None
        lines.append(f"{lv.level:>5} {_fmt(lv.status, ''):<10} {_fmt(lv.steps, 'd'):>6} "
                     f"{_fmt(lv.wall_time_s, '.1f'):>7} {_fmt(lv.stop_time_s, '.4f'):>8} "
                     f"{_fmt(lv.runout_m, '.5f'):>9} "
                     f"{_fmt(d and d['stop_time_s'], '.2e'):>9} "
                     f"{_fmt(d and d['runout_m'], '.2e'):>10} "
                     f"{_fmt(_worst(d, 'mean'), '.2e'):>9} {_fmt(_worst(d, 'max'), '.2e'):>9}")
    fitted = [o for o in report.orders if not o["quantity"].startswith("surface_")
              or o["quantity"].startswith("surface_mean")]
    for o in fitted:
        levels = "-".join(map(str, o["levels"]))
        lines.append(f"order p of {o['quantity']} (levels {levels}): "
                     + (f"{o['p']:.2f}" if math.isfinite(o["p"]) else f"n/a, {o['note']}"))
    v = report.verdict
    failed = [c for c in v["checks"] if c["ok"] is False]
    what = "converged" if v["converged"] else "NOT converged"
    lines.append(f"verdict: {what} (levels {v['levels'][0]} and {v['levels'][1]})" + (
        ": " + "; ".join(_describe(c) for c in failed) if failed else ""))
    lines += [f"note: {c['criterion']}: {c['note']}" for c in v["checks"] if c["ok"] is None]
    for judged, varied in zip(report.against_reference, report.varied, strict=False):
        failed = [c for c in judged["checks"] if c["ok"] is False]
        setting = ", ".join(f"{k} = {val:g}" for k, val in varied.items())
        lines.append(f"level {judged['levels'][0]} ({setting}) against the reference: "
                     + ("within the tolerances" if judged["converged"] else
                        "not within: " + "; ".join(_describe(c) for c in failed)))
    if report.against_reference:
        k = report.loosest
        lines.append("loosest within the tolerances of the reference: " + (
            "none" if k is None else f"level {k} (" + ", ".join(
                f"{key} = {val:g}" for key, val in report.varied[k].items()) + ")"))
    return "\n".join(lines)


def _describe(check: dict[str, Any]) -> str:
    if check["value"] is None:
        return f"{check['criterion']}: {check['note']}"
    return f"{check['criterion']} = {check['value']:.3g} > {check['tolerance']:g}"
